#pragma once
// U-Lion's flight controller (thesis 2.6.6): three modes and the transitions between them.
//  - Hover: the thrust axis is the attitude (the multicopter law with x_B as the thrust axis),
//    position and velocity loops as the quadrotor's (ctl_*), the belly toward the heading; with
//    ts_weathervane the wing turns edge-on to the wind, its broadside caught 10 N in 5 m/s.
//  - Transition to the wing: 80 % of the available thrust, and the nose down at
//    ts_trans_pitch_rate to the lowest pitch at which that thrust and the wing's lift at the
//    airspeed reached still give the altitude loop's vertical force (the wing model the vehicle
//    file gives): the fastest way onto the wing at constant height. Complete at
//    ts_trans_airspeed.
//  - Cruise: airspeed by thrust (the level-flight trim fed forward), altitude by pitch, course by
//    coordinated turns (bank toward the course, the turn rate fed forward, the bank limited so
//    the load factor keeps the airspeed 15 % above the stall speed); a leg is followed by L1
//    guidance with a look-ahead of 2.5 s of flight.
//  - Transition to hover: the nose comes up at ts_back_pitch_rate while the thrust holds the
//    altitude; the wing at high angle of attack brakes. Hover takes over near vertical.
// A front transition that takes longer than ts_trans_timeout or loses ts_trans_alt_loss aborts
// back to hover. The attitude loop is one law in every mode (a geometric controller on SO(3),
// no Euler singularity at the hover's 90 degrees); its moment is shared among the effectors by
// their effectiveness at the present airspeed and propwash: gimbal, elevator, ailerons, canards
// and the rotors' differential torque. Plain class, fed plain data.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/control/position_loop_params.hpp"
#include "uav/hal/navigation_estimate.hpp"
#include "uav/airframe/tailsitter_params.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::control {

using TailSitterMode = uav::VtolMode;

// How the front transition schedules the pitch: ours (above), or PX4's tail-sitter law for
// comparison (the pitch ramps linearly over ts 5 s; complete past 63 degrees of rotation once
// the airspeed is reached).
enum class TransitionSchedule : int8_t { kLiftLimited = 0, kPx4Ramp = 1 };

struct TailSitterControlParams : PositionLoopParams {
  airframe::TailSitterParams vehicle;  // the model the controller inverts
  double att_gain, rate_gain, att_int, tilt_max;
  double cruise_speed, trans_airspeed, trans_pitch_rate, back_pitch_rate, trans_timeout, trans_alt_loss;
  double trans_min_alt, bank_max;
  double land_approach_alt;  // [m] a landing's back transition from the wing happens at this altitude
  bool weathervane = true;
  TransitionSchedule schedule = TransitionSchedule::kLiftLimited;
  static TailSitterControlParams FromParameters(const ParameterSet& p);
};

struct TailSitterSetpoint {
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // hover: where to hold; on the wing: altitude from z
  double heading = 0.0;  // hover: where the belly faces; on the wing and in transitions: the course [rad]
  // On the wing: when set, the straight leg from here to p_N is followed (L1 guidance) instead
  // of the course `heading`.
  std::optional<Eigen::Vector3d> leg_from_N;
  // Hover: when set, the vertical position loop is replaced by this descent rate [m/s, down
  // positive] (a landing).
  std::optional<double> descent_rate;
  // Hover: the belly turns to `heading` whatever the wind (ts_weathervane yields), to transition
  // that way.
  bool face_heading = false;
};

// L1 guidance (Park, Deyst and How, 2004) for a straight leg: the course toward the point on the
// leg `l1_m` from the vehicle (or the leg's nearest point when farther off than that) [rad].
double L1Course(const Eigen::Vector2d& from_N, const Eigen::Vector2d& to_N, const Eigen::Vector2d& p_N, double l1_m);

// Circling a point on the wing (a fixed wing's hold, PX4's loiter): the course along the circle of
// `radius_m` about `centre_N`, clockwise seen from above, turned toward the circle in proportion
// to how far off it the vehicle is, by up to 45 degrees [rad].
double OrbitCourse(const Eigen::Vector2d& centre_N, const Eigen::Vector2d& p_N, double radius_m);

