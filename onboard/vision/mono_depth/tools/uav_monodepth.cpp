// uav-monodepth DIR --out grid.csv [--poses FILE] [--overlay DIR] [--truth-stereo]
// Monocular depth from motion (thesis 3.4) on a capture folder written by the vehicle (images,
// captures.csv with the navigation solution per image, session.json with the camera), or on a
// KITTI odometry sequence (the left images, the camera from calib.txt, the poses of poses.txt or
// --poses, e.g. uav-vo's estimate): the 4x3 depth grid per frame, one CSV row per cell. A frame
// whose navigation columns are not finite has its cells unknown with the reason, never a
// made-up depth. --truth-stereo (KITTI): each known cell scored against the depth the right
// image gives at the same features (OpenCV's SGBM, left-right checked: a method not ours).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numeric>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <opencv2/calib3d.hpp>

#include "uav/shared/capture_folder.hpp"
#include "uav/vision/kitti_odometry.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/mono_depth.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

std::string Quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The frame with its features (green converged, grey not yet) and the grid: each cell's depth
// and state (red obstacle, green free, grey unknown).
cv::Mat Overlay(const cv::Mat& image, const uav::vision::DepthGrid& g, const std::vector<uav::vision::DepthFeature>& features) {
  cv::Mat out = image.clone();
  for (const auto& f : features)
    cv::circle(out, f.px, 2, f.converged ? cv::Scalar(60, 220, 60) : cv::Scalar(160, 160, 160), cv::FILLED);
  const int w = out.cols / g.cols, h = out.rows / g.rows;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const auto& cell = g.at(r, c);
      const cv::Scalar colour = cell.state == uav::vision::CellState::kObstacle ? cv::Scalar(40, 40, 230)
                                : cell.state == uav::vision::CellState::kFree   ? cv::Scalar(60, 200, 60)
                                                                                 : cv::Scalar(150, 150, 150);
      cv::rectangle(out, cv::Rect(c * w, r * h, w, h), colour, 1);
      char text[48];
      if (cell.state == uav::vision::CellState::kUnknown) std::snprintf(text, sizeof text, "?");
      else std::snprintf(text, sizeof text, "%.1f m (%d)", cell.depth_m, cell.features);
      cv::putText(out, text, cv::Point(c * w + 6, r * h + 22), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
      cv::putText(out, text, cv::Point(c * w + 6, r * h + 22), cv::FONT_HERSHEY_SIMPLEX, 0.55, colour, 1, cv::LINE_AA);
    }
  return out;
}

// One frame of the input, whichever its layout.
struct InputFrame {
  std::string file;   // as written in the CSV
  std::string path;
  int64_t utime = 0;
  std::optional<Eigen::Isometry3d> T_NC;
  std::string problem;     // why there is no pose
  std::string right_path;  // KITTI: the right image (stereo truth)
};

