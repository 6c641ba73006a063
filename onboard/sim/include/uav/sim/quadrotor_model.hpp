#pragma once
// Cross-style quadrotor rigid-body model, thesis 2.4 (Eq. 2.1-2.11) with the first-order rotor
// thrust lag of Eq. 2.13, the airframe imbalance of Table 2.4, and the gyro-in-the-loop attitude
// dynamics of thesis 2.5 (Eq. 2.17-2.22). Plain class: no threads, no messages, no clock.
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
  // Gyro hover mode: the first of the two lags of Eq. 2.17 and 2.18 (roll, pitch) [rad].
  Eigen::Vector2d gyro_lag = Eigen::Vector2d::Zero();
};

class QuadrotorModel {
 public:
  explicit QuadrotorModel(const QuadrotorParams& params);

  const QuadrotorParams& params() const { return params_; }

  // Thrust of rotor i [N] for a (lagged) normalised input (Eq. 2.13 static gain).
  double RotorThrust(double input) const;
  // Total force on the body in B [N] (Eq. 2.9) and torque [N m] (Eq. 2.10, 2.11, plus the
  // imbalance that the trim of Table 2.4 balances).
  Eigen::Vector3d ForceB(const QuadrotorState& s, const Eigen::Vector3d& wind_N) const;
  Eigen::Vector3d TorqueB(const QuadrotorState& s) const;
  // Specific force an accelerometer at the CG measures, in B [m/s^2] (gravity excluded).
  Eigen::Vector3d SpecificForceB(const QuadrotorState& s, const Eigen::Vector3d& wind_N) const;

  // Advances the state by dt with 4th-order Runge-Kutta, output channels held constant.
  // `channels` are what the servo board drives (hal::VehicleBackend::WriteOutputs): rotor inputs
  // in direct mode, the gyro's aileron, elevator, throttle, rudder inputs otherwise.
  // `delayed` are the channels of gyro_hover_delay ago (gyro hover mode uses them for roll and
  // pitch, Eq. 2.17-2.18). Returns true while the ground holds the vehicle (flat ground, z = 0).
  bool Step(QuadrotorState& s, const std::array<double, 4>& channels, const std::array<double, 4>& delayed,
            const Eigen::Vector3d& wind_N, double dt) const;
  bool Step(QuadrotorState& s, const std::array<double, 4>& channels, const Eigen::Vector3d& wind_N,
            double dt) const {
    return Step(s, channels, channels, wind_N, dt);
  }

  // Hover mode has no rate states: the body rates follow from the angle dynamics (Eq. 2.3
  // inverted). Sets s.w_B's roll and pitch rates accordingly.
  void UpdateHoverModeRates(QuadrotorState& s) const;

 private:
  struct Derivative {
    Eigen::Vector3d dp, dv, dw;
    Eigen::Vector4d dq;  // quaternion derivative (w, x, y, z)
    std::array<double, 4> drotor;
    Eigen::Vector2d dgyro_lag = Eigen::Vector2d::Zero();
  };
  Derivative Derive(const QuadrotorState& s, const std::array<double, 4>& cmd,
                    const std::array<double, 4>& delayed, const Eigen::Vector3d& wind_N) const;
  // Roll and pitch rates in hover mode, and the angle rates they come from.
  Eigen::Vector2d HoverModeRates(const QuadrotorState& s) const;
  QuadrotorParams params_;
  Eigen::Vector3d imbalance_torque_B_;  // [N m] balanced by the trim inputs in direct mode
};

}  // namespace uav::sim
