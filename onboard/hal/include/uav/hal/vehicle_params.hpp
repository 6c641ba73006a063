#pragma once
// Physical parameters of the vehicle (thesis Tables 2.2, 2.4, 2.5 and 2.6), read once from the
// vehicle file. The simulator integrates with them; the controller inverts the same model.
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::hal {

// How the servo board's four outputs reach the rotors (thesis 2.5, Fig. 2.21).
using AttitudeMode = uav::AttitudeMode;

// Closed-loop attitude of the airframe with the gyro in the loop (thesis Table 2.6). The inputs
// are the servo channels minus their hover trim.
struct GyroModels {
  double roll_gain, roll_tau;        // hover: phi = K_phi / (1 + tau s)^2 e^(-T s) u_a   (Eq. 2.17)
  double pitch_gain, pitch_tau;      // hover: theta = K_theta / (1 + tau s)^2 e^(-T s) u_e (Eq. 2.18)
  double hover_delay;                // T_phi = T_theta [s]
  double yaw_rate_gain, yaw_rate_tau;  // both modes: r = K_r / (1 + tau_r s) u_r (Eq. 2.19, 2.22)
  double roll_rate_gain, roll_rate_tau;    // cruise: p = K_p / (1 + tau_p s) u_a (Eq. 2.20)
  double pitch_rate_gain, pitch_rate_tau;  // cruise: q = K_q / (1 + tau_q s) u_e (Eq. 2.21)
};

struct VehicleParams {
  double mass;                     // m [kg]
  Eigen::Vector3d inertia;         // diag(J_xx, J_yy, J_zz) [kg m^2]
  double arm_length;               // l [m]
  double gravity;                  // g [m/s^2]
  double thrust_gain;              // K_f [N per unit input] (Eq. 2.13)
  double thrust_time_constant;     // tau_f [s] (Eq. 2.13)
  double induced_torque_coeff;     // d (Eq. 2.10)
  double rotor_speed_gain;         // K_v (Eq. 2.5)
  double rotor_input_zero_thrust;  // input at which thrust vanishes
  double air_density;              // rho [kg/m^3] (Eq. 2.6)
  double drag_area;                // C_d * A [m^2] (Eq. 2.6)
  // Servo inputs (aileron, elevator, rudder) at which the airframe hovers without turning
  // (Table 2.4: rotor imbalance, payload, asymmetry).
  Eigen::Vector3d trim;
  AttitudeMode attitude_mode;
  GyroModels gyro;

  static VehicleParams FromParameters(const ParameterSet& p) {
    VehicleParams v{p.Get("mass"),
                    {p.Get("inertia_xx"), p.Get("inertia_yy"), p.Get("inertia_zz")},
                    p.Get("arm_length"),
                    p.Get("gravity"),
                    p.Get("thrust_gain"),
                    p.Get("thrust_time_constant"),
                    p.Get("induced_torque_coeff"),
                    p.Get("rotor_speed_gain"),
                    p.Get("rotor_input_zero_thrust"),
                    p.Get("air_density"),
                    p.Get("drag_area"),
                    {p.Get("trim_aileron"), p.Get("trim_elevator"), p.Get("trim_rudder")},
                    static_cast<AttitudeMode>(static_cast<int>(p.Get("attitude_mode"))),
                    {p.Get("gyro_hover_roll_gain"), p.Get("gyro_hover_roll_tau"), p.Get("gyro_hover_pitch_gain"),
                     p.Get("gyro_hover_pitch_tau"), p.Get("gyro_hover_delay"), p.Get("gyro_yaw_rate_gain"),
                     p.Get("gyro_yaw_rate_tau"), p.Get("gyro_cruise_roll_rate_gain"),
                     p.Get("gyro_cruise_roll_rate_tau"), p.Get("gyro_cruise_pitch_rate_gain"),
                     p.Get("gyro_cruise_pitch_rate_tau")}};
    const double mode = p.Get("attitude_mode");
    if (mode != 0 && mode != 1 && mode != 2)
      throw std::invalid_argument(p.source() + ": attitude_mode must be 0, 1 or 2, got " + std::to_string(mode));
    // The controller divides by the gyro gains: a gain near zero would be a broken model.
    for (const char* name : {"gyro_hover_roll_gain", "gyro_hover_pitch_gain", "gyro_yaw_rate_gain",
                             "gyro_cruise_roll_rate_gain", "gyro_cruise_pitch_rate_gain"})
      if (std::abs(p.Get(name)) < 0.01)
        throw std::invalid_argument(p.source() + ": " + name + " must be at least 0.01 in magnitude");
    return v;
  }
};

}  // namespace uav::hal
