#pragma once
// Flies a compiled mission (an uploaded survey or a stored "track N" path, waypoints/mission.hpp).
// A reference point moves along the legs at the commanded speed with bounded acceleration and is
// fed forward to the position loop, so straight survey lines are flown at constant speed; it
// slows to a stop at corners sharper than 30 degrees and waits there until the vehicle has stopped within
// the acceptance radius; it never runs more than a leash length ahead of the vehicle. Speed and
// camera steps take effect as the reference passes them; a hold keeps the vehicle at the point
// it stopped at for its time. Plain class on the simulated clock.
#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "uav/hal/navigation_estimate.hpp"
#include "uav/control/position_attitude_controller.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::control {

using hal::VehicleEstimate;

struct MissionRunnerParams {
  double reached_radius;   // [m] a stop waypoint counts as reached within this distance ...
  double reached_speed;    // [m/s] ... and below this speed (so the turn starts from rest)
  double speed_max_xy;     // [m/s] vehicle limit
  double speed_max_up;     // [m/s]
  double speed_max_down;   // [m/s]
  double accel;            // [m/s^2] of the reference along the path
  double leash;            // [m] longest lead of the reference over the vehicle
  double return_alt;       // [m] lowest altitude for the flight home
  std::vector<Eigen::Vector2d> rally_N = {};  // [m] a return lands at the nearest (none: home)
};

// A winged vehicle cruising (U-Lion on its wing) cannot stop: a path's waypoints are flown
// through and count as reached within `acceptance_m` horizontally at any speed (or once past the
// line through them square to the leg), and the reference
// moves at its cruise speed; a point to hold (goto's target) is circled at `loiter_radius_m`, and
// reached once the vehicle is on that circle.
struct WingBorne {
  double acceptance_m = 10.0;     // [m]
  double speed_mps = 12.0;        // [m/s]
  double loiter_radius_m = 40.0;  // [m]
  // On a loiter circle about a point: within 1.2 of its radius and the altitude within the
  // acceptance radius.
  bool OnLoiterCircle(const Eigen::Vector3d& centre_N, const Eigen::Vector3d& p_N) const {
    return (centre_N - p_N).head<2>().norm() < 1.2 * loiter_radius_m && std::abs(centre_N.z() - p_N.z()) < acceptance_m;
  }
};

class MissionRunner {
 public:
  MissionRunner(std::vector<waypoints::MissionStep> steps, const MissionRunnerParams& p,
                const VehicleEstimate& est);

  struct Output {
    Setpoint setpoint;
    // Where the current leg ends (the reference moves toward it); nullopt while the reference
    // is not moving (waiting at a stop, landing, done).
    std::optional<Eigen::Vector3d> leg_end_N;
    bool land = false;        // the mission ends in a landing at setpoint.p_N (x, y)
    bool done = false;        // every step flown (holding at the last point)
    int percent = 0;          // of the path length flown
    int item = -1;            // mission item of the current step
    std::size_t step = 0;     // the current step (where a resume starts)
    bool holding = false;     // at a hold step (a loiter, a photo)
    std::optional<double> capture_interval_s;  // camera on: every this many seconds ...
    std::optional<double> capture_distance_m;  // ... or every this many metres
  };
  Output Update(const VehicleEstimate& est, double dt);
  // On the wing (nullopt: hovering, the default), from the next step on.
  void SetWingBorne(std::optional<WingBorne> wing) { wing_ = wing; }
  // The vehicle's limits changed in flight (ctl_speed_max_*): the mission's speed is held to the
  // new ones from now on, and goes back up to what the mission asked when they are raised.
  void SetSpeedLimits(double speed_max_xy, double speed_max_up, double speed_max_down);

  double path_length_m() const { return total_length_; }

 private:
  void Advance();  // runs non-position steps, sets the next target
  bool IsStopAfter(std::size_t step) const;   // is the waypoint at `step` a corner?

  std::vector<waypoints::MissionStep> steps_;
  MissionRunnerParams p_;
  std::size_t index_ = 0;
  Eigen::Vector3d ref_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d target_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d leg_from_ = Eigen::Vector3d::Zero();  // the previous target: the leg to target_
  double yaw_ = 0.0;
  double asked_speed_ = 0.0;  // what the mission asked (DO_CHANGE_SPEED), before the limit
  double speed_ = 0.0;      // commanded cruise speed
  double ref_speed_ = 0.0;  // current speed of the reference
  bool moving_ = false;     // a position step is in progress
  bool waiting_ = false;    // reference at a stop waypoint, waiting for the vehicle
  bool landing_ = false;
  bool done_ = false;
  bool holding_ = false;    // at a hold step, for hold_left_s_ more
  double hold_left_s_ = 0.0;
  double total_length_ = 0.0, flown_length_ = 0.0;
  std::optional<double> capture_interval_s_, capture_distance_m_;
  std::optional<Eigen::Vector2d> return_to_;  // where the return step lands, once chosen
  std::optional<WingBorne> wing_;
};

}  // namespace uav::control
