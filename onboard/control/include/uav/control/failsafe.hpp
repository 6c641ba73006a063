#pragma once
// Failsafes (PX4's commander is the bar): each is a small state machine on the vehicle clock that
// says what the vehicle must at least do; the monitor reports the strictest. Plain class, fed
// plain data; the task manager carries the action out and refuses commands that would do less.
//
//   GCS link   no GCS heartbeat for link_hold_s: hold; for link_return_s: return home. Only once a
//              GCS has been heard (a vehicle flown without a GCS is not "lost"). When the link
//              comes back it is reported; the action already taken is not downgraded.
//   battery    remaining below battery_return: return home; below battery_land: land now.
//              Latched: a battery does not recover in flight.
//   geofence   farther than fence_radius_m from home, higher than fence_alt_m, or outside the
//              uploaded zones (SetGeofence): hold, return or land (fence_action). Clears when
//              back inside.
//   position   no position source (GPS lost and visual odometry unhealthy or absent): hold at
//              once on the IMU alone, land after nav_land_s (latched: a landing that began
//              without position is finished). Clears when a source returns before that.
//   perception obstacle avoidance on and its perception lost in flight (a stereo camera failed):
//              return home at the altitude flown, through space the map has seen free
//              (perception_lost()); latched until landing.
//   manual     the RC fail-safe switch (thesis 2.3.2): the pilot flies, at once, whatever else.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"
#include "uav/waypoints/geofence.hpp"

namespace uav::control {

// Ordered by strictness: a larger value wins.
using FailsafeAction = uav::FailsafeAction;

struct FailsafeParams {
  double link_hold_s;      // [s]
  double link_return_s;    // [s] > link_hold_s
  double battery_return;   // [0..1] remaining
  double battery_land;     // [0..1] remaining, < battery_return
  double fence_radius_m;   // [m] horizontal distance from home
  double fence_alt_m;      // [m] above home
  FailsafeAction fence_action;  // kHold, kReturn or kLand
  double nav_land_s = 5.0;      // [s] without a position source before landing
  static FailsafeParams FromParameters(const ParameterSet& p);
};

struct FailsafeInputs {
  double t = 0;                    // [s] vehicle clock
  bool airborne = false;
  // [s] since the last GCS heartbeat, on the wall clock (the link is real even when the
  // simulation runs faster than real time); < 0: no GCS heard yet.
  double gcs_link_age_s = -1;
  double battery_remaining = 1;    // [0..1]
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();
  bool rc_manual = false;
  // No position source now (GPS lost and no healthy visual odometry), and why.
  bool position_lost = false;
  std::string position_lost_reason;
  // Obstacle avoidance on and its perception lost (none for avd_blind_return), and why.
  bool perception_lost = false;
  std::string perception_lost_reason;
};

// Last line of defence before the controller: "" when the setpoint is finite and within the
// geofence (plus `margin_m`) and the speed limits, else what is wrong ("p_N.z is NaN"). A
// rejected setpoint never reaches the controller; the previous valid one is held instead.
std::string CheckSetpoint(const struct Setpoint& sp, const FailsafeParams& p, double speed_max_xy,
                          double margin_m = 10.0);

class FailsafeMonitor {
 public:
  explicit FailsafeMonitor(const FailsafeParams& p);
  void SetParams(const FailsafeParams& p) { p_ = p; }  // a failsafe already taken stays
  void SetGeofence(waypoints::Geofence fence) { fence_zones_ = std::move(fence); }  // uploaded zones

  // One step; appends operator messages (a failsafe triggering, escalating or clearing) and
  // returns the strictest action required now.
  FailsafeAction Update(const FailsafeInputs& in, std::vector<std::string>* events);
  FailsafeAction required() const { return required_; }
  // Why the current requirement holds ("battery 9 % below 10 %").
  const std::string& reason() const { return reason_; }
  // The perception failsafe is in force: the return flies on the map alone, at its altitude.
  bool perception_lost() const { return perception_ != FailsafeAction::kNone; }

 private:
  FailsafeParams p_;
  waypoints::Geofence fence_zones_;
  FailsafeAction link_ = FailsafeAction::kNone, battery_ = FailsafeAction::kNone;
  FailsafeAction fence_ = FailsafeAction::kNone, manual_ = FailsafeAction::kNone;
  FailsafeAction position_ = FailsafeAction::kNone, perception_ = FailsafeAction::kNone;
  std::string perception_reason_;
  bool perception_lost_said_ = false;
  double position_lost_since_ = -1;
  std::string position_reason_;
  FailsafeAction required_ = FailsafeAction::kNone;
  std::string reason_;
  std::string link_reason_, battery_reason_, fence_reason_;
};

}  // namespace uav::control
