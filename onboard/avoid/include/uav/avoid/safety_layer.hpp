#pragma once
// The safety layer between every task and the position controller (as PX4's Collision
// Prevention, in 3-D, with the planner's path): at the control rate it
// - flies the task's own setpoint while its straight way is clear, else the planner's detour
//   (a carrot avd_lookahead ahead on the path, brought nearer so as not to cut the detour's
//   corners by more than 0.2 m, and slowing, after its reaction time, before each turn to the
//   speed of that arc, and before each leg steeper than ctl_speed_max_up or _down let it follow;
//   a turn is counted from the way the vehicle travels now to each leg ahead);
// - limits the speed so that the vehicle can always stop, after its reaction time, within the
//   space seen free along its way: v = -a t + sqrt((a t)^2 + 2 a d), the stopping distance
//   v t + v^2 / (2 a) solved for v (a = avd_brake_accel, t = avd_reaction plus the perception's
//   age or, when longer, its period: a slow sensor's next look is that far away, and the speed
//   stays steady between its frames; d = the seen-free length left);
// - brakes and holds when the perception or the plan is late: older than avd_stale, or than
//   twice its own period when that is longer (a stereo pair at 1-2 Hz on a loaded computer is
//   slow, not lost: the vehicle flies as fast as it can stop on it, and arrives), and says why;
//   and when the planner finds no path;
// - with the perception lost for good (a failed camera: the failsafe's return), flies on the map
//   alone: only plans made through space seen free, the plan's age in place of the perception's;
// - turns the vehicle to face the way it flies, so that the forward cameras see it, and moves
//   where the watching pair does not look only as fast as it stops within its clearance.
// Failsafes and the geofence win: they change the task, and the layer only ever slows or
// detours it. Plain class on the control clock.
#include <cstdint>
#include <optional>
#include <string>

#include "uav/avoid/avoidance.hpp"
#include "uav/control/position_attitude_controller.hpp"
#include "uav/hal/navigation_estimate.hpp"

namespace uav::avoid {

class SafetyLayer {
 public:
  explicit SafetyLayer(const AvoidanceParams& params) : p_(params) {}
  void SetParams(const AvoidanceParams& params) { p_ = params; }
  const AvoidanceParams& params() const { return p_; }

  struct Output {
    control::Setpoint setpoint;
    AvoidState state = AvoidState::kOff;
    std::string reason;          // why blocked, no path, no data
    double speed_limit = 0.0;    // [m/s] what the seen space allows now
    bool changed = false;        // the state differs from the last step's
    // Where the plan stops short of a goal nearer an obstacle than the clearance (`reason`
    // says why); nullopt when the goal itself is planned to.
    std::optional<Eigen::Vector3d> stand_in_N;
  };
  // `goal_N`: where the task is going (nullopt: a task that does not move the vehicle, or one
  // the layer leaves alone: takeoff, landing, hover). `plan`: the planner's newest, if any.
  // `map_only`: the perception is lost; fly plans made on the map alone (AvoidancePlan::map_only).
  Output Apply(const control::Setpoint& task_setpoint, const std::optional<Eigen::Vector3d>& goal_N,
               const hal::VehicleEstimate& est, const AvoidancePlan* plan, int64_t utime, double dt,
               bool map_only = false);

 private:
  control::Setpoint Hold(const control::Setpoint& task_setpoint, const hal::VehicleEstimate& est);
  double FaceTravel(const Eigen::Vector3d& direction_N, const hal::VehicleEstimate& est, double dt);
  // The time between the perception's frames, from the plans' perception times: the longest of
  // the last kPeriods intervals (a rate that varies counts at its slowest); 0 until known.
  void ObservePerception(int64_t perception_utime);
  double PerceptionPeriod() const;
  // How old the perception or the plan may be before the vehicle holds: avd_stale, or twice
  // the perception's period when that is longer.
  double StaleAfter() const;

  AvoidanceParams p_;
  AvoidState state_ = AvoidState::kOff;
  std::optional<Eigen::Vector3d> hold_N_;  // where it stops while holding
  std::optional<double> yaw_ref_;          // the rate-limited heading toward travel
  double yaw_rate_ = 0.0;                  // [rad/s] its rate this step (fed forward)
  bool blocked_ = false;
  static constexpr int kPeriods = 5;
  int64_t last_perception_utime_ = 0;
  double periods_s_[kPeriods] = {0, 0, 0, 0, 0};
  int next_period_ = 0;
};

}  // namespace uav::avoid