class TailSitterController {
 public:
  explicit TailSitterController(const TailSitterControlParams& params);

  // Starts a transition from the present estimate. Returns "" or why it is refused (not in the
  // mode it leaves, below ts_trans_min_alt, already transitioning).
  std::string StartTransition(bool to_wing, const hal::VehicleEstimate& est);
  // One control step of dt [s]. `airspeed_mps` is the pitot's reading along x_B.
  airframe::TailSitterInputs Update(const hal::VehicleEstimate& est, double airspeed_mps, const TailSitterSetpoint& sp,
                               double dt);

  TailSitterMode mode() const { return mode_; }
  const TailSitterControlParams& params() const { return p_; }
  // 0..1 through the present transition (1 when not transitioning).
  double transition_progress() const;
  double transition_time() const { return mode_time_; }
  // The last thing the controller decided on its own ("front transition aborted: ...").
  const std::string& event() const { return event_; }
  double pitch_setpoint() const { return pitch_sp_; }  // nose elevation above the horizon [rad]
  // The hover position the controller holds after a back transition or an abort (where it
  // could stop), until the setpoint changes.
  const Eigen::Vector3d& hold_N() const { return hold_N_; }
  bool holding() const { return hold_set_; }
  // Lets the hover go on to the setpoint from the hold (the vehicle has stopped there).
  void ReleaseHold() { hold_set_ = false; }
  // The radius of a level turn at cruise speed and the bank limit [m] (a loiter's circle).
  double TurnRadius() const;
  // The lowest pitch at which `thrust_n` and the wing's lift at this airspeed in level flight
  // give `vertical_n` upward [rad]; 90 degrees when none does.
  double PitchForVertical(double airspeed_mps, double thrust_n, double vertical_n) const;
  // The rotor's thrust at full command at this airspeed [N] (the controller's model).
  double AvailableThrust(double airspeed_mps) const;

 private:
  airframe::TailSitterInputs Attitude(const hal::VehicleEstimate& est, const Eigen::Matrix3d& R_d, const Eigen::Vector3d& w_d_B,
                                 double thrust_n, double airspeed, double dt, double boost_limit_n);
  // Thrust [N] that holds the altitude reference with the wing's expected lift taken off.
  double AltitudeThrust(const hal::VehicleEstimate& est, double airspeed, double pitch, double h_ref, double dt);
  double ThrustCommand(double thrust_n, double airspeed) const;
  // The hover's heading: the requested one, or with ts_weathervane the wing turned edge-on to
  // the wind the velocity integrator feels.
  double HoverHeading(double requested, bool face, double dt);
  // The wing's lift in the propwash in still air at this thrust, in B [N] (hover feed-forward).
  Eigen::Vector3d PropwashLift_B(double thrust_n) const;
  void Enter(TailSitterMode m, const hal::VehicleEstimate& est);

  TailSitterControlParams p_;
  airframe::WingAerodynamics wing_;
  double cruise_alpha_ = 0.0, cruise_thrust_ = 0.0;  // level-flight trim at cruise speed
  double stall_speed_ = 0.0;                         // on the wing alone, level [m/s]
  TailSitterMode mode_ = TailSitterMode::kHover;
  double mode_time_ = 0.0, pitch_sp_ = M_PI / 2, pitch_start_ = M_PI / 2;
  double h_ref_ = 0.0, h_start_ = 0.0, course_ = 0.0;
  std::string event_;
  Eigen::Vector3d hold_N_ = Eigen::Vector3d::Zero();
  bool hold_set_ = false;
  Eigen::Vector3d hold_released_by_ = Eigen::Vector3d::Zero();  // the setpoint when the hold was taken
  // Integrators.
  Eigen::Vector3d int_v_N_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d int_att_ = Eigen::Vector3d::Zero();
  double int_h_ = 0.0, int_speed_ = 0.0, int_pitch_ = 0.0;
  double bank_sp_ = 0.0;  // cruise: the rate-limited bank setpoint [rad]
  double last_thrust_n_ = 0.0;
  double last_vertical_n_ = 0.0;
  double hover_heading_ = 0.0;
  bool hover_heading_set_ = false;  // the altitude loop's upward force demand [N]
};

}  // namespace uav::control
