#pragma once
// Cascaded position / velocity / attitude controller (thesis 2.3.2 hierarchical control:
// outer loop position and velocity, inner loop attitude). The inner loop follows the vehicle's
// wiring (thesis 2.5): torques through the mixer in direct mode, or commands to the gyro through
// its identified closed loops (Eq. 2.17-2.22) with the gyro in the loop. Plain class, fed plain
// data.
#include <optional>

#include <Eigen/Core>

#include "uav/hal/navigation_estimate.hpp"
#include "uav/control/mixer.hpp"
#include "uav/control/position_loop_params.hpp"
#include "uav/hal/vehicle_params.hpp"

namespace uav::control {

using hal::VehicleEstimate;

struct ControllerParams : PositionLoopParams {
  hal::VehicleParams vehicle;  // the model the controller inverts
  double tilt_max;
  // [s] the horizontal velocity error is taken against v + vel_lead * a (a measured): the attitude
  // loop behind the velocity loop lags, and without the lead a reversal overshoots its setpoint.
  double vel_lead;
  double att_gain, rate_gain, yaw_gain, yaw_rate_gain;
  Eigen::Vector3d trim;  // aileron, elevator, rudder at zero controller output (Table 2.4)
  double gyro_att_gain, gyro_yaw_gain;
  double att_int, att_int_limit;  // attitude integrator [servo units / (rad s)], its limit [servo units]
  static ControllerParams FromParameters(const ParameterSet& p);
};

struct Setpoint {
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // [m] position to hold
  double yaw = 0.0;                               // [rad]
  // When set, the vertical position loop is replaced by this descent rate [m/s, down positive].
  std::optional<double> descent_rate;
  // Velocity of a moving reference [m/s], fed forward so a path is flown without lag.
  Eigen::Vector3d v_ff_N = Eigen::Vector3d::Zero();
  // Rate of a turning yaw reference [rad/s], fed forward so it is followed without the yaw
  // loop's ramp lag (yaw_rate_gain / yaw_gain seconds behind otherwise).
  double yaw_rate_ff = 0.0;
  // Horizontal speed limit below the vehicle's own (mission DO_CHANGE_SPEED) [m/s].
  std::optional<double> speed_max_xy;
  // Limit on the speed in any direction, climbing and descending included [m/s]: obstacle
  // avoidance's stopping distance holds along a climbing detour as along a level one.
  std::optional<double> speed_max;
};

class PositionAttitudeController {
 public:
  explicit PositionAttitudeController(const ControllerParams& params);
  // One control step of length dt [s]. Returns the servo channels for the mixer.
  ServoCommand Update(const VehicleEstimate& est, const Setpoint& sp, double dt);
  // Clears the integrators (on the ground, before a takeoff).
  void Reset();

  const ControllerParams& params() const { return p_; }
  // New gains and limits (a parameter changed over the link); the integrators carry on.
  void SetParams(const ControllerParams& params) { p_ = params; }

 private:
  ControllerParams p_;
  Eigen::Vector2d int_xy_ = Eigen::Vector2d::Zero();
  double int_z_ = 0.0;
  Eigen::Vector3d int_att_ = Eigen::Vector3d::Zero();  // [servo units] aileron, elevator, rudder
};

}  // namespace uav::control
