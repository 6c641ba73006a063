#pragma once
// U-Lion's physical parameters (thesis 2.6), read once from the vehicle file's ts_* entries. The
// simulator integrates with them (sim/tailsitter_model.hpp); the controller inverts the same
// model (control/tailsitter_controller.hpp). Where the thesis is silent the vehicle file names
// the assumption.
#include <cmath>

#include <Eigen/Core>

#include "uav/airframe/tailsitter_aero.hpp"
#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::airframe {

using hal::kOutputChannels;
using hal::OutputChannels;
using hal::UnwiredChannels;

// From the vehicle file (resources/vehicles/ulion.params); lengths along x_B from the centre of
// gravity with the battery forward (the cruise position).
struct TailSitterParams {
  double mass_kg = 2.2, gravity = 9.80665, air_density = 1.225;
  Eigen::Vector3d inertia = Eigen::Vector3d(0.12, 0.10, 0.21);  // diag(J_xx, J_yy, J_zz) [kg m^2]
  WingGeometry wing;
  WingCoefficients wing_coefficients;
  double wing_x_m = 0.01;  // the wing's aerodynamic centre (quarter chord) from the CG
  // Horizontal tail (elevator over its whole span) and fin.
  double tail_area_m2 = 0.05, tail_span_m = 0.4, tail_x_m = -0.55;
  double fin_area_m2 = 0.03, fin_height_m = 0.2;
  // Canards, one each side, in the propwash (thesis 2.6.2: yaw in hover).
  double canard_area_m2 = 0.008, canard_y_m = 0.09, canard_x_m = 0.2;
  double flap_effectiveness = 0.5;  // tau: effective angle of attack per radian of deflection
  double surface_max_rad = 0.44, surface_rate_rad_s = 9.5;  // +-25 deg; HS-65MG 0.11 s/60 deg
  // The coaxial rotor on its two-servo gimbal.
  double rotor_x_m = 0.45, rotor_diameter_m = 0.28;
  double thrust_max_n = 40, thrust_tau_s = 0.05, prop_pitch_speed_mps = 30;
  double rotor_torque_max_nm = 0.06;  // differential torque of the pair at full command
  double gimbal_max_rad = 0.5236, gimbal_rate_rad_s = 6.5;  // +-30 deg; 0.16 s/60 deg
  double servo_tau_s = 0.02;
  // Fuselage drag areas C_D A: along x_B and broadside.
  double fuselage_axial_m2 = 0.01, fuselage_side_m2 = 0.1;
  // The sliding battery (thesis 2.6.3): its mass, full travel toward the tail and belt speed.
  double battery_kg = 0.3, battery_travel_m = 0.4, battery_speed_mps = 0.1;

  double SlipstreamDiameter() const { return rotor_diameter_m / std::sqrt(2.0); }  // fully contracted
  // Throws std::invalid_argument naming the entry: out of range, or a geometry that cannot be
  // built (a tail ahead of the CG, canards outside the slipstream, a slipstream wider than the
  // wing, an inertia that breaks the triangle inequality).
  void Validate() const;
  // From the vehicle file's ts_* entries (and mass, inertia, gravity, air density); validated.
  static TailSitterParams FromParameters(const ParameterSet& p);
};


// The servo board's outputs, each in its own range. Positive commands give positive moments
// about B's axes.
struct TailSitterInputs {
  double thrust = 0;        // 0..1 of thrust_max (the coaxial pair's collective)
  double rotor_torque = 0;  // -1..1: differential, about x_B (the heading in hover)
  double gimbal_pitch = 0;  // -1..1 of gimbal_max: moment about y_B
  double gimbal_yaw = 0;    // -1..1: moment about z_B
  double elevator = 0;      // -1..1 of surface_max: moment about y_B
  double aileron = 0;       // -1..1: moment about x_B
  double canard = 0;        // -1..1: differential, moment about x_B
  double battery = 0;       // 0 forward (cruise CG) .. 1 at the tail (hover CG)
};

// U-Lion's wiring of the servo board (each channel -1..1): 0 the rotors' collective (-1 stopped,
// 1 full), 1 their differential, 2-3 the gimbal's pitch and yaw servos, 4 the elevator, 5 the
// ailerons, 6 the canards, 7 the battery's belt (-1 forward, 1 at the tail).
OutputChannels ToChannels(const TailSitterInputs& in);
// The inverse, each value clamped to its range (a non-finite one taken as its channel's -1).
TailSitterInputs FromChannels(const OutputChannels& channels);

}  // namespace uav::airframe
