#include "uav/control/pre_arm.hpp"

#include <cmath>
#include <cstdio>
#include <string>

namespace uav::control {

PreArmParams PreArmParams::FromParameters(const ParameterSet& p) {
  PreArmParams out{static_cast<int>(p.Get("prearm_min_sats")), p.Get("prearm_max_att_sigma") * M_PI / 180.0,
                   p.Get("prearm_max_sensor_age"), p.Get("fs_battery_return"), p.Get("fs_fence_radius"), p.Get("fs_fence_alt")};
  out.max_tilt_rad = p.Get("prearm_max_tilt") * M_PI / 180.0;
  out.visual_odometry = p.Get("vo_enable") != 0.0;
  return out;
}

namespace {

std::string Format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// GPS: a 3-D fix from enough satellites, unless the position comes from visual odometry (a
// GPS-denied start); never with no position source at all.
PreArmCheck CheckGps(const PreArmInputs& in, const PreArmParams& p) {
  if (in.position_source == PositionSource::kVision) return {"gps", true, "position from visual odometry"};
  if (in.position_source == PositionSource::kInertial) return {"gps", false, "no position source (no GPS fix, no visual odometry)"};
  if (in.gps_fix < 3 && p.visual_odometry)
    return {"gps", true, "no GPS fix: the position comes from visual odometry once it sees the ground"};
  if (in.gps_fix < 3) return {"gps", false, Format("no 3-D fix (fix %.0f, %.0f satellites)", in.gps_fix, in.gps_satellites)};
  if (in.gps_satellites < p.min_satellites)
    return {"gps", false, Format("%.0f satellites, at least %.0f needed", in.gps_satellites, p.min_satellites)};
  return {"gps", true, Format("3-D fix, %.0f satellites", in.gps_satellites)};
}

// INS: a finite estimate, at rest, whose attitude has converged (the largest 1-sigma).
PreArmCheck CheckIns(const PreArmInputs& in, const PreArmParams& p) {
  if (!in.p_N.allFinite() || !in.v_N.allFinite() || !in.attitude_covariance_B.allFinite())
    return {"ins", false, "the estimate is not finite"};
  const double sigma = std::sqrt(std::max(0.0, in.attitude_covariance_B.diagonal().maxCoeff()));
  if (sigma > p.max_attitude_sigma_rad)
    return {"ins", false,
            Format("attitude not converged: %.1f deg 1-sigma, at most %.1f", sigma * 180 / M_PI, p.max_attitude_sigma_rad * 180 / M_PI)};
  return {"ins", true, Format("attitude %.2f deg 1-sigma", sigma * 180 / M_PI)};
}

PreArmCheck CheckSensors(const PreArmInputs& in, const PreArmParams& p) {
  if (!in.sensors_finite) return {"sensors", false, "the IMU reports a number that is not finite"};
  if (!(in.sensor_age_s <= p.max_sensor_age_s))
    return {"sensors", false, Format("no IMU sample for %.2f s (at most %.2f)", in.sensor_age_s, p.max_sensor_age_s)};
  return {"sensors", true, "IMU current"};
}

PreArmCheck CheckBattery(const PreArmInputs& in, const PreArmParams& p) {
  if (!(in.battery_remaining > p.battery_min))
    return {"battery", false,
            Format("%.0f %% remaining, at or below the return threshold %.0f %%", 100 * in.battery_remaining, 100 * p.battery_min)};
  return {"battery", true, Format("%.0f %% remaining", 100 * in.battery_remaining)};
}

// The vehicle must stand inside the geofence it would enforce (it would breach on takeoff).
PreArmCheck CheckGeofence(const PreArmInputs& in, const PreArmParams& p) {
  if (!(p.fence_radius_m > 0 && p.fence_alt_m > 0)) return {"geofence", false, "no geofence loaded"};
  const double d = in.p_N.head<2>().norm();
  if (!(d < p.fence_radius_m))
    return {"geofence", false, Format("%.0f m from home, outside the %.0f m geofence", d, p.fence_radius_m)};
  return {"geofence", true, Format("inside, %.0f m of %.0f m", d, p.fence_radius_m)};
}

// Standing upright (PX4 and ArduPilot refuse to arm a tilted vehicle: it would flip on its rotors).
PreArmCheck CheckAttitude(const PreArmInputs& in, const PreArmParams& p) {
  if (!(in.rest_tilt_rad <= p.max_tilt_rad))
    return {"attitude", false, Format("tilted %.0f deg from upright, at most %.0f", in.rest_tilt_rad * 180 / M_PI, p.max_tilt_rad * 180 / M_PI)};
  return {"attitude", true, Format("upright, tilted %.0f deg", in.rest_tilt_rad * 180 / M_PI)};
}

PreArmCheck CheckMotion(const PreArmInputs& in, const PreArmParams&) {
  if (!in.at_rest) return {"motion", false, "the vehicle is moving (the IMU is not still)"};
  return {"motion", true, "still"};
}

// A crash is over once the vehicle stands upright and still and its estimator has aligned anew;
// until then the estimate may be anything (it ran on a tumbling IMU).
PreArmCheck CheckCrash(const PreArmInputs& in, const PreArmParams&) {
  if (!in.crash.empty()) return {"crash", false, "crashed (" + in.crash + "): stand it upright and still"};
  return {"crash", true, "no crash"};
}

}  // namespace

std::vector<PreArmCheck> EvaluatePreArm(const PreArmInputs& in, const PreArmParams& p) {
  return {CheckGps(in, p),      CheckIns(in, p),      CheckSensors(in, p), CheckBattery(in, p),
          CheckGeofence(in, p), CheckAttitude(in, p), CheckMotion(in, p),  CheckCrash(in, p)};
}

}  // namespace uav::control
