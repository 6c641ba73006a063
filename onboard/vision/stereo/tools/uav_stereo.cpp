// uav-stereo LEFT RIGHT [--calib FILE | --rectified [--focal PX --baseline M]] [--matcher bm|sgbm|census]
//   [--num-disparities N] [--block N] [--downscale N] [--wls] [--dense] [--disparity OUT.png]
//   [--cloud OUT.pcd] [--obstacles OUT.json] [--truth GT.png [--truth-scale S]]
// The stereo obstacle pipeline (thesis 3.5) on a pair of image files. A raw pair is rectified
// with a calibration file (uav-stereo-calibrate writes one); an already rectified pair (e.g.
// Middlebury's) needs no calibration, and its focal length and baseline make it metric. Writes
// the disparity (16-bit PNG, disparity x 16, 0 where invalid, the left image's pixels), the
// point cloud (PCD, left camera frame: x right, y down, z forward, metres) and the obstacles
// (JSON, level camera frame: x forward, y right, z down), and prints a JSON report with each
// stage's time. With --dense the disparity file holds the densified map (holes filled from the
// background). With --truth, it also scores the measured and the densified disparity (bad
// pixels: off by more than 1 px or missing; and of the pixels given a value) beside OpenCV's
// matchers run on the same grey pair with the same search range, each with its time.
// Exit 0 on success, 1 when the input cannot be used (named on stderr; nothing written), 2 on bad options.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/disparity_filter.hpp>

#include "uav/shared/text_file.hpp"
#include "uav/vision/point_cloud.hpp"
#include "uav/vision/stereo_calibration.hpp"
#include "uav/vision/stereo_obstacles.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/image_files.hpp"

