#pragma once
// Follow: keeps the tracked target (thesis 3.7) in view from a set distance and height, as
// camera-tracking followers do. The vehicle trails the target along the line of sight: the
// reference is the target's ground point pulled back towards the vehicle by the follow
// distance, at the follow height above the home ground. The nose (and the gimbal, which looks
// along it) points along the camera ray to the target, with the ray's turn rate fed forward, so
// the target stays centred left-right whatever the position estimate's error. When the target
// is lost it holds where it is; when lost longer than the timeout, or when tracking stops, it
// gives up. Plain class on the simulated clock: the task manager owns it and the geofence.
#include <string>

#include <Eigen/Core>

#include "uav/control/position_attitude_controller.hpp"
#include "uav/hal/navigation_estimate.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/tracking.hpp"

namespace uav::control {

struct FollowParams {
  double distance_m = 8.0;       // flw_distance: horizontal distance kept from the target
  double height_m = 5.0;         // flw_height: height above the home ground
  double lost_timeout_s = 10.0;  // flw_lost_timeout: hold this long after a loss, then give up
  double bearing_rate_tau_s = 0.2;  // [s] time constant of the line of sight's turn-rate filter
  static FollowParams FromParameters(const ParameterSet& p);
};

class TargetFollower {
 public:
  enum class State { kFollowing, kHolding, kGaveUp };
  TargetFollower(const FollowParams& params, const hal::VehicleEstimate& est);

  struct Output {
    Setpoint setpoint;
    State state = State::kFollowing;
    std::string reason;  // why it holds or gave up
    bool stopped_by_operator = false;  // gave up because the operator stopped the tracker
  };
  // One control step: `target` is the tracker's newest (TrackedTarget times in us, `t` in s on
  // the same clock).
  Output Update(const TrackedTarget& target, const hal::VehicleEstimate& est, double t);

 private:
  FollowParams p_;
  Setpoint hold_;                  // where it holds while the target is lost
  bool holding_ = false;
  int64_t last_utime_ = -1;        // newest observation used by the turn-rate filter
  double last_bearing_ = 0.0;
  double bearing_rate_ = 0.0;  // [rad/s] filtered turn rate of the line of sight
};

}  // namespace uav::control
