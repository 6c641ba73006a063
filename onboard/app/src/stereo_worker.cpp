#include "uav/app/stereo_worker.hpp"

#include <algorithm>

#include "uav/shared/frames.hpp"

namespace uav::app {

namespace {
vision::StereoRig RigOf(const hal::StereoCamera& camera) {
  return {camera.left().intrinsics, camera.right().intrinsics, camera.T_LR()};
}

// Distance from the origin to the polyline.
double PolylineDistance(const std::vector<Eigen::Vector3d>& p) {
  double best = p.empty() ? -1.0 : p[0].norm();
  for (std::size_t i = 0; i + 1 < p.size(); ++i) {
    const Eigen::Vector3d ab = p[i + 1] - p[i];
    const double t = ab.squaredNorm() > 0 ? std::clamp(-p[i].dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
    best = std::min(best, (p[i] + t * ab).norm());
  }
  return best;
}
}  // namespace

StereoWorkerParams StereoWorkerParams::FromParameters(const ParameterSet& p) {
  StereoWorkerParams s;
  s.power_lines = p.Get("pwl_enable") != 0.0;
  s.ranging.min_range_m = p.Get("pwl_min_range");
  s.ranging.max_range_m = p.Get("pwl_max_range");
  s.ranging.Validate();
  return s;
}

StereoWorker::StereoWorker(hal::StereoCamera& camera, Blackboard& board, const StereoWorkerParams& params)
    : camera_(camera),
      range_(RigOf(camera), vision::StereoRangeParams()),
      board_(board),
      preview_(camera.left().name, camera.left().preview_rate_hz) {
  if (params.power_lines) power_lines_.emplace(RigOf(camera), vision::PowerLineParams(), params.ranging);
}

void StereoWorker::Tick(int64_t utime) {
  const hal::StereoImages pair = camera_.Capture(utime);
  // One rectification of the pair for every algorithm that reads it.
  cv::Mat left_rect, right_rect;
  range_.rectifier().Rectify(pair.left, pair.right, &left_rect, &right_rect);
  const vision::StereoRangeResult r = range_.ProcessRectified(left_rect, right_rect);
  board_.Update([&](BlackboardData& d) { d.obstacle_range_m = r.obstacle ? r.range_m : -1.0; });
  if (preview_.Due(utime)) board_.PutPreview(preview_.Encode(utime, pair.left));
  if (power_lines_) ReportPowerLines(utime, power_lines_->ProcessRectified(left_rect, right_rect), pair.left.size());
  ++frames_;
}

void StereoWorker::ReportPowerLines(int64_t utime, const std::vector<vision::Wire3D>& wires, const cv::Size& image) {
  const BlackboardData d = board_.Snapshot();
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.linear() = RotationNBFromEuler(d.estimate.euler);
  T_NB.translation() = d.estimate.p_N;
  const Eigen::Isometry3d& T_BL = camera_.left().T_BC;
  const double width = image.width, height = image.height;
  PowerLines report;
  report.utime = utime;
  report.camera = camera_.left().name;
  for (const vision::Wire3D& w : wires) {
    PowerLine seen;
    for (const Eigen::Vector2d& px : w.image_px) seen.image_uv.emplace_back((px.x() + 0.5) / width, (px.y() + 0.5) / height);
    std::vector<Eigen::Vector3d> p_B;
    for (const Eigen::Vector3d& p_L : w.p_L) {
      p_B.push_back(T_BL * p_L);
      seen.p_N.push_back(T_NB * p_B.back());
    }
    if (!p_B.empty()) {
      seen.range_m = PolylineDistance(p_B);
      seen.range_sigma_m = w.range_sigma_m;
      if (report.nearest_m < 0 || seen.range_m < report.nearest_m) report.nearest_m = seen.range_m;
    }
    report.wires.push_back(std::move(seen));
  }
  // The nearest wire the vehicle reports is the median of the last three pairs (none counting
  // as farthest): one pair's misrange, a bundle of wires matched one wire off, must not raise
  // the operator's warning; three pairs take 0.2 s at 15 Hz.
  recent_nearest_m_[frames_ % recent_nearest_m_.size()] = report.nearest_m < 0 ? kNoWire : report.nearest_m;
  std::array<double, 3> sorted = recent_nearest_m_;
  std::sort(sorted.begin(), sorted.end());
  report.nearest_m = sorted[1] == kNoWire ? -1.0 : sorted[1];
  board_.Update([&](BlackboardData& b) { b.nearest_wire_m = report.nearest_m; });
  board_.PutPowerLines(std::move(report));
}

}  // namespace uav::app