// Depth from the right image, as a check independent of ours: OpenCV's semi-global matcher on the
// rectified pair (128 disparities, 5 px blocks), kept only where the right-to-left match agrees
// within 1 px; at a feature, the median of the valid disparities of its 5 x 5 neighbourhood
// (none when fewer than half are valid). Z = f b / d (Eq. 3.11).
class StereoTruth {
 public:
  explicit StereoTruth(const uav::vision::RectifiedGeometry& g) : g_(g) {
    left_ = cv::StereoSGBM::create(0, 128, 5, 8 * 25, 32 * 25, 1, 0, 10, 100, 2, cv::StereoSGBM::MODE_SGBM);
  }
  void SetPair(const cv::Mat& left_grey, const cv::Mat& right_grey) {
    cv::Mat dl, dr, l_flip, r_flip;
    left_->compute(left_grey, right_grey, dl);  // 16 x disparity
    // The right view's disparities: the same matcher on the mirrored pair.
    cv::flip(left_grey, l_flip, 1);
    cv::flip(right_grey, r_flip, 1);
    left_->compute(r_flip, l_flip, dr);
    cv::flip(dr, dr, 1);
    disparity_.create(dl.size(), CV_32F);
    for (int v = 0; v < dl.rows; ++v)
      for (int u = 0; u < dl.cols; ++u) {
        const float d = dl.at<int16_t>(v, u) / 16.f;
        float keep = -1.f;
        if (d > 0) {
          const int ur = static_cast<int>(std::lround(u - d));
          if (ur >= 0 && ur < dr.cols) {
            const float d_r = dr.at<int16_t>(v, ur) / 16.f;
            if (d_r > 0 && std::abs(d_r - d) <= 1.f) keep = d;
          }
        }
        disparity_.at<float>(v, u) = keep;
      }
  }
  // Depth [m] at pixel `px`, or NaN.
  double DepthAt(const cv::Point2f& px) const {
    std::vector<float> d;
    const int u0 = static_cast<int>(std::lround(px.x)), v0 = static_cast<int>(std::lround(px.y));
    for (int v = v0 - 2; v <= v0 + 2; ++v)
      for (int u = u0 - 2; u <= u0 + 2; ++u)
        if (v >= 0 && u >= 0 && v < disparity_.rows && u < disparity_.cols && disparity_.at<float>(v, u) > 0)
          d.push_back(disparity_.at<float>(v, u));
    if (d.size() < 13) return NAN;
    std::nth_element(d.begin(), d.begin() + d.size() / 2, d.end());
    return g_.f_px * g_.baseline_m / d[d.size() / 2];
  }