namespace {

using uav::vision::DisparityErrors;

cv::Mat ReadImage(const std::string& path, const char* which) {
  if (!std::filesystem::is_regular_file(path)) throw std::invalid_argument(std::string(which) + " image " + path + ": no such file");
  if (const std::string problem = uav::ImageFileProblem(path); !problem.empty())
    throw std::invalid_argument(std::string(which) + " image " + path + ": " + problem);
  cv::Mat image = cv::imread(path, cv::IMREAD_COLOR);
  if (image.empty()) throw std::invalid_argument(std::string(which) + " image " + path + ": cannot read it as an image");
  return image;
}

nlohmann::json ErrorsJson(const DisparityErrors& e) {
  return {{"pixels_with_truth", e.pixels},
          {"bad_fraction", e.bad_fraction},
          {"invalid_fraction", e.invalid_fraction},
          {"bad_valid_fraction", e.bad_valid_fraction},
          {"mean_abs_error_px", e.mean_abs_error_px}};
}

double MillisecondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// OpenCV's matchers on the same grey pair with the same search range, each scored and timed:
// StereoBM and StereoSGBM with their documented defaults, StereoSGBM as OpenCV's stereo_match
// sample sets it (P1 = 8 w^2, P2 = 32 w^2, uniqueness 10, speckle 100 px / 32, left-right
// check 1 px) in its single-pass, three-way and full eight-path (HH) modes, and the sample's
// SGBM followed by ximgproc's WLS filter with a left-right confidence.
nlohmann::json OpenCvMatchers(const cv::Mat& left_grey, const cv::Mat& right_grey, int num_disparities,
                              const cv::Mat& truth) {
  nlohmann::json table;
  const auto score = [&](const std::string& name, const cv::Ptr<cv::StereoMatcher>& matcher, bool wls) {
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat d;
    matcher->compute(left_grey, right_grey, d);
    if (wls) {
      cv::Mat right_d, filtered;
      cv::ximgproc::createRightMatcher(matcher)->compute(right_grey, left_grey, right_d);
      cv::Ptr<cv::ximgproc::DisparityWLSFilter> filter = cv::ximgproc::createDisparityWLSFilter(matcher);
      filter->filter(d, left_grey, filtered, right_d);
      d = filtered;
    }
    const double ms = MillisecondsSince(t0);
    nlohmann::json j = ErrorsJson(uav::vision::CompareDisparity(d, truth));
    j["ms"] = ms;
    table[name] = j;
  };
  score("bm_defaults", cv::StereoBM::create(num_disparities), false);
  cv::Ptr<cv::StereoSGBM> defaults = cv::StereoSGBM::create();
  defaults->setNumDisparities(num_disparities);
  score("sgbm_defaults", defaults, false);
  const int w = 3;
  const auto sample = [&](int mode) {
    return cv::StereoSGBM::create(0, num_disparities, w, 8 * w * w, 32 * w * w, 1, 63, 10, 100, 32, mode);
  };
  score("sgbm_sample", sample(cv::StereoSGBM::MODE_SGBM), false);
  score("sgbm_sample_3way", sample(cv::StereoSGBM::MODE_SGBM_3WAY), false);
  // The full eight-path mode keeps the whole cost volume (2 bytes a disparity a pixel).
  const double volume_mb = 2.0 * left_grey.total() * num_disparities / 1e6;
  if (volume_mb <= 512) score("sgbm_sample_hh", sample(cv::StereoSGBM::MODE_HH), false);
  else table["sgbm_sample_hh"] = {{"skipped", "its cost volume would take " + std::to_string(int(volume_mb)) + " MB"}};
  score("sgbm_sample_wls", sample(cv::StereoSGBM::MODE_SGBM), true);
  return table;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-stereo: disparity, point cloud and obstacle cylinders from a stereo pair (thesis 3.5)"};
  std::string left_path, right_path, calib_path, matcher = "sgbm", disparity_out, cloud_out, obstacles_out, truth_path;
  bool rectified = false, wls = false;
  double focal_px = 0, baseline_m = 0, truth_scale = 1.0;
  uav::vision::ObstacleParams params;
  params.disparity.downscale = 1;
  params.disparity.num_disparities = 128;
  params.disparity.block_size = 5;
  params.disparity.texture_threshold = 0.0;  // any pair; the vehicle masks featureless areas (2)
  cli.add_option("left", left_path, "left image")->required();
  cli.add_option("right", right_path, "right image")->required();
  auto* calib = cli.add_option("--calib", calib_path, "calibration file (.yml/.json) of a raw pair");
  cli.add_flag("--rectified", rectified, "the pair is already rectified")->excludes(calib);
  cli.add_option("--focal", focal_px, "rectified focal length [px] (with --rectified)");
  cli.add_option("--baseline", baseline_m, "baseline [m] (with --rectified)");
  cli.add_option("--matcher", matcher, "bm, sgbm (OpenCV's) or census (ours)")->check(CLI::IsMember({"bm", "sgbm", "census"}))->capture_default_str();
  cli.add_option("--num-disparities", params.disparity.num_disparities, "search range [px] at matching resolution, multiple of 16")
      ->capture_default_str();
  cli.add_option("--block", params.disparity.block_size, "matching window [px], odd 5..21")->capture_default_str();
  cli.add_option("--downscale", params.disparity.downscale, "match at 1/N resolution (1, 2, 4)")->capture_default_str();
  cli.add_option("--texture", params.disparity.texture_threshold, "minimum mean |dI/dx| [grey levels/px]; 0: off")
      ->capture_default_str();
  cli.add_flag("--wls", wls, "edge-aware WLS filtering of the disparity (ximgproc)");
  bool dense = false;
  cli.add_flag("--dense", dense, "write the densified disparity (holes filled from the background)");
  cli.add_option("--max-depth-sigma", params.max_depth_sigma_m, "range gate: depth error limit [m] (Eq. 3.7)")->capture_default_str();
  cli.add_option("--margin", params.safety_margin_m, "safety margin added to each cylinder [m]")->capture_default_str();
  cli.add_option("--disparity", disparity_out, "16-bit PNG: disparity x 16, 0 invalid");
  cli.add_option("--cloud", cloud_out, "PCD point cloud, left camera frame");
  cli.add_option("--obstacles", obstacles_out, "JSON obstacle cylinders, level camera frame (x fwd, y right, z down)");
  cli.add_option("--truth", truth_path, "ground-truth disparity image (0 unknown) to score against");
  cli.add_option("--truth-scale", truth_scale, "ground-truth pixel value per pixel of disparity")->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (calib_path.empty() && !rectified) {
    std::fprintf(stderr, "uav-stereo: give --calib FILE for a raw pair or --rectified for a rectified one\n");
    return 2;
  }
  params.disparity.matcher = uav::vision::ParseMatcherKind(matcher);
  params.disparity.wls_filter = wls;
  const bool metric_geometry = !calib_path.empty() || (focal_px > 0 && baseline_m > 0);
  if (!metric_geometry && (!cloud_out.empty() || !obstacles_out.empty())) {
    std::fprintf(stderr, "uav-stereo: --cloud and --obstacles need metric geometry: --calib, or --focal and --baseline\n");
    return 2;
  }
  try {
    cv::Mat left = ReadImage(left_path, "left"), right = ReadImage(right_path, "right");
    if (left.size() != right.size())
      throw std::invalid_argument("the left image is " + std::to_string(left.cols) + "x" + std::to_string(left.rows) +
                                  " and the right " + std::to_string(right.cols) + "x" + std::to_string(right.rows));
    uav::vision::RectifiedGeometry geometry;
    const auto t_rect = std::chrono::steady_clock::now();
    double rectify_ms = 0.0;
    if (!calib_path.empty()) {
      const uav::vision::StereoCalibration c = uav::vision::ReadStereoCalibration(calib_path);
      const uav::vision::StereoRectifier rectifier(c.rig);
      cv::Mat l, r;
      rectifier.Rectify(left, right, &l, &r);  // names a calibration that does not fit the images
      left = l;
      right = r;
      geometry = rectifier.geometry();
      rectify_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t_rect).count();
    } else {
      // Without a focal length and baseline only the disparity is computed.
      geometry = uav::vision::RectifiedGeometry::OfRectifiedPair(left.cols, left.rows, metric_geometry ? focal_px : 1.0,
                                                                 metric_geometry ? baseline_m : 1.0);
    }
    // The matcher wants sizes divisible by the downscale: crop the last rows/columns.
    const int s = params.disparity.downscale;
    const cv::Rect crop(0, 0, left.cols / s * s, left.rows / s * s);
    const cv::Size full = left.size();
    geometry.width = crop.width;
    geometry.height = crop.height;
    const uav::vision::StereoObstacleDetector detector(geometry, params);
    uav::vision::StereoObstacles result;
    if (metric_geometry) {
      result = detector.Process(left(crop), right(crop), uav::vision::StereoObstacleDetector::LevelCameraPose());
    } else {
      const auto t0 = std::chrono::steady_clock::now();
      result.disparity = uav::vision::DisparityMatcher(params.disparity).Compute(left(crop), right(crop));
      result.times.disparity_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    }
    const auto t_dense = std::chrono::steady_clock::now();
    const uav::vision::DisparityMap densified = result.disparity.Densified();
    const double dense_ms = MillisecondsSince(t_dense);
    cv::Mat measured16 = cv::Mat::zeros(full, CV_16U), dense16 = cv::Mat::zeros(full, CV_16U);
    result.disparity.FullResolution16U(crop.size()).copyTo(measured16(crop));
    densified.FullResolution16U(crop.size()).copyTo(dense16(crop));
    const cv::Mat& disparity16 = dense ? dense16 : measured16;

    nlohmann::json report;
    report["left"] = left_path;
    report["right"] = right_path;
    report["width"] = full.width;
    report["height"] = full.height;
    report["matcher"] = matcher;
    report["wls"] = wls;
    report["downscale"] = s;
    report["num_disparities"] = params.disparity.num_disparities;
    report["block"] = params.disparity.block_size;
    report["valid_fraction"] = result.disparity.ValidFraction();
    report["dense"] = dense;
    const auto& t = result.times;
    report["stage_ms"] = {{"rectify", rectify_ms},         {"disparity", t.disparity_ms}, {"reproject", t.reproject_ms},
                          {"voxel", t.voxel_ms},           {"ground", t.ground_ms},       {"cluster", t.cluster_ms},
                          {"cylinders", t.cylinders_ms}, {"densify", dense_ms}};
    if (metric_geometry) {
      report["range_gate_m"] = result.gate_depth_m;
      report["points"] = result.points_L.size();
      report["obstacles"] = result.obstacles.size();
    }
    if (!truth_path.empty()) {
      const cv::Mat truth8 = cv::imread(truth_path, cv::IMREAD_ANYDEPTH | cv::IMREAD_GRAYSCALE);
      if (truth8.empty()) throw std::invalid_argument("truth image " + truth_path + ": cannot read it as an image");
      cv::Mat truth;
      truth8.convertTo(truth, CV_32F, 1.0 / truth_scale);
      if (truth.size() != full)
        throw std::invalid_argument("truth image " + truth_path + " is " + std::to_string(truth.cols) + "x" +
                                    std::to_string(truth.rows) + ", the pair " + std::to_string(full.width) + "x" +
                                    std::to_string(full.height));
      report["errors"] = ErrorsJson(uav::vision::CompareDisparity(measured16, truth));
      report["dense_errors"] = ErrorsJson(uav::vision::CompareDisparity(dense16, truth));
      cv::Mat gl, gr;
      cv::cvtColor(left, gl, cv::COLOR_BGR2GRAY);
      cv::cvtColor(right, gr, cv::COLOR_BGR2GRAY);
      report["opencv"] = OpenCvMatchers(gl, gr, params.disparity.num_disparities * s, truth);
    }
    if (!disparity_out.empty()) {
      std::vector<uint8_t> png;
      cv::imencode(".png", disparity16, png);
      uav::WriteFileAtomically(disparity_out, std::string(png.begin(), png.end()));
    }
    if (!cloud_out.empty()) uav::vision::WritePcd(cloud_out, result.points_L);
    if (!obstacles_out.empty()) {
      nlohmann::json j;
      j["frame"] = "level left camera: x forward, y right, z down [m]";
      j["range_gate_m"] = result.gate_depth_m;
      j["obstacles"] = nlohmann::json::array();
      for (const auto& o : result.obstacles)
        j["obstacles"].push_back({{"centre_m", {o.centre_W.x(), o.centre_W.y(), o.centre_W.z()}},
                                  {"radius_m", o.radius_m},
                                  {"safety_radius_m", o.safety_radius_m},
                                  {"top_m", o.top_m},
                                  {"bottom_m", o.bottom_m},
                                  {"range_m", o.range_m},
                                  {"cov_xy_m2", {o.cov_xy(0, 0), o.cov_xy(0, 1), o.cov_xy(1, 1)}},
                                  {"voxels", o.voxels},
                                  // A round crown above a trunk: drawn into the vehicle's map at any width
                                  // (other wide cylinders are left to their points).
                                  {"crown_on_trunk", o.on_trunk}});
      uav::WriteFileAtomically(obstacles_out, j.dump(2) + "\n");
    }
    std::printf("%s\n", report.dump(2).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stereo: %s\n", e.what());
    return 1;
  }
  return 0;
}
