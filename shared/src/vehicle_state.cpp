#include "uav/shared/vehicle_state.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>


namespace uav {
namespace {

using F = SignalFormat;
using S = VehicleState;

double B(bool b) { return b ? 1.0 : 0.0; }

}  // namespace

double VehicleState::ground_speed() const { return (RotationNBFromEuler(euler) * v_B).head<2>().norm(); }

double VehicleState::heading() const {
  const double h = std::fmod(euler.psi, 2 * M_PI);
  return h < 0 ? h + 2 * M_PI : h;
}

const std::vector<Signal<VehicleState>>& VehicleStateSignals() {
  // Table 2.3's signals first, under the thesis's names, then the rest of vehicle_state_t.
  static const std::vector<Signal<VehicleState>> kSignals = {
      {{"x", "x", "m", "N", F::kMetres}, [](const S& s) { return s.p_N.x(); }},
      {{"y", "y", "m", "N", F::kMetres}, [](const S& s) { return s.p_N.y(); }},
      {{"z", "z", "m", "N", F::kMetres}, [](const S& s) { return s.p_N.z(); }},
      {{"u", "u", "m/s", "B", F::kSpeed}, [](const S& s) { return s.v_B.x(); }},
      {{"v", "v", "m/s", "B", F::kSpeed}, [](const S& s) { return s.v_B.y(); }},
      {{"w", "w", "m/s", "B", F::kSpeed}, [](const S& s) { return s.v_B.z(); }},
      {{"phi", "phi", "rad", "N to B", F::kAngle}, [](const S& s) { return s.euler.phi; }},
      {{"theta", "theta", "rad", "N to B", F::kAngle}, [](const S& s) { return s.euler.theta; }},
      {{"psi", "psi", "rad", "N to B", F::kAngle}, [](const S& s) { return s.euler.psi; }},
      {{"p", "p", "rad/s", "B", F::kAngularRate}, [](const S& s) { return s.w_B.x(); }},
      {{"q", "q", "rad/s", "B", F::kAngularRate}, [](const S& s) { return s.w_B.y(); }},
      {{"r", "r", "rad/s", "B", F::kAngularRate}, [](const S& s) { return s.w_B.z(); }},
      {{"acx", "acx", "m/s^2", "B", F::kAccel}, [](const S& s) { return s.f_B.x(); }},
      {{"acy", "acy", "m/s^2", "B", F::kAccel}, [](const S& s) { return s.f_B.y(); }},
      {{"acz", "acz", "m/s^2", "B", F::kAccel}, [](const S& s) { return s.f_B.z(); }},
      {{"M1", "rotor_input[0]", "1", "", F::kNormalised}, [](const S& s) { return s.rotor_input[0]; }},
      {{"M2", "rotor_input[1]", "1", "", F::kNormalised}, [](const S& s) { return s.rotor_input[1]; }},
      {{"M3", "rotor_input[2]", "1", "", F::kNormalised}, [](const S& s) { return s.rotor_input[2]; }},
      {{"M4", "rotor_input[3]", "1", "", F::kNormalised}, [](const S& s) { return s.rotor_input[3]; }},
      {{"Ua", "servo_input[0]", "1", "", F::kNormalised}, [](const S& s) { return s.servo_input[0]; }},
      {{"Ue", "servo_input[1]", "1", "", F::kNormalised}, [](const S& s) { return s.servo_input[1]; }},
      {{"Uth", "servo_input[2]", "1", "", F::kNormalised}, [](const S& s) { return s.servo_input[2]; }},
      {{"Ur", "servo_input[3]", "1", "", F::kNormalised}, [](const S& s) { return s.servo_input[3]; }},
      {{"armed", "armed", "1", "", F::kBool}, [](const S& s) { return B(s.armed); }},
      {{"task", "task", "1", "", F::kTask}, [](const S& s) { return double(static_cast<int>(s.task)); }},
      {{"battery_v", "battery_voltage_v", "V", "", F::kVolts}, [](const S& s) { return s.battery_voltage_v; }},
      {{"mission_item", "mission_item", "1", "", F::kInteger}, [](const S& s) { return double(s.mission_item); }},
      {{"capturing", "capturing", "1", "", F::kBool}, [](const S& s) { return B(s.capturing); }},
      {{"obstacle_range", "obstacle_range_m", "m", "B", F::kMetres}, [](const S& s) { return s.obstacle_range_m; }},
      {{"wire_range", "nearest_wire_m", "m", "B", F::kMetres}, [](const S& s) { return s.nearest_wire_m; }},
      {{"obstacles", "obstacle_count", "1", "", F::kInteger}, [](const S& s) { return double(s.obstacle_count); }},
      {{"obstacle_nearest", "nearest_obstacle_m", "m", "N", F::kMetres}, [](const S& s) { return s.nearest_obstacle_m; }},
      {{"alt", "", "m", "above home", F::kMetres}, [](const S& s) { return s.altitude(); }},
      // What an operator reads at a glance (the status bar shows them).
      {{"gspeed", "", "m/s", "N, horizontal", F::kSpeed}, [](const S& s) { return s.ground_speed(); }},
      {{"heading", "", "rad", "N, 0 north, [0, 2 pi)", F::kAngle}, [](const S& s) { return s.heading(); }},
      {{"home_dist", "", "m", "N, horizontal", F::kMetres}, [](const S& s) { return s.home_distance(); }},
      {{"gps_lat", "gps_latitude_deg", "deg", "WGS84", F::kLatLon}, [](const S& s) { return s.gps.latitude_deg; }},
      {{"gps_lon", "gps_longitude_deg", "deg", "WGS84", F::kLatLon}, [](const S& s) { return s.gps.longitude_deg; }},
      {{"gps_alt", "gps_altitude_m", "m", "WGS84", F::kGeodeticAlt}, [](const S& s) { return s.gps.altitude_m; }},
      {{"gps_fix", "gps_fix", "1", "", F::kInteger}, [](const S& s) { return double(s.gps_fix); }},
      {{"gps_sats", "gps_satellites", "1", "", F::kInteger}, [](const S& s) { return double(s.gps_satellites); }},
      {{"mode", "flight_mode", "1", "", F::kFlightMode}, [](const S& s) { return double(static_cast<int>(s.flight_mode)); }},
      {{"failsafe", "failsafe", "1", "", F::kFailsafe}, [](const S& s) { return double(static_cast<int>(s.failsafe)); }},
      {{"landed", "landed", "1", "", F::kBool}, [](const S& s) { return B(s.landed); }},
      {{"battery_remaining", "battery_remaining", "1", "", F::kFraction}, [](const S& s) { return s.battery_remaining; }},
      {{"fence_radius", "fence_radius_m", "m", "N", F::kMetres}, [](const S& s) { return s.fence_radius_m; }},
      {{"fence_alt", "fence_alt_m", "m", "above home", F::kMetres}, [](const S& s) { return s.fence_alt_m; }},
      {{"home_lat", "home_latitude_deg", "deg", "WGS84", F::kLatLon}, [](const S& s) { return s.home.latitude_deg; }},
      {{"home_lon", "home_longitude_deg", "deg", "WGS84", F::kLatLon}, [](const S& s) { return s.home.longitude_deg; }},
      {{"home_alt", "home_altitude_m", "m", "WGS84", F::kGeodeticAlt}, [](const S& s) { return s.home.altitude_m; }},
      // uav-sysid reads these two to cut the log into chirps and pick the model structure.
      {{"chirp", "chirp_channel", "1", "", F::kInteger}, [](const S& s) { return double(s.chirp_channel); }},
      {{"att_mode", "attitude_mode", "1", "", F::kAttitudeMode}, [](const S& s) { return double(static_cast<int>(s.attitude_mode)); }},
      {{"avoid", "avoid_state", "1", "", F::kAvoidState}, [](const S& s) { return double(static_cast<int>(s.avoid_state)); }},
      {{"avoid_speed", "avoid_speed_limit_m_s", "m/s", "N", F::kSpeed}, [](const S& s) { return s.avoid_speed_limit_m_s; }},
      {{"replan_ms", "replan_ms", "ms", "", F::kMilliseconds}, [](const S& s) { return s.replan_ms; }},
      // U-Lion (thesis 2.6): the airframe, the tail-sitter's mode and its air data.
      {{"vehicle", "vehicle_type", "1", "", F::kVehicleType}, [](const S& s) { return double(static_cast<int>(s.vehicle_type)); }},
      {{"vtol_mode", "vtol_mode", "1", "", F::kVtolMode}, [](const S& s) { return double(static_cast<int>(s.vtol_mode)); }},
      {{"transition", "transition_progress", "1", "", F::kFraction}, [](const S& s) { return s.transition_progress; }},
      {{"airspeed", "airspeed_m_s", "m/s", "B, along x_B", F::kSpeed}, [](const S& s) { return s.airspeed_m_s; }},
      {{"alpha", "alpha_rad", "rad", "B", F::kAngle}, [](const S& s) { return s.alpha_rad; }},
  };
  return kSignals;
}

std::string_view DisplayUnit(const SignalDef& d) {
  switch (d.format) {
    case F::kAngle: return "deg";
    case F::kAngularRate: return "deg/s";
    case F::kFraction: return "%";
    case F::kLatLon: return "deg";
    default: return d.unit == "1" ? "" : d.unit;
  }
}

double DisplayValue(const SignalDef& d, double si) {
  constexpr double kDeg = 180.0 / M_PI;
  switch (d.format) {
    case F::kAngle:
    case F::kAngularRate: return si * kDeg;
    case F::kFraction: return si * 100.0;
    default: return si;
  }
}

std::string FormatForDisplay(const SignalDef& d, double si) {
  if (!std::isfinite(si)) return "n/a";
  char buf[64];
  const double v = DisplayValue(d, si);
  const std::string unit(DisplayUnit(d));
  const int i = static_cast<int>(std::lround(si));
  switch (d.format) {
    case F::kBool: return si > 0.5 ? "yes" : "no";
    case F::kTask: return TaskFromWire(i) ? std::string(Name(*TaskFromWire(i))) : "unknown (" + std::to_string(i) + ")";
    case F::kFailsafe: return FailsafeFromWire(i) ? std::string(Name(*FailsafeFromWire(i))) : "unknown";
    case F::kFlightMode: return FlightModeFromWire(i) ? std::string(Name(*FlightModeFromWire(i))) : "unknown";
    case F::kAttitudeMode: return AttitudeModeFromWire(i) ? std::string(Name(*AttitudeModeFromWire(i))) : "unknown";
    case F::kAvoidState: return AvoidStateFromWire(i) ? std::string(Name(*AvoidStateFromWire(i))) : "unknown";
    case F::kVehicleType: return VehicleTypeFromWire(i) ? std::string(Name(*VehicleTypeFromWire(i))) : "unknown";
    case F::kVtolMode: return VtolModeFromWire(i) ? std::string(Name(*VtolModeFromWire(i))) : "unknown";
    case F::kInteger: std::snprintf(buf, sizeof buf, "%d", i); return buf;
    case F::kLatLon: std::snprintf(buf, sizeof buf, "%.7f deg", v); return buf;
    case F::kAngle:
    case F::kAngularRate: std::snprintf(buf, sizeof buf, "%.1f %s", v, unit.c_str()); return buf;
    case F::kFraction: std::snprintf(buf, sizeof buf, "%.0f %%", v); return buf;
    case F::kNormalised: std::snprintf(buf, sizeof buf, "%.3f", v); return buf;
    default: std::snprintf(buf, sizeof buf, "%.2f %s", v, unit.c_str()); return buf;
  }
}

std::string FormatForLog(const SignalDef& d, double si) {
  char buf[64];
  switch (d.format) {
    case F::kAngle:
    case F::kAngularRate: std::snprintf(buf, sizeof buf, "%.5f", si); break;
    case F::kLatLon: std::snprintf(buf, sizeof buf, "%.8f", si); break;
    case F::kVolts:
    case F::kFraction:
    case F::kGeodeticAlt: std::snprintf(buf, sizeof buf, "%.3f", si); break;
    case F::kInteger:
    case F::kBool:
    case F::kTask:
    case F::kFailsafe:
    case F::kFlightMode:
    case F::kAvoidState:
    case F::kVehicleType:
    case F::kVtolMode:
    case F::kAttitudeMode: std::snprintf(buf, sizeof buf, "%d", static_cast<int>(std::lround(si))); break;
    default: std::snprintf(buf, sizeof buf, "%.4f", si); break;
  }
  return buf;
}

}  // namespace uav
