#include "uav/control/target_follower.hpp"

#include <cmath>
#include <cstdio>

#include "uav/shared/frames.hpp"

namespace uav::control {

FollowParams FollowParams::FromParameters(const ParameterSet& p) {
  FollowParams f;
  f.distance_m = p.Get("flw_distance");
  f.height_m = p.Get("flw_height");
  f.lost_timeout_s = p.Get("flw_lost_timeout");
  return f;
}

TargetFollower::TargetFollower(const FollowParams& params, const hal::VehicleEstimate& est) : p_(params) {
  hold_.p_N = est.p_N;
  hold_.yaw = est.euler.psi;
}

TargetFollower::Output TargetFollower::Update(const TrackedTarget& target, const hal::VehicleEstimate& est, double t) {
  Output o;
  if (target.last_seen_utime < 0) {
    o.state = State::kGaveUp;
    o.reason = "tracking stopped by the operator";
    o.stopped_by_operator = true;
    return o;
  }
  const double unseen_s = t - target.last_seen_utime * 1e-6;
  if (!target.locked || !target.on_ground) {
    if (!holding_) {
      hold_ = Setpoint{};
      hold_.p_N = est.p_N;
      hold_.yaw = target.bearing_rad;  // facing where it was last seen, for the tracker's re-acquisition
      holding_ = true;
      last_utime_ = -1;  // a re-lock starts the velocity afresh
    }
    o.setpoint = hold_;
    if (unseen_s > p_.lost_timeout_s) {
      char buf[96];
      std::snprintf(buf, sizeof buf, "target lost for %.0f s", unseen_s);
      o.state = State::kGaveUp;
      o.reason = buf;
    } else {
      o.state = State::kHolding;
      o.reason = target.locked ? "target is above the horizon" : "target lost";
    }
    return o;
  }
  holding_ = false;
  if (target.utime != last_utime_) {
    // The line of sight's turn rate by filtered differences of the observed bearings.
    if (last_utime_ >= 0) {
      const double dt = (target.utime - last_utime_) * 1e-6;
      if (dt > 0)
        bearing_rate_ += (dt / (p_.bearing_rate_tau_s + dt)) * (WrapAngle(target.bearing_rad - last_bearing_) / dt - bearing_rate_);
    } else {
      bearing_rate_ = 0.0;
    }
    last_utime_ = target.utime;
    last_bearing_ = target.bearing_rad;
  }
  // The point the follow distance short of the target along the line of sight. The target's
  // velocity is not fed forward: differenced from a single camera's ground points it is noisy
  // along the range, and fed forward it made the vehicle weave (docs/modules/tracking.md, Follow); the position
  // loop alone trails a walker by about a metre more than the set distance.
  const Eigen::Vector2d toward(std::cos(target.bearing_rad), std::sin(target.bearing_rad));
  const Eigen::Vector2d want_NE = target.p_N.head<2>() - p_.distance_m * toward;
  o.setpoint.p_N = Eigen::Vector3d(want_NE.x(), want_NE.y(), -p_.height_m);
  const double age_s = std::max(0.0, t - target.utime * 1e-6);
  // The nose points along the ray the target was seen on, carried on at the ray's turn rate
  // over the frame's age; the rate is fed forward so the nose keeps up with a target crossing
  // the view (the yaw loop alone lags a turning reference by yaw_rate_gain / yaw_gain seconds).
  o.setpoint.yaw_rate_ff = bearing_rate_;
  o.setpoint.yaw = WrapAngle(target.bearing_rad + bearing_rate_ * age_s);
  o.state = State::kFollowing;
  return o;
}

}  // namespace uav::control
