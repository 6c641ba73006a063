#pragma once
// Visual odometry's report (thesis ch. 5) as plain data: what the vehicle publishes
// (visual_odometry_t) and the GCS plots and draws. Decoded once, here.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "uav/shared/signals.hpp"

namespace uav {

// Where the INS takes its position from (values of visual_odometry_t.SOURCE_*).
enum class PositionSource : int8_t { kGps = 0, kVision = 1, kInertial = 2 };
const char* Name(PositionSource s);

struct VisualOdometryReport {
  int64_t utime = 0;
  bool healthy = false;
  std::string reason;
  std::string method;
  int segment = 0;
  int keyframe_points = 0, tracked = 0, inliers = 0;
  double rms_px = 0.0;
  double disparity_offset_px = 0.0, disparity_offset_sigma_px = 0.0;  // [px] learnt from the motion
  std::optional<Eigen::Vector3d> track_N;  // [m] the VO+IMU filter's body position
  PositionSource source = PositionSource::kGps;
  std::optional<Eigen::Vector3d> truth_N;  // [m] simulation only
};

// Its signals (health, counts, the position source and the track against the truth): group "VO".
template <>
struct ReportSignals<VisualOdometryReport> {
  static constexpr std::string_view kGroup = "VO";
  static const std::vector<Signal<VisualOdometryReport>>& Table();
};

}  // namespace uav
