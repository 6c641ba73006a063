#pragma once
// Physical parameters of the vehicle (thesis Tables 2.2 and 2.5), read once from the vehicle
// file. The simulator integrates with them; the controller inverts the same model.
#include <Eigen/Core>

#include "uav/shared/parameters.hpp"

namespace uav::hal {

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

  static VehicleParams FromParameters(const ParameterSet& p) {
    return {p.Get("mass"),
            {p.Get("inertia_xx"), p.Get("inertia_yy"), p.Get("inertia_zz")},
            p.Get("arm_length"),
            p.Get("gravity"),
            p.Get("thrust_gain"),
            p.Get("thrust_time_constant"),
            p.Get("induced_torque_coeff"),
            p.Get("rotor_speed_gain"),
            p.Get("rotor_input_zero_thrust"),
            p.Get("air_density"),
            p.Get("drag_area")};
  }
};

}  // namespace uav::hal
