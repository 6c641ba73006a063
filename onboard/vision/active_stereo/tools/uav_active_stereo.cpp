// uav-active-stereo LEFT RIGHT (--calib FILE | --rectified --focal PX --baseline M)
//   [--mount-pitch DEG] [--min-disparity PX] [--max-disparity PX] [--row-tolerance PX]
//   [--threshold DN] [--min-points N] [--csv OUT.csv] [--overlay DIR]
// Active stereo (thesis ch. 4) on recorded pairs of a rig with a laser dot projector: LEFT and
// RIGHT are two image files, or two folders whose images pair up in name order. Per pair: the
// dots found in each image, the matched and triangulated points, the K-means clusters and the
// height over the ground cluster along gravity, with the rig held level and its cameras pitched
// by --mount-pitch (-90: looking straight down). Writes a CSV row per pair (height, sigma, dot
// counts, clusters, or the reason there is no height), optionally each left image with its dots
// drawn (green on the ground cluster, orange above it) and the height, and prints a JSON report
// (pairs, pairs with a height, median height, reasons, ms per pair). A progress bar goes to
// stderr.
// Exit 0 on success, 1 when the input cannot be used (named on stderr; nothing written), 2 on
// bad options.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/active_stereo.hpp"
#include "uav/vision/stereo_calibration.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace fs = std::filesystem;

