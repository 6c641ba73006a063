#include "uav/runtime/stereo_worker.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Eigenvalues>
#include <opencv2/core.hpp>

#include "uav/shared/frames.hpp"

namespace uav::runtime {

namespace {
// Grey-level spread of a frame below which it shows nothing (the odometry's blank-frame figure).
constexpr double kMinSpreadDn = 3.0;

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
  s.detection.segments =
      p.Get("pwl_segments") != 0.0 ? vision::PowerLineParams::Segments::kEdLines : vision::PowerLineParams::Segments::kLsd;
  if (p.Get("pwl_verify") == 0.0) s.detection.min_wire_probability = 0.0;
  static constexpr vision::MatcherKind kMatchers[] = {vision::MatcherKind::kBlockMatching, vision::MatcherKind::kSemiGlobal,
                                                      vision::MatcherKind::kCensusSemiGlobal};
  s.obstacles.disparity.matcher = kMatchers[static_cast<int>(p.Get("obs_matcher"))];
  s.obstacles.max_depth_sigma_m = p.Get("obs_max_sigma");
  s.obstacles.safety_margin_m = p.Get("obs_margin");
  s.obstacles.min_cluster_voxels = static_cast<int>(p.Get("obs_min_voxels"));
  s.obstacles.Validate();
  s.cloud_rate_hz = p.Get("obs_cloud_rate");
  s.to_map = p.Get("avd_enable") != 0.0;
  return s;
}

StereoWorker::StereoWorker(hal::StereoCamera& camera, Blackboard& board, const StereoWorkerParams& params)
    : VisionWorker(board),
      camera_(camera),
      rectifier_(RigOf(camera)),
      obstacles_(rectifier_.geometry(), params.obstacles),
      detect_obstacles_(params.detect_obstacles),
      cloud_rate_hz_(params.cloud_rate_hz),
      to_map_(params.to_map),
      preview_(camera.left().name, camera.left().preview_rate_hz) {
  if (!params.detect_obstacles && !params.power_lines)
    throw std::invalid_argument("a stereo worker with neither obstacles nor wires to detect");
  if (params.power_lines) power_lines_.emplace(RigOf(camera), params.detection, params.ranging);
}

void StereoWorker::ApplyParameters(const ParameterSet& params) {
  obstacles_.SetSafetyMargin(StereoWorkerParams::FromParameters(params).obstacles.safety_margin_m);
}

void StereoWorker::Begin(int64_t utime) {
  const BlackboardData d = board_.Snapshot();
  utime_ = utime;
  T_NB_.linear() = RotationNBFromEuler(d.estimate.euler);
  T_NB_.translation() = d.estimate.p_N;
  p_NO_ = d.estimate.p_NO();
}

void StereoWorker::Work(Outbox& out) {
  const int64_t utime = utime_;
  const Eigen::Isometry3d T_NB = T_NB_;
  const hal::StereoImages pair = TimedCapture([&] { return camera_.Capture(utime, hal::Emitter::kOn); });
  // One rectification of the pair for every algorithm that reads it. A pair that cannot be used
  // (a camera gone blank, a wrong size, a navigation solution gone non-finite) leaves the
  // channel unhealthy: nothing stale is reported and the thread keeps running.
  cv::Mat left_rect, right_rect;
  vision::StereoObstacles found;
  try {
    // A camera whose sensor or cable died gives black or flat frames: nothing is seen in them, and
    // an empty result must not pass for a look at empty space (it would keep the obstacle
    // perception fresh while the vehicle flies blind).
    for (const auto& [image, side] : {std::pair{&pair.left, "left"}, std::pair{&pair.right, "right"}}) {
      cv::Scalar mean, spread;
      cv::meanStdDev(*image, mean, spread);
      if (image->empty() || spread[0] < kMinSpreadDn)
        throw std::runtime_error(std::string(side) + " image is blank or flat (mean " + std::to_string(std::lround(mean[0])) +
                                 " DN, spread " + std::to_string(std::lround(spread[0])) + " DN)");
    }
    rectifier_.Rectify(pair.left, pair.right, &left_rect, &right_rect);
    if (detect_obstacles_) found = obstacles_.Process(left_rect, right_rect, T_NB * camera_.left().T_BC);
  } catch (const std::exception& e) {
    ReportUnhealthy(utime, e.what(), out);
    return;
  }
  if (detect_obstacles_) {
    // The corridor ahead from the same points (one disparity per pair).
    const vision::StereoRangeResult corridor = vision::StereoRange::RangeFromPoints(found.points_L, vision::StereoRangeParams());
    const double range_m = corridor.obstacle ? corridor.range_m : -1.0;
    out.Post([range_m](Blackboard& b) {
      b.Update([&](BlackboardData& d) {
        d.obstacle_range_m = range_m;
        d.obstacle_unhealthy_reason.clear();
      });
    });
    ReportObstacles(utime, found, T_NB, out);
  } else {
    found.gate_depth_m = obstacles_.GateDepth();
  }
  if (!pair.left.empty() && preview_.Due(utime)) out.Post([f = preview_.Encode(utime, pair.left)](Blackboard& b) { b.previews.Put(f.camera, f); });
  std::vector<vision::Wire3D> wires;
  if (power_lines_) {
    // Gravity in the left camera frame, from the estimate: poles and trunks are not wires.
    const Eigen::Vector3d down_L = (T_NB * camera_.left().T_BC).rotation().transpose() * Eigen::Vector3d::UnitZ();
    wires = power_lines_->ProcessRectified(left_rect, right_rect, down_L);
    ReportPowerLines(wires, pair.left.size(), utime, T_NB, out);
  }
  if (to_map_) ReportToMap(utime, found, wires, T_NB, p_NO_, out);
  ++frames_;
}

void StereoWorker::ReportUnhealthy(int64_t utime, const std::string& reason, Outbox& out) {
  ++unhealthy_;
  if (!detect_obstacles_) {
    // A pair for wires alone: no wire is ranged now (the obstacles' rig says its own health).
    recent_nearest_m_.fill(kNoWire);
    PowerLines report;
    report.utime = utime;
    report.camera = camera_.left().name;
    out.Post([report](Blackboard& b) {
      b.Update([](BlackboardData& d) { d.nearest_wire_m = -1.0; });
      b.reports.Put(report);
    });
    return;
  }
  out.Post([reason, camera = camera_.left().name](Blackboard& b) {
    b.Update([&](BlackboardData& d) {
      d.obstacle_unhealthy_reason = camera + ": " + reason;
      d.obstacle_range_m = -1.0;
      d.obstacle_count = 0;
      d.nearest_obstacle_m = -1.0;
      d.nearest_wire_m = -1.0;
    });
  });
  Obstacles report;
  report.utime = utime;
  report.camera = camera_.left().name;
  report.healthy = false;
  report.reason = reason;
  report.range_gate_m = obstacles_.GateDepth();
  out.Post([report](Blackboard& b) { b.reports.Put(report); });
}

void StereoWorker::ReportObstacles(int64_t utime, const vision::StereoObstacles& found, const Eigen::Isometry3d& T_NB,
                                   Outbox& out) {
  const CameraIntrinsics& k = camera_.left().intrinsics;
  const Eigen::Isometry3d T_LN = (T_NB * camera_.left().T_BC).inverse();
  Obstacles report;
  report.utime = utime;
  report.camera = camera_.left().name;
  report.range_gate_m = found.gate_depth_m;
  for (const vision::ObstacleCylinder& c : found.obstacles) {
    Obstacle o;
    o.p_NE = c.centre_W.head<2>();
    o.top_down_m = c.top_m;
    o.bottom_down_m = c.bottom_m;
    o.radius_m = c.radius_m;
    o.safety_radius_m = c.safety_radius_m;
    o.range_m = std::max(0.0, (o.p_NE - T_NB.translation().head<2>()).norm() - c.radius_m);
    o.cov_NE = c.cov_xy;
    // The box around the cylinder's projection into the (unrectified) left image.
    double x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (int i = 0; i < 8; ++i) {
      const double a = i % 4 * M_PI / 2;
      const Eigen::Vector3d p_N(o.p_NE.x() + c.radius_m * std::cos(a), o.p_NE.y() + c.radius_m * std::sin(a),
                                i < 4 ? c.top_m : c.bottom_m);
      const Eigen::Vector3d p_C = T_LN * p_N;
      if (p_C.z() < 0.1) continue;
      const Eigen::Vector2d px = Project(k, p_C);
      x0 = std::min(x0, px.x()), x1 = std::max(x1, px.x());
      y0 = std::min(y0, px.y()), y1 = std::max(y1, px.y());
    }
    if (x1 >= x0) {
      auto clamp = [](double v) { return std::clamp(v, 0.0, 1.0); };
      o.image_box = {clamp((x0 + 0.5) / k.width), clamp((y0 + 0.5) / k.height), clamp((x1 + 0.5) / k.width),
                     clamp((y1 + 0.5) / k.height)};
    }
    if (report.nearest_m < 0 || o.range_m < report.nearest_m) report.nearest_m = o.range_m;
    report.obstacles.push_back(o);
  }
  std::sort(report.obstacles.begin(), report.obstacles.end(),
            [](const Obstacle& a, const Obstacle& b) { return a.range_m < b.range_m; });
  out.Post([report](Blackboard& b) {
    b.Update([&](BlackboardData& d) {
      d.obstacle_count = static_cast<int>(report.obstacles.size());
      d.nearest_obstacle_m = report.nearest_m;
    });
    b.reports.Put(report);
  });
  if (cloud_rate_hz_ > 0 && (last_cloud_utime_ < 0 || utime - last_cloud_utime_ >= static_cast<int64_t>(1e6 / cloud_rate_hz_))) {
    last_cloud_utime_ = utime;
    PointCloud cloud;
    cloud.utime = utime;
    cloud.origin_N = T_NB.translation();
    cloud.p_N = found.cloud_W;
    out.Post([cloud = std::move(cloud)](Blackboard& b) { b.reports.Put(cloud); });
  }
}

void StereoWorker::ReportPowerLines(const std::vector<vision::Wire3D>& wires, const cv::Size& image, int64_t utime,
                                    const Eigen::Isometry3d& T_NB, Outbox& out) {
  const Eigen::Isometry3d& T_BL = camera_.left().T_BC;
  const double width = image.width, height = image.height;
  PowerLines report;
  report.utime = utime;
  report.camera = camera_.left().name;
  for (const vision::Wire3D& w : wires) {
    if (w.vertical) continue;  // a pole or a trunk: it goes to the map as an obstacle, not to the operator as a wire
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
  out.Post([report](Blackboard& b) {
    b.Update([&](BlackboardData& d) { d.nearest_wire_m = report.nearest_m; });
    b.reports.Put(report);
  });
}

avoid::PerceptionUpdate StereoMapUpdate(int64_t utime, const vision::StereoObstacles& found,
                                        const std::vector<vision::Wire3D>& wires, const Eigen::Isometry3d& T_NL) {
  // Rays for the map: at most this many points per pair, evenly spread over the image's (the
  // map's cells are 20 cm: more rays only repeat the same cells).
  constexpr std::size_t kMaxRays = 6000;
  // [m] the thickest pole of the benchmark's fields is 0.6 m; the matcher's window reads it wider
  // (0.61-0.67 m at 3-6 m, rendered), and at 0.6 the thickest poles were left out of the map.
  constexpr double kMaxMapCylinderRadius = 0.8;
  avoid::PerceptionUpdate u;
  u.utime = utime;
  avoid::RangeScan scan;
  scan.utime = utime;
  scan.origin_N = T_NL.translation();
  scan.max_range_m = found.gate_depth_m;
  const std::size_t stride = std::max<std::size_t>(1, found.points_L.size() / kMaxRays);
  const Eigen::Isometry3f T = T_NL.cast<float>();
  for (std::size_t i = 0; i < found.points_L.size(); i += stride) scan.p_N.push_back(T * found.points_L[i]);
  u.scan = std::move(scan);
  for (const vision::ObstacleCylinder& c : found.obstacles) {
    // Thin ones (poles, trunks, people: few points reach the map from them), and crowns found
    // on their trunks: the crown's points are its near face, and a detour passing beside it
    // needs its far side too. Any other wide cylinder may be a wall seen at a slant, or several
    // obstacles drawn as one, whose cylinder would fill the gaps between them: its own points
    // describe it.
    if (c.radius_m > kMaxMapCylinderRadius && !c.on_trunk) continue;
    // Grown by one standard deviation of the axis position (its larger axis), at most 0.3 m.
    const double sigma = std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c.cov_xy).eigenvalues().maxCoeff()));
    u.cylinders.push_back({c.centre_W.head<2>(), c.top_m, c.bottom_m, c.radius_m + std::min(sigma, 0.3)});
  }
  // Wires, and the poles and trunks found with them, where their depth is trusted: the
  // polyline's points within the range gate whose depth standard deviation is under a wire's
  // clearance margin. A wire ranged far off (a horizon or a field edge taken for one) would
  // otherwise draw a wall across the map. Each run of trusted points is drawn as thick as the
  // cable plus its largest depth standard deviation (Eq. 3.7): the planner's clearance then
  // holds from where the cable may truly be, not only from where it was measured.
  constexpr double kCableRadius = 0.1;  // [m] the cable, its insulation and the map's rounding
  const Eigen::Isometry3d T_NLd = T_NL;
  for (const vision::Wire3D& w : wires) {
    avoid::MapWire run;
    run.radius_m = kCableRadius;
    for (std::size_t i = 0; i < w.p_L.size(); ++i) {
      const bool trusted = w.p_L[i].norm() <= found.gate_depth_m && i < w.sigma_m.size() && w.sigma_m[i] < 0.5;
      if (trusted) {
        run.p_N.push_back(T_NLd * w.p_L[i]);
        run.radius_m = std::max(run.radius_m, kCableRadius + w.sigma_m[i]);
      }
      if (trusted && i + 1 < w.p_L.size()) continue;
      if (run.p_N.size() >= 2) u.wires.push_back(run);
      run = avoid::MapWire();
      run.radius_m = kCableRadius;
    }
  }
  return u;
}