 private:
  uav::vision::RectifiedGeometry g_;
  cv::Ptr<cv::StereoSGBM> left_;
  cv::Mat disparity_;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-monodepth: depth from motion (thesis 3.4) on a capture folder or a KITTI sequence, as a 4x3 grid per frame"};
  std::string dir, out, poses_path, overlay_dir;
  bool truth_stereo = false;
  cli.add_option("DIR", dir, "a capture folder (images, captures.csv, session.json) or a KITTI odometry sequence (calib.txt, image_0/, image_1/, poses.txt)")
      ->required();
  uav::OutputFile(cli.add_option("--out", out, "CSV: frame,utime,file,row,col,state,depth_m,sigma_m,features,confidence,reason[,truth_m,truth_features]"))->required();
  cli.add_option("--poses", poses_path, "poses: a captures CSV (default DIR/captures.csv) or, for KITTI, a poses file (default DIR/poses.txt)");
  cli.add_option("--overlay", overlay_dir, "write every frame with its features and grid drawn here");
  cli.add_flag("--truth-stereo", truth_stereo, "KITTI: score each known cell against the right image's depth at its features");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    namespace fs = std::filesystem;
    const bool kitti = fs::exists(dir + "/calib.txt");
    if (truth_stereo && !kitti) throw std::invalid_argument("--truth-stereo needs a KITTI sequence (calib.txt and the right images)");
    uav::CameraIntrinsics camera;
    std::vector<InputFrame> frames;
    std::optional<uav::vision::RectifiedGeometry> geometry;
    if (kitti) {
      const uav::vision::KittiSequence seq = uav::vision::ReadKittiSequence(dir);
      if (poses_path.empty()) poses_path = dir + "/poses.txt";
      const std::vector<Eigen::Isometry3d> poses = uav::vision::ReadKittiPoses(poses_path);
      if (poses.size() != seq.left.size())
        throw std::invalid_argument(poses_path + ": " + std::to_string(poses.size()) + " poses for " +
                                    std::to_string(seq.left.size()) + " images");
      geometry = seq.geometry;
      camera.width = seq.geometry.width, camera.height = seq.geometry.height;
      camera.fx = camera.fy = seq.geometry.f_px;
      camera.cx = seq.geometry.cx, camera.cy = seq.geometry.cy;
      // The poses are the left camera in the first one's frame (x right, y down, z forward), the
      // axes of our camera frame: the estimator needs only their relative motion.
      for (std::size_t i = 0; i < seq.left.size(); ++i)
        frames.push_back({fs::path(seq.left[i]).filename().string(), seq.left[i],
                          static_cast<int64_t>(std::llround(seq.times_s[i] * 1e6)) + 1, poses[i], "", seq.right[i]});
    } else {
      if (poses_path.empty()) poses_path = dir + "/captures.csv";
      const uav::CaptureSession session = uav::ReadCaptureSession(dir + "/session.json");
      camera = session.camera;
      for (const uav::CaptureRow& c : uav::ReadCaptureRows(poses_path)) {
        std::optional<Eigen::Isometry3d> T_NC;
        if (c.T_NB_estimate) T_NC = *c.T_NB_estimate * session.T_BC;
        frames.push_back({c.file, dir + "/" + c.file, c.utime, T_NC, c.problem, ""});
      }
    }
    if (frames.empty()) throw std::invalid_argument(poses_path + ": no captures");
    if (!overlay_dir.empty()) std::filesystem::create_directories(overlay_dir);
    uav::vision::MonoDepthEstimator estimator(camera, uav::vision::MonoDepthParams{});
    std::optional<StereoTruth> truth;
    if (truth_stereo) truth.emplace(*geometry);
    std::ostringstream csv;
    csv << "frame,utime,file,row,col,state,depth_m,sigma_m,features,confidence,reason" << (truth ? ",truth_m,truth_features" : "") << "\n";
    std::vector<double> ms;
    int healthy = 0, known_cells = 0, first_all_known = -1;
    std::vector<std::string> skipped;  // named and left out, as a camera's dropped frame
    const int rows = estimator.params().grid_rows, cols = estimator.params().grid_cols;
    // Per cell: relative errors |est - truth| / truth of the scored frames, and frames known.
    std::vector<std::vector<double>> cell_errors(rows * cols);
    std::vector<int> cell_known(rows * cols, 0);
    std::vector<double> all_errors, signed_errors;
    uav::ProgressBar progress(frames.size());
    for (size_t i = 0; i < frames.size(); ++i) {
      const InputFrame& c = frames[i];
      std::string problem = uav::ImageFileProblem(c.path);
      cv::Mat image;
      if (problem.empty() && (image = cv::imread(c.path, cv::IMREAD_COLOR)).empty()) problem = "not an image OpenCV reads";
      if (!problem.empty()) {
        skipped.push_back(c.path + ": " + problem);
        std::fprintf(stderr, "\nuav-monodepth: skipped %s: %s\n", c.path.c_str(), problem.c_str());
        continue;
      }
      const auto t0 = std::chrono::steady_clock::now();
      uav::vision::DepthGrid g = estimator.Update(image, c.utime, c.T_NC);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!c.T_NC) g.reason = "no navigation sample: " + c.problem;
      healthy += g.healthy;
      // The truth at each converged feature, by cell: the cell's depth is the mean of its own.
      std::vector<double> truth_sum(rows * cols, 0.0);
      std::vector<int> truth_n(rows * cols, 0);
      if (truth) {
        cv::Mat left_grey, right_grey = cv::imread(c.right_path, cv::IMREAD_GRAYSCALE);
        cv::cvtColor(image, left_grey, cv::COLOR_BGR2GRAY);
        if (right_grey.size() != left_grey.size()) throw std::invalid_argument(c.right_path + ": not the left image's size");
        truth->SetPair(left_grey, right_grey);
        for (const auto& f : estimator.features()) {
          if (!f.converged) continue;
          const int col = std::clamp(static_cast<int>(f.px.x * cols / image.cols), 0, cols - 1);
          const int row = std::clamp(static_cast<int>(f.px.y * rows / image.rows), 0, rows - 1);
          const double z = truth->DepthAt(f.px);
          if (std::isfinite(z)) truth_sum[row * cols + col] += z, ++truth_n[row * cols + col];
        }
      }
      int known = 0;
      for (int r = 0; r < g.rows; ++r)
        for (int col = 0; col < g.cols; ++col) {
          const auto& cell = g.at(r, col);
          const bool is_known = cell.state != uav::vision::CellState::kUnknown;
          known += is_known;
          char num[128];
          std::snprintf(num, sizeof num, "%.3f,%.3f,%d,%.3f", cell.depth_m, cell.sigma_m, cell.features, cell.confidence);
          csv << i << ',' << c.utime << ',' << c.file << ',' << r << ',' << col << ',' << uav::Name(cell.state) << ','
              << num << ',' << Quoted(g.healthy ? cell.reason : g.reason);
          if (truth) {
            const int k = r * cols + col;
            // Scored when the right image gave depth at three or more of the cell's features.
            const double z = truth_n[k] >= 3 ? truth_sum[k] / truth_n[k] : NAN;
            char t[48];
            std::snprintf(t, sizeof t, ",%.3f,%d", z, truth_n[k]);
            csv << t;
            if (is_known) ++cell_known[k];
            if (is_known && std::isfinite(z)) {
              cell_errors[k].push_back(std::abs(cell.depth_m - z) / z);
              all_errors.push_back(cell_errors[k].back());
              signed_errors.push_back((cell.depth_m - z) / z);
            }
          }
          csv << '\n';
        }
      known_cells += known;
      if (known == g.rows * g.cols && first_all_known < 0) first_all_known = static_cast<int>(i);
      if (!overlay_dir.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "/depth_%06zu.jpg", i);
        cv::imwrite(overlay_dir + name, Overlay(image, g, estimator.features()));
      }
      progress.Update(i + 1);
    }
    progress.Finish(frames.size());
    if (ms.empty()) throw std::invalid_argument(dir + ": no frame could be read (" + std::to_string(skipped.size()) + " skipped)");
    uav::WriteFileAtomically(out, csv.str());
    std::sort(ms.begin(), ms.end());
    const int cells = cols * rows;
    std::string skipped_json;
    for (const std::string& s : skipped) skipped_json += (skipped_json.empty() ? "" : ", ") + uav::JsonString(s);
    std::string truth_json;
    if (truth) {
      auto quantile = [](std::vector<double> v, double q) -> double {
        if (v.empty()) return NAN;
        std::sort(v.begin(), v.end());
        return v[std::min(v.size() - 1, static_cast<size_t>(q * v.size()))];
      };
      std::string per_cell, known_per_cell;
      for (int r = 0; r < rows; ++r) {
        per_cell += r ? ", [" : "[";
        known_per_cell += r ? ", [" : "[";
        for (int col = 0; col < cols; ++col) {
          const auto& e = cell_errors[r * cols + col];
          double mean = NAN;
          if (!e.empty()) {
            mean = 0;
            for (double x : e) mean += x / e.size();
          }
          char t[64];
          if (std::isfinite(mean)) std::snprintf(t, sizeof t, "%s%.4f", col ? ", " : "", mean);
          else std::snprintf(t, sizeof t, "%snull", col ? ", " : "");
          per_cell += t;
          std::snprintf(t, sizeof t, "%s%.3f", col ? ", " : "", static_cast<double>(cell_known[r * cols + col]) / ms.size());
          known_per_cell += t;
        }
        per_cell += "]";
        known_per_cell += "]";
      }
      double bias = 0;
      for (double x : signed_errors) bias += x / std::max<size_t>(1, signed_errors.size());
      char t[256];
      std::snprintf(t, sizeof t, ", \"stereo_truth\": {\"cells_scored\": %zu, \"rel_error_median\": %.4f, \"rel_error_p90\": %.4f, "
                    "\"rel_error_mean\": %.4f, \"bias\": %.4f, ",
                    all_errors.size(), quantile(all_errors, 0.5), quantile(all_errors, 0.9),
                    all_errors.empty() ? NAN : std::accumulate(all_errors.begin(), all_errors.end(), 0.0) / all_errors.size(), bias);
      truth_json = std::string(t) + "\"rel_error_mean_per_cell\": [" + per_cell + "], \"known_fraction_per_cell\": [" + known_per_cell + "]}";
    }
    std::printf("{\"frames\": %zu, \"healthy_frames\": %d, \"known_cell_fraction\": %.3f, \"first_frame_all_known\": %d, "
                "\"ms_per_frame_median\": %.2f, \"ms_per_frame_max\": %.2f, \"skipped\": [%s]%s}\n",
                ms.size(), healthy, static_cast<double>(known_cells) / (cells * ms.size()), first_all_known,
                ms[ms.size() / 2], ms.back(), skipped_json.c_str(), truth_json.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-monodepth: %s\n", e.what());
    return 2;
  }
}
