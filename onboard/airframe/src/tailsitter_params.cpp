#include "uav/airframe/tailsitter_params.hpp"

#include <algorithm>

#include <cmath>
#include <stdexcept>
#include <string>

namespace uav::airframe {

namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

void RequireRange(const char* name, double v, double lo, double hi) {
  Require(std::isfinite(v) && v >= lo && v <= hi, std::string(name) + " = " + std::to_string(v) + " is outside [" +
                                                     std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

}  // namespace

void TailSitterParams::Validate() const {
  RequireRange("mass", mass_kg, 0.1, 50);
  RequireRange("gravity", gravity, 9.7, 9.9);
  RequireRange("air_density", air_density, 0.5, 1.5);
  for (int i = 0; i < 3; ++i) RequireRange(i == 0 ? "inertia_xx" : i == 1 ? "inertia_yy" : "inertia_zz", inertia[i], 1e-4, 10);
  // A rigid body's principal moments obey the triangle inequality.
  Require(inertia.x() + inertia.y() >= inertia.z() && inertia.y() + inertia.z() >= inertia.x() &&
              inertia.z() + inertia.x() >= inertia.y(),
          "inertia_xx, inertia_yy, inertia_zz break the triangle inequality: no rigid body has them");
  wing.Validate();
  wing_coefficients.Validate();
  RequireRange("ts_wing_x", wing_x_m, -0.5, 0.5);
  RequireRange("ts_tail_area", tail_area_m2, 0.001, 1);
  RequireRange("ts_tail_span", tail_span_m, 0.05, 2);
  RequireRange("ts_tail_x", tail_x_m, -3, -0.05);
  Require(tail_x_m < wing_x_m - wing.chord_m, "ts_tail_x must lie behind the wing's chord (ts_wing_x - ts_wing_chord)");
  RequireRange("ts_fin_area", fin_area_m2, 0, 1);
  RequireRange("ts_fin_height", fin_height_m, 0.02, 1);
  RequireRange("ts_canard_area", canard_area_m2, 0.0005, 0.1);
  RequireRange("ts_canard_y", canard_y_m, 0.01, 0.5);
  RequireRange("ts_canard_x", canard_x_m, -1, 2);
  Require(canard_x_m < rotor_x_m, "ts_canard_x must lie behind the rotor (ts_rotor_x) to sit in its propwash");
  Require(canard_y_m < 0.5 * SlipstreamDiameter(),
          "ts_canard_y must lie inside the rotor's slipstream (radius ts_rotor_diameter / (2 sqrt 2))");
  RequireRange("ts_flap_effectiveness", flap_effectiveness, 0.1, 1);
  RequireRange("ts_surface_max", surface_max_rad, 0.05, 0.8);
  RequireRange("ts_surface_rate", surface_rate_rad_s, 0.5, 50);
  RequireRange("ts_rotor_x", rotor_x_m, 0.05, 3);
  RequireRange("ts_rotor_diameter", rotor_diameter_m, 0.05, 3);
  Require(SlipstreamDiameter() < wing.span_m, "ts_rotor_diameter: the slipstream must be narrower than the wing span");
  RequireRange("ts_thrust_max", thrust_max_n, 1, 1000);
  Require(thrust_max_n > 1.2 * mass_kg * gravity,
          "ts_thrust_max must exceed 1.2 x the weight: a tail-sitter hovers on its rotor alone");
  RequireRange("ts_thrust_tau", thrust_tau_s, 0.005, 1);
  RequireRange("ts_prop_pitch_speed", prop_pitch_speed_mps, 5, 200);
  RequireRange("ts_rotor_torque_max", rotor_torque_max_nm, 0, 10);
  RequireRange("ts_gimbal_max", gimbal_max_rad, 0.05, 0.8);
  RequireRange("ts_gimbal_rate", gimbal_rate_rad_s, 0.5, 50);
  RequireRange("ts_servo_tau", servo_tau_s, 0.001, 0.5);
  RequireRange("ts_fuselage_axial", fuselage_axial_m2, 0, 1);
  RequireRange("ts_fuselage_side", fuselage_side_m2, 0, 2);
  RequireRange("ts_battery_mass", battery_kg, 0.01, 10);
  Require(battery_kg < mass_kg, "ts_battery_mass must be below the total mass");
  RequireRange("ts_battery_travel", battery_travel_m, 0, 2);
  RequireRange("ts_battery_speed", battery_speed_mps, 0.01, 2);
}

TailSitterParams TailSitterParams::FromParameters(const ParameterSet& s) {
  TailSitterParams p;
  p.mass_kg = s.Get("mass");
  p.gravity = s.Get("gravity");
  p.air_density = s.Get("air_density");
  p.inertia = {s.Get("inertia_xx"), s.Get("inertia_yy"), s.Get("inertia_zz")};
  p.wing = {s.Get("ts_wing_area"), s.Get("ts_wing_span"), s.Get("ts_wing_chord")};
  p.wing_coefficients.section_lift_slope_per_rad = s.Get("ts_wing_lift_slope");
  p.wing_coefficients.zero_lift_alpha_rad = s.Get("ts_wing_zero_lift_alpha");
  p.wing_coefficients.stall_alpha_rad = s.Get("ts_wing_stall_alpha");
  p.wing_coefficients.profile_drag = s.Get("ts_wing_profile_drag");
  p.wing_coefficients.oswald = s.Get("ts_wing_oswald");
  p.wing_coefficients.normal_force_at_90 = s.Get("ts_wing_normal_force_90");
  p.wing_x_m = s.Get("ts_wing_x");
  p.tail_area_m2 = s.Get("ts_tail_area");
  p.tail_span_m = s.Get("ts_tail_span");
  p.tail_x_m = s.Get("ts_tail_x");
  p.fin_area_m2 = s.Get("ts_fin_area");
  p.fin_height_m = s.Get("ts_fin_height");
  p.canard_area_m2 = s.Get("ts_canard_area");
  p.canard_y_m = s.Get("ts_canard_y");
  p.canard_x_m = s.Get("ts_canard_x");
  p.flap_effectiveness = s.Get("ts_flap_effectiveness");
  p.surface_max_rad = s.Get("ts_surface_max");
  p.surface_rate_rad_s = s.Get("ts_surface_rate");
  p.rotor_x_m = s.Get("ts_rotor_x");
  p.rotor_diameter_m = s.Get("ts_rotor_diameter");
  p.thrust_max_n = s.Get("ts_thrust_max");
  p.thrust_tau_s = s.Get("ts_thrust_tau");
  p.prop_pitch_speed_mps = s.Get("ts_prop_pitch_speed");
  p.rotor_torque_max_nm = s.Get("ts_rotor_torque_max");
  p.gimbal_max_rad = s.Get("ts_gimbal_max");
  p.gimbal_rate_rad_s = s.Get("ts_gimbal_rate");
  p.servo_tau_s = s.Get("ts_servo_tau");
  p.fuselage_axial_m2 = s.Get("ts_fuselage_axial");
  p.fuselage_side_m2 = s.Get("ts_fuselage_side");
  p.battery_kg = s.Get("ts_battery_mass");
  p.battery_travel_m = s.Get("ts_battery_travel");
  p.battery_speed_mps = s.Get("ts_battery_speed");
  try {
    p.Validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(s.SourceName() + ": " + e.what());
  }
  return p;
}

OutputChannels ToChannels(const TailSitterInputs& in) {
  OutputChannels c = UnwiredChannels();
  c[0] = 2.0 * in.thrust - 1.0;
  c[1] = in.rotor_torque;
  c[2] = in.gimbal_pitch;
  c[3] = in.gimbal_yaw;
  c[4] = in.elevator;
  c[5] = in.aileron;
  c[6] = in.canard;
  c[7] = 2.0 * in.battery - 1.0;
  return c;
}

TailSitterInputs FromChannels(const OutputChannels& channels) {
  OutputChannels c;
  for (int i = 0; i < kOutputChannels; ++i) c[i] = std::isfinite(channels[i]) ? std::clamp(channels[i], -1.0, 1.0) : -1.0;
  TailSitterInputs in;
  in.thrust = 0.5 * (c[0] + 1.0);
  in.rotor_torque = c[1];
  in.gimbal_pitch = c[2];
  in.gimbal_yaw = c[3];
  in.elevator = c[4];
  in.aileron = c[5];
  in.canard = c[6];
  in.battery = 0.5 * (c[7] + 1.0);
  return in;
}

}  // namespace uav::airframe