namespace {

// One file, or a folder's images in name order.
std::vector<std::string> ImagesOf(const std::string& path, const char* which) {
  if (fs::is_regular_file(path)) return {path};
  if (!fs::is_directory(path)) throw std::invalid_argument(std::string(which) + " " + path + ": no such file or folder");
  std::vector<std::string> out = uav::ImageFilesIn(path);
  if (out.empty()) throw std::invalid_argument(std::string(which) + " folder " + path + " holds no images");
  return out;
}

cv::Mat Read(const std::string& path) {
  if (const std::string problem = uav::ImageFileProblem(path); !problem.empty())
    throw std::invalid_argument(fs::path(path).filename().string() + ": " + problem);
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw std::invalid_argument(fs::path(path).filename().string() + ": cannot read it as an image");
  return image;
}

// The left image with its dots and the height (or the reason there is none).
cv::Mat Overlay(const cv::Mat& left, const uav::vision::ActiveStereoResult& r) {
  cv::Mat out = left.clone();
  for (const auto& p : r.points) {
    const bool ground = p.cluster >= 0 && p.cluster < static_cast<int>(r.clusters.size()) && r.clusters[p.cluster].ground;
    cv::circle(out, p.left_px, 5, ground ? cv::Scalar(60, 220, 60) : cv::Scalar(0, 140, 255), 2, cv::LINE_AA);
  }
  std::ostringstream text;
  text.precision(3);
  if (r.healthy)
    text << "height " << r.height_m << " m +- " << r.height_sigma_m << ", " << r.points.size() << " points, "
         << r.clusters.size() << " clusters";
  else
    text << "no height: " << r.reason;
  const std::string s = text.str().substr(0, 110);
  cv::putText(out, s, cv::Point(8, 22), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
  cv::putText(out, s, cv::Point(8, 22), cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(255, 255, 255), 1, cv::LINE_AA);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-active-stereo: height and 3-D points from a laser-dot stereo rig (thesis ch. 4)"};
  std::string left_path, right_path, calib_path, csv_out, overlay_dir;
  bool rectified = false;
  double focal_px = 0, baseline_m = 0, mount_pitch_deg = -90;
  uav::vision::ActiveStereoParams params;
  cli.add_option("left", left_path, "left image, or a folder of left images")->required();
  cli.add_option("right", right_path, "right image, or a folder of right images (paired in name order)")->required();
  auto* calib = cli.add_option("--calib", calib_path, "calibration file of a raw pair (uav-stereo-calibrate writes one)");
  cli.add_flag("--rectified", rectified, "the pairs are already rectified (give --focal and --baseline)")->excludes(calib);
  cli.add_option("--focal", focal_px, "rectified focal length [px]");
  cli.add_option("--baseline", baseline_m, "baseline [m]");
  cli.add_option("--mount-pitch", mount_pitch_deg, "camera pitch on the level rig [deg]: -90 looks straight down, 0 ahead")
      ->check(CLI::Range(-90.0, 90.0))
      ->capture_default_str();
  cli.add_option("--min-disparity", params.min_disparity_px, "search window start [px] (thesis 20)")->capture_default_str();
  cli.add_option("--max-disparity", params.max_disparity_px, "search window end [px] (thesis 150)")->capture_default_str();
  cli.add_option("--row-tolerance", params.row_tolerance_px, "epipolar row tolerance [px] (thesis 10)")->capture_default_str();
  cli.add_option("--threshold", params.threshold_dn, "a dot is this much brighter than the image median [DN]")
      ->capture_default_str();
  cli.add_option("--min-points", params.min_points, "fewer triangulated dots: no height")->capture_default_str();
  uav::OutputFile(cli.add_option("--csv", csv_out, "CSV with one row per pair"));
  cli.add_option("--overlay", overlay_dir, "folder for the left images with their dots and height drawn");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (calib_path.empty() && !rectified) {
    std::fprintf(stderr, "uav-active-stereo: give --calib FILE for raw pairs or --rectified --focal PX --baseline M\n");
    return 2;
  }
  if (rectified && !(focal_px > 0 && baseline_m > 0 && std::isfinite(focal_px) && std::isfinite(baseline_m))) {
    std::fprintf(stderr, "uav-active-stereo: --rectified needs a positive --focal and --baseline\n");
    return 2;
  }
  try {
    params.Validate();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-active-stereo: %s\n", e.what());
    return 2;
  }
  try {
    const std::vector<std::string> lefts = ImagesOf(left_path, "left"), rights = ImagesOf(right_path, "right");
    if (lefts.size() != rights.size())
      throw std::invalid_argument("the left side has " + std::to_string(lefts.size()) + " images and the right " +
                                  std::to_string(rights.size()) + ": they must pair up");
    uav::vision::StereoRig rig;
    if (!calib_path.empty()) {
      rig = uav::vision::ReadStereoCalibration(calib_path).rig;
    } else {
      const cv::Mat first = Read(lefts.front());
      uav::CameraIntrinsics k;
      k.width = first.cols, k.height = first.rows;
      k.fx = k.fy = focal_px;
      k.cx = (first.cols - 1) / 2.0, k.cy = (first.rows - 1) / 2.0;
      rig.left = rig.right = k;
      rig.T_LR.translation() = Eigen::Vector3d(baseline_m, 0, 0);
    }
    const uav::vision::ActiveStereo stereo(rig, params);  // names a rig that cannot be used
    Eigen::Isometry3d T_BL = Eigen::Isometry3d::Identity();
    T_BL.linear() = Eigen::AngleAxisd(mount_pitch_deg * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix() *
                    uav::RotationBCForward();
    if (!overlay_dir.empty()) fs::create_directories(overlay_dir);

    std::ostringstream csv;
    csv << "left,right,healthy,height_m,height_sigma_m,left_dots,right_dots,ambiguous,points,clusters,ground_points,reason\n";
    std::vector<double> heights, ms;
    std::map<std::string, int> reasons;
    uav::ProgressBar progress(lefts.size());
    for (std::size_t i = 0; i < lefts.size(); ++i) {
      // A pair that cannot be read is a row with the reason; the others are still measured.
      cv::Mat left, right;
      uav::vision::ActiveStereoResult r;
      try {
        left = Read(lefts[i]);
        right = Read(rights[i]);
        const auto t0 = std::chrono::steady_clock::now();
        r = stereo.Process(left, right, T_BL, Eigen::Matrix3d::Identity());
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      } catch (const std::invalid_argument& e) {
        r.healthy = false;
        r.reason = e.what();
      }
      int ground_points = 0;
      for (const auto& c : r.clusters) ground_points += c.ground ? c.points : 0;
      std::string reason = r.reason;
      std::replace(reason.begin(), reason.end(), '"', '\'');
      csv << fs::path(lefts[i]).filename().string() << "," << fs::path(rights[i]).filename().string() << ","
          << (r.healthy ? 1 : 0) << ",";
      if (r.healthy) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.4f,%.4f", r.height_m, r.height_sigma_m);
        csv << buf;
        heights.push_back(r.height_m);
      } else {
        csv << ",";
        ++reasons[r.reason.substr(0, r.reason.find(" ("))];
      }
      csv << "," << r.left_dots << "," << r.right_dots << "," << r.ambiguous << "," << r.points.size() << ","
          << r.clusters.size() << "," << ground_points << ",\"" << reason << "\"\n";
      if (!overlay_dir.empty() && !left.empty())
        cv::imwrite((fs::path(overlay_dir) / (fs::path(lefts[i]).stem().string() + ".png")).string(), Overlay(left, r));
      progress.Update(i + 1, r.healthy ? "" : r.reason);
    }
    progress.Finish(lefts.size());
    if (!csv_out.empty()) uav::WriteFileAtomically(csv_out, csv.str());

    auto median = [](std::vector<double> v) {
      if (v.empty()) return std::nan("");
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    nlohmann::json report;
    report["pairs"] = lefts.size();
    report["pairs_with_height"] = heights.size();
    if (!heights.empty()) report["height_median_m"] = median(heights);
    report["reasons"] = reasons;
    report["ms_per_pair_median"] = median(ms);
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-active-stereo: %s\n", e.what());
    return 1;
  }
}
