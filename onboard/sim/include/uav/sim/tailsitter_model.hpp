#pragma once
// U-Lion's rigid-body model (thesis 2.6): a tail-sitter that hovers on a gimballed coaxial rotor
// and cruises on its wing. Six degrees of freedom, built up from its parts: the rotor's thrust
// vector and differential torque, the wing in four strips (two in the propwash, ailerons on
// all), the horizontal tail with its elevator, the fin, the two canards in the propwash and the
// fuselage. Each lifting part sees its own airflow (the body's motion through the air, its
// rotation and, inside the slipstream, the rotor's induced flow by momentum theory), so damping,
// weathervaning and the propwash's control power follow from the geometry. Servos are rate
// limited with a lag; the sliding battery moves the centre of gravity (2.6.3). Plain class: no
// threads, no messages, no clock.
//
// Frames: N (NED, origin at home); B the fixed-wing body frame of thesis Fig. 2.50: x_B along
// the fuselage toward the rotor (the nose), y_B the right wing, z_B the belly. In hover the nose
// points up (x_B = -z_N) and the belly faces the way the vehicle will fly on its wing.
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/airframe/tailsitter_params.hpp"

namespace uav::sim {

using airframe::AeroCoefficients;
using airframe::TailSitterInputs;
using airframe::TailSitterParams;
using airframe::WingAerodynamics;

struct TailSitterState {
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // centre of gravity [m]
  Eigen::Vector3d v_B = Eigen::Vector3d::Zero();  // [m/s]
  Eigen::Quaterniond q_NB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();  // [rad/s]
  // Actuators as they are (lagged, rate limited).
  double thrust_n = 0;
  double gimbal_pitch_rad = 0, gimbal_yaw_rad = 0;
  double elevator_rad = 0, aileron_rad = 0, canard_rad = 0;
  double battery_m = 0;  // travel toward the tail [m]
  // Upright on its tail with the belly toward `heading_rad` (clockwise from north).
  static TailSitterState UprightOnGround(double heading_rad);
};

// What the sensors of a tail-sitter read besides the INS's: a pitot tube along x_B and the
// truth the tests score against.
struct TailSitterAirData {
  Eigen::Vector3d air_B = Eigen::Vector3d::Zero();  // the body's velocity through the air [m/s]
  double airspeed_mps = 0;                          // |air_B|
  double alpha_rad = 0;                             // angle of attack atan2(w, u)
  double slipstream_mps = 0;                        // induced flow behind the rotor, 2 v_i
};

struct TailSitterForces {
  Eigen::Vector3d force_B = Eigen::Vector3d::Zero();   // aerodynamic and rotor, no gravity [N]
  Eigen::Vector3d torque_B = Eigen::Vector3d::Zero();  // about the CG [N m]
  double wing_lift_n = 0;                              // the four strips' lift, for the plots
};

class TailSitterModel {
 public:
  explicit TailSitterModel(const TailSitterParams& params);
  const TailSitterParams& params() const { return p_; }
  const WingAerodynamics& wing() const { return wing_; }

  // The thrust the pair gives at a lagged command, falling with the axial inflow (a fixed-pitch
  // propeller's thrust at constant throttle falls to zero near its pitch speed).
  double AvailableThrust(double axial_speed_mps) const;
  TailSitterAirData AirData(const TailSitterState& s, const Eigen::Vector3d& wind_N) const;
  TailSitterForces Forces(const TailSitterState& s, const Eigen::Vector3d& wind_N) const;
  // The centre of gravity relative to the battery-forward reference, along x_B [m].
  double CgShift(const TailSitterState& s) const;

  // Advances by dt with 4th-order Runge-Kutta, inputs held. Returns true while the ground holds
  // the vehicle (flat ground at z = 0, standing on its tail).
  bool Step(TailSitterState& s, const TailSitterInputs& in, const Eigen::Vector3d& wind_N, double dt) const;

 private:
  struct Derivative;
  Derivative Derive(const TailSitterState& s, const TailSitterInputs& in, const Eigen::Vector3d& wind_N) const;
  TailSitterParams p_;
  WingAerodynamics wing_;
  WingAerodynamics tail_;    // symmetric sections: tail, fin, canards
  WingAerodynamics canard_;
};

}  // namespace uav::sim
