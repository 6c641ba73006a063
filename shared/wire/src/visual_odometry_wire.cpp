#include "uav/wire/messages.hpp"

#include <cmath>
#include <stdexcept>

#include "uavmsg/visual_odometry_t.hpp"

namespace uav {

VisualOdometryReport FromMessage(const uavmsg::visual_odometry_t& m) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("visual_odometry_t: " + what); };
  VisualOdometryReport r;
  r.utime = m.utime;
  r.healthy = m.healthy;
  r.reason = m.reason;
  if (!r.healthy && r.reason.empty()) fail("unhealthy without a reason");
  if (m.method != "pnp" && m.method != "epnp" && m.method != "rigid") fail("unknown method '" + m.method + "'");
  r.method = m.method;
  if (m.segment < 0 || m.keyframe_points < 0 || m.tracked < 0 || m.inliers < 0) fail("negative count");
  r.segment = m.segment;
  r.keyframe_points = m.keyframe_points;
  r.tracked = m.tracked;
  r.inliers = m.inliers;
  if (!std::isfinite(m.rms_px) || m.rms_px < 0) fail("rms_px is not a finite non-negative number");
  r.rms_px = m.rms_px;
  if (!std::isfinite(m.disparity_offset_px) || !std::isfinite(m.disparity_offset_sigma_px) || m.disparity_offset_sigma_px < 0)
    fail("disparity offset or its sigma is not a finite number (sigma non-negative)");
  r.disparity_offset_px = m.disparity_offset_px;
  r.disparity_offset_sigma_px = m.disparity_offset_sigma_px;
  if (m.track_valid) {
    const Eigen::Vector3d p(m.track_n, m.track_e, m.track_d);
    if (!p.allFinite()) fail("track position is not finite");
    r.track_N = p;
  }
  if (m.nav_source < 0 || m.nav_source > 2) fail("unknown nav_source " + std::to_string(m.nav_source));
  r.source = static_cast<PositionSource>(m.nav_source);
  if (m.truth_valid) {
    const Eigen::Vector3d p(m.truth_n, m.truth_e, m.truth_d);
    if (!p.allFinite()) fail("truth position is not finite");
    r.truth_N = p;
  }
  return r;
}

uavmsg::visual_odometry_t ToMessage(const VisualOdometryReport& r) {
  uavmsg::visual_odometry_t m{};
  m.utime = r.utime;
  m.healthy = r.healthy;
  m.reason = r.reason;
  m.method = r.method;
  m.segment = r.segment;
  m.keyframe_points = static_cast<int16_t>(std::min(r.keyframe_points, 32767));
  m.tracked = static_cast<int16_t>(std::min(r.tracked, 32767));
  m.inliers = static_cast<int16_t>(std::min(r.inliers, 32767));
  m.rms_px = static_cast<float>(r.rms_px);
  m.disparity_offset_px = static_cast<float>(r.disparity_offset_px);
  m.disparity_offset_sigma_px = static_cast<float>(r.disparity_offset_sigma_px);
  m.track_valid = r.track_N.has_value();
  if (r.track_N) m.track_n = r.track_N->x(), m.track_e = r.track_N->y(), m.track_d = r.track_N->z();
  m.nav_source = static_cast<int8_t>(r.source);
  m.truth_valid = r.truth_N.has_value();
  if (r.truth_N) m.truth_n = r.truth_N->x(), m.truth_e = r.truth_N->y(), m.truth_d = r.truth_N->z();
  return m;
}

}  // namespace uav
