#include "uav/vision/kitti_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>

#include "uav/shared/image_files.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::vision {
namespace {

namespace fs = std::filesystem;

// "P0: 12 numbers" lines of calib.txt.
bool ReadProjection(const std::string& text, const std::string& name, double P[12]) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream l(line);
    std::string key;
    if (!(l >> key) || key != name + ":") continue;
    for (int i = 0; i < 12; ++i)
      if (!(l >> P[i]) || !std::isfinite(P[i])) return false;
    return true;
  }
  return false;
}

}  // namespace

KittiSequence ReadKittiSequence(const std::string& dir) {
  auto fail = [&](const std::string& what) { throw std::runtime_error("KITTI sequence '" + dir + "': " + what); };
  KittiSequence s;
  s.dir = dir;
  s.left = uav::ImageFilesIn((fs::path(dir) / "image_0").string());
  s.right = uav::ImageFilesIn((fs::path(dir) / "image_1").string());
  if (s.left.empty()) fail("no images in image_0/ (left camera, .png/.jpg/.pgm)");
  if (s.left.size() != s.right.size())
    fail("image_0/ has " + std::to_string(s.left.size()) + " images but image_1/ has " + std::to_string(s.right.size()));
  for (size_t i = 0; i < s.left.size(); ++i)
    if (fs::path(s.left[i]).filename() != fs::path(s.right[i]).filename())
      fail("left and right image names differ at frame " + std::to_string(i) + ": " +
           fs::path(s.left[i]).filename().string() + " and " + fs::path(s.right[i]).filename().string());
  const std::string calib_path = (fs::path(dir) / "calib.txt").string();
  if (!fs::exists(calib_path)) fail("no calib.txt");
  const std::string calib = ReadTextFile(calib_path, "calibration");
  double P0[12], P1[12];
  if (!ReadProjection(calib, "P0", P0) || !ReadProjection(calib, "P1", P1))
    fail("calib.txt needs lines 'P0:' and 'P1:' with 12 finite numbers each");
  if (!(P0[0] > 0) || std::abs(P1[0] - P0[0]) > 1e-6 * P0[0] || std::abs(P1[2] - P0[2]) > 1e-3 ||
      std::abs(P1[6] - P0[6]) > 1e-3)
    fail("calib.txt: P0 and P1 must share a positive focal length and principal point (a rectified pair)");
  const double baseline = -P1[3] / P1[0];
  if (!(baseline > 0)) fail("calib.txt: P1 gives a baseline of " + std::to_string(baseline) + " m; it must be positive");
  const cv::Mat first = cv::imread(s.left.front(), cv::IMREAD_GRAYSCALE);
  if (first.empty()) fail("cannot read " + s.left.front());
  try {
    s.geometry = RectifiedGeometry::OfRectifiedPair(first.cols, first.rows, P0[0], baseline, P0[2], P0[6]);
  } catch (const std::exception& e) {
    fail(std::string("calib.txt: ") + e.what());
  }
  const std::string times_path = (fs::path(dir) / "times.txt").string();
  if (fs::exists(times_path)) {
    std::istringstream in(ReadTextFile(times_path, "frame times"));
    double t;
    while (in >> t) {
      if (!std::isfinite(t) || (!s.times_s.empty() && t <= s.times_s.back()))
        fail("times.txt: time " + std::to_string(s.times_s.size()) + " is not finite or does not increase");
      s.times_s.push_back(t);
    }
    if (s.times_s.size() != s.left.size())
      fail("times.txt has " + std::to_string(s.times_s.size()) + " times for " + std::to_string(s.left.size()) + " frames");
  } else {
    for (size_t i = 0; i < s.left.size(); ++i) s.times_s.push_back(0.1 * i);
  }
  return s;
}

std::vector<Eigen::Isometry3d> ReadKittiPoses(const std::string& path) {
  std::istringstream in(ReadTextFile(path, "pose file"));
  std::vector<Eigen::Isometry3d> out;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream l(line);
    double v[12];
    for (double& x : v)
      if (!(l >> x) || !std::isfinite(x))
        throw std::runtime_error("pose file '" + path + "' line " + std::to_string(n) + ": needs 12 finite numbers");
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) T.linear()(r, c) = v[4 * r + c];
      T.translation()(r) = v[4 * r + 3];
    }
    out.push_back(T);
  }
  return out;
}

void WriteKittiPoses(const std::string& path, const std::vector<Eigen::Isometry3d>& poses) {
  std::string text;
  char buf[64];
  for (const auto& T : poses) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) {
        std::snprintf(buf, sizeof buf, "%s%.9e", r + c ? " " : "", c < 3 ? T.linear()(r, c) : T.translation()(r));
        text += buf;
      }
    text += '\n';
  }
  WriteFileAtomically(path, text);
}

KittiErrors EvaluateKittiOdometry(const std::vector<Eigen::Isometry3d>& gt, const std::vector<Eigen::Isometry3d>& est,
                                  std::vector<double> lengths_m) {
  if (gt.size() != est.size())
    throw std::invalid_argument("odometry evaluation: " + std::to_string(est.size()) + " estimated poses for " +
                                std::to_string(gt.size()) + " ground-truth poses");
  // Distance travelled to each frame (devkit trajectoryDistances).
  std::vector<double> dist(gt.size(), 0.0);
  for (size_t i = 1; i < gt.size(); ++i) dist[i] = dist[i - 1] + (gt[i].translation() - gt[i - 1].translation()).norm();
  KittiErrors e;
  double t_sum = 0, r_sum = 0;
  constexpr int kStep = 10;  // devkit step_size: every 10th frame starts segments
  for (double len : lengths_m) {
    KittiErrors::PerLength pl{len, 0, 0, 0};
    for (size_t first = 0; first < gt.size(); first += kStep) {
      size_t last = first;
      while (last < gt.size() && dist[last] <= dist[first] + len) ++last;
      if (last >= gt.size()) continue;  // devkit lastFrameFromSegmentLength: no frame that far
      const Eigen::Isometry3d d_gt = gt[first].inverse() * gt[last];
      const Eigen::Isometry3d d_est = est[first].inverse() * est[last];
      const Eigen::Isometry3d err = d_est.inverse() * d_gt;
      const double cos_a = std::clamp(0.5 * (err.linear().trace() - 1.0), -1.0, 1.0);
      pl.translation_pct += 100.0 * err.translation().norm() / len;
      pl.rotation_deg_per_m += std::acos(cos_a) * 180.0 / M_PI / len;
      ++pl.segments;
    }
    if (pl.segments == 0) continue;
    t_sum += pl.translation_pct, r_sum += pl.rotation_deg_per_m;
    e.segments += pl.segments;
    pl.translation_pct /= pl.segments, pl.rotation_deg_per_m /= pl.segments;
    e.per_length.push_back(pl);
  }
  if (e.segments > 0) e.translation_pct = t_sum / e.segments, e.rotation_deg_per_m = r_sum / e.segments;
  return e;
}

}  // namespace uav::vision
