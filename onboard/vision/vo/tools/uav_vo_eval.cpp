// uav-vo-eval GT.txt EST.txt [--lengths 100,200,...] [--plot trajectory.png] [--json report.json]
// KITTI's odometry metric (the devkit's evaluate_odometry): for every 10th frame and every
// segment length, the relative pose over that distance from the estimate against ground truth;
// prints the mean translation error [% of distance] and rotation error [deg/m], overall and per
// length. Both files hold one KITTI pose line per frame (uav-vo writes them). --lengths sets
// shorter segments for short flights (KITTI uses 100..800 m). --plot draws both trajectories from
// above (the camera's x-z plane, KITTI's bird's-eye view) with the start marked.
// Exit 0 on success, 1 when a file cannot be used or no segment fits (named on stderr), 2 on bad
// options.
#include <algorithm>
#include <cstdio>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/text_file.hpp"
#include "uav/vision/kitti_odometry.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

using Poses = std::vector<Eigen::Isometry3d>;

// Bird's-eye view, one scale for both axes. The plane is the one the truth moves in: the first
// camera's axis along which it moves least is dropped. A forward camera (KITTI) keeps x right and
// z forward (up in the picture); a downward camera keeps x and y as its own image shows them.
cv::Mat PlotTopView(const Poses& gt, const Poses& est, const uav::vision::KittiErrors& e) {
  constexpr int kSize = 800, kMargin = 50;
  Eigen::Vector3d gt_lo = Eigen::Vector3d::Constant(1e300), gt_hi = -gt_lo;
  for (const auto& T : gt) gt_lo = gt_lo.cwiseMin(T.translation()), gt_hi = gt_hi.cwiseMax(T.translation());
  int dropped = 0;
  (gt_hi - gt_lo).minCoeff(&dropped);
  const int a = dropped == 0 ? 1 : 0, b = dropped == 2 ? 1 : 2;
  const double up = b == 2 ? 1.0 : -1.0;  // z forward is up in the picture; y (down in the image) is down
  auto plane = [&](const Eigen::Isometry3d& T) { return Eigen::Vector2d(T.translation()[a], up * T.translation()[b]); };
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const Poses* p : {&gt, &est})
    for (const auto& T : *p) {
      const Eigen::Vector2d q = plane(T);
      lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    }
  const double span = std::max({hi.x() - lo.x(), hi.y() - lo.y(), 1e-3});
  const double scale = (kSize - 2 * kMargin) / span;
  const Eigen::Vector2d mid = 0.5 * (lo + hi);
  auto pixel = [&](const Eigen::Isometry3d& T) {
    const Eigen::Vector2d q = plane(T);
    return cv::Point(static_cast<int>(kSize / 2 + scale * (q.x() - mid.x())),
                     static_cast<int>(kSize / 2 - scale * (q.y() - mid.y())));
  };
  cv::Mat img(kSize, kSize, CV_8UC3, cv::Scalar(255, 255, 255));
  // A grid at a round spacing, labelled.
  const double step = std::pow(10.0, std::floor(std::log10(span / 2)));
  for (double x = std::floor(lo.x() / step) * step; x <= hi.x() + step; x += step) {
    const int u = static_cast<int>(kSize / 2 + scale * (x - mid.x()));
    cv::line(img, {u, 0}, {u, kSize}, cv::Scalar(225, 225, 225));
  }
  for (double z = std::floor(lo.y() / step) * step; z <= hi.y() + step; z += step) {
    const int v = static_cast<int>(kSize / 2 - scale * (z - mid.y()));
    cv::line(img, {0, v}, {kSize, v}, cv::Scalar(225, 225, 225));
  }
  auto draw = [&](const Poses& p, const cv::Scalar& colour) {
    for (size_t i = 1; i < p.size(); ++i) cv::line(img, pixel(p[i - 1]), pixel(p[i]), colour, 2, cv::LINE_AA);
  };
  draw(gt, cv::Scalar(0, 0, 0));
  draw(est, cv::Scalar(200, 80, 0));
  cv::circle(img, pixel(gt.front()), 6, cv::Scalar(0, 160, 0), -1, cv::LINE_AA);
  char text[160];
  cv::putText(img, "ground truth", {20, 30}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 2);
  cv::putText(img, "visual odometry", {20, 55}, cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(200, 80, 0), 2);
  std::snprintf(text, sizeof text, "grid %.3g m; translation %.2f %%, rotation %.4f deg/m", step, e.translation_pct,
                e.rotation_deg_per_m);
  cv::putText(img, text, {20, kSize - 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1);
  return img;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-vo-eval: KITTI odometry errors of estimated poses against ground truth"};
  std::string gt_path, est_path, plot_path, json_path;
  std::vector<double> lengths = {100, 200, 300, 400, 500, 600, 700, 800};
  cli.add_option("ground_truth", gt_path, "KITTI pose file of the ground truth")->required();
  cli.add_option("estimate", est_path, "KITTI pose file to score (one line per ground-truth line)")->required();
  cli.add_option("--lengths", lengths, "segment lengths [m]")->delimiter(',')->check(CLI::PositiveNumber)->capture_default_str();
  uav::OutputFile(cli.add_option("--plot", plot_path, "PNG: both trajectories from above"));
  uav::OutputFile(cli.add_option("--json", json_path, "write the report as JSON too"));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    const Poses gt = uav::vision::ReadKittiPoses(gt_path), est = uav::vision::ReadKittiPoses(est_path);
    if (gt.size() != est.size())
      throw std::runtime_error(est_path + " has " + std::to_string(est.size()) + " poses and " + gt_path + " " +
                               std::to_string(gt.size()));
    const uav::vision::KittiErrors e = uav::vision::EvaluateKittiOdometry(gt, est, lengths);
    if (e.segments == 0) {
      double travelled = 0;
      for (size_t i = 1; i < gt.size(); ++i) travelled += (gt[i].translation() - gt[i - 1].translation()).norm();
      char buf[160];
      std::snprintf(buf, sizeof buf, "the ground truth travels %.1f m, shorter than the shortest segment (%.0f m): give --lengths",
                    travelled, *std::min_element(lengths.begin(), lengths.end()));
      throw std::runtime_error(buf);
    }
    nlohmann::json per_length = nlohmann::json::array();
    std::printf("segments %d: translation %.3f %%, rotation %.5f deg/m\n", e.segments, e.translation_pct,
                e.rotation_deg_per_m);
    std::printf("%10s %9s %16s %14s\n", "length_m", "segments", "translation_pct", "rotation_deg_m");
    for (const auto& l : e.per_length) {
      std::printf("%10.0f %9d %16.3f %14.5f\n", l.length_m, l.segments, l.translation_pct, l.rotation_deg_per_m);
      per_length.push_back({{"length_m", l.length_m},
                            {"segments", l.segments},
                            {"translation_pct", l.translation_pct},
                            {"rotation_deg_per_m", l.rotation_deg_per_m}});
    }
    if (!json_path.empty()) {
      const nlohmann::json report = {{"frames", gt.size()},
                                     {"segments", e.segments},
                                     {"translation_pct", e.translation_pct},
                                     {"rotation_deg_per_m", e.rotation_deg_per_m},
                                     {"per_length", per_length}};
      uav::WriteFileAtomically(json_path, report.dump(2) + "\n");
    }
    if (!plot_path.empty()) {
      std::vector<uchar> png;
      cv::imencode(".png", PlotTopView(gt, est, e), png);
      uav::WriteFileAtomically(plot_path, std::string(png.begin(), png.end()));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-vo-eval: %s\n", e.what());
    return 1;
  }
  return 0;
}
