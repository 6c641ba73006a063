#pragma once
// Cross-style quadrotor rigid-body model, thesis 2.4 (Eq. 2.1-2.11) with the first-order rotor
// thrust lag of Eq. 2.13. Plain class: no threads, no messages, no clock.
#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/hal/vehicle_params.hpp"

namespace uav::sim {

using QuadrotorParams = hal::VehicleParams;

// Continuous state. Frames: N (NED, origin at home), B (body FRD).
struct QuadrotorState {
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();        // position [m]
  Eigen::Vector3d v_B = Eigen::Vector3d::Zero();        // velocity in B [m/s] (u, v, w)
  Eigen::Quaterniond q_NB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();        // body rates [rad/s] (p, q, r)
  std::array<double, 4> rotor = {0, 0, 0, 0};           // lagged rotor inputs, Eq. 2.13 state
};

class QuadrotorModel {
 public:
  explicit QuadrotorModel(const QuadrotorParams& params);

  const QuadrotorParams& params() const { return params_; }

  // Thrust of rotor i [N] for a (lagged) normalised input (Eq. 2.13 static gain).
  double RotorThrust(double input) const;
  // Total force on the body in B [N] (Eq. 2.9) and torque [N m] (Eq. 2.10, 2.11).
  Eigen::Vector3d ForceB(const QuadrotorState& s, const Eigen::Vector3d& wind_N) const;
  Eigen::Vector3d TorqueB(const QuadrotorState& s) const;
  // Specific force an accelerometer at the CG measures, in B [m/s^2] (gravity excluded).
  Eigen::Vector3d SpecificForceB(const QuadrotorState& s, const Eigen::Vector3d& wind_N) const;

  // Advances the state by dt with 4th-order Runge-Kutta, rotor commands held constant.
  // `on_ground` holds the vehicle on a flat ground at z = 0 while thrust cannot lift it.
  void Step(QuadrotorState& s, const std::array<double, 4>& rotor_cmd, const Eigen::Vector3d& wind_N,
            double dt) const;

 private:
  struct Derivative {
    Eigen::Vector3d dp, dv, dw;
    Eigen::Vector4d dq;  // quaternion derivative (w, x, y, z)
    std::array<double, 4> drotor;
  };
  Derivative Derive(const QuadrotorState& s, const std::array<double, 4>& cmd,
                    const Eigen::Vector3d& wind_N) const;
  QuadrotorParams params_;
};

}  // namespace uav::sim