void StereoWorker::ReportToMap(int64_t utime, const vision::StereoObstacles& found, const std::vector<vision::Wire3D>& wires,
                               const Eigen::Isometry3d& T_NB, const Eigen::Vector3d& p_NO, Outbox& out) const {
  const hal::CameraInfo& left = camera_.left();
  avoid::PerceptionUpdate u = StereoMapUpdate(utime, found, wires, T_NB * left.T_BC);
  // What the pair sees across the ground: its optical axis's azimuth in the body frame, and the
  // half view to the nearer image edge (to the nearer of the four for a pair rolled about its
  // axis, whose image is no longer level).
  const Eigen::Vector3d axis_B = left.T_BC.linear() * Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d across_B = left.T_BC.linear() * Eigen::Vector3d::UnitX();
  const CameraIntrinsics& k = left.intrinsics;
  double half_px = std::min(k.cx, k.width - k.cx);
  if (std::abs(across_B.z()) > std::sin(10.0 * M_PI / 180.0)) half_px = std::min({half_px, k.cy, k.height - k.cy});
  u.view_azimuth_B = std::atan2(axis_B.y(), axis_B.x());
  u.view_half_rad = std::atan(half_px / k.fx);
  if (!detect_obstacles_) {
    // Wires alone: the pair's points are not matched, so it clears no space and does not stand
    // for a look ahead (the obstacles' pair keeps the perception fresh, or the vehicle holds).
    u.scan.reset();
    u.cylinders.clear();
    u.watches_ahead = false;
  }
  out.Post([u = avoid::Translated(std::move(u), -p_NO)](Blackboard& b) { b.perception.Push(u); });
}

}  // namespace uav::runtime
