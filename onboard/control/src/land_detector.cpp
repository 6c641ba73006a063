#include "uav/control/land_detector.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "uav/shared/vehicle_enums.hpp"

namespace uav::control {

const char* Name(GroundState s) {
  switch (s) {
    case GroundState::kOnGround: return "on the ground";
    case GroundState::kFlying: return "flying";
    case GroundState::kFalling: return "falling";
    case GroundState::kCrashed: return "crashed";
  }
  return "?";
}

LandDetectorParams LandDetectorParams::FromParameters(const ParameterSet& p) {
  LandDetectorParams d;
  d.gravity = p.Get("gravity");
  d.free_fall_accel = 0.5 * d.gravity;
  d.crash_tilt_rad = p.Get("fs_crash_tilt") * M_PI / 180.0;
  d.crash_accel = p.Get("fs_crash_accel");
  d.upright_tilt_rad = p.Get("prearm_max_tilt") * M_PI / 180.0;
  if (p.Get("vehicle_type") == static_cast<double>(VehicleType::kTailSitter)) {
    d.up_B = Eigen::Vector3d(1, 0, 0);  // it stands on its tail, nose up
    d.check_tilt_in_flight = false;
  }
  return d;
}

namespace {
std::string Format(const char* fmt, double a, double b = 0.0) {
  char buf[120];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
}  // namespace

void LandDetector::Crash(std::string reason) {
  state_ = GroundState::kCrashed;
  crash_reason_ = std::move(reason);
}

void LandDetector::Recover() {
  state_ = GroundState::kOnGround;
  crash_reason_.clear();
  tipped_since_ = -1.0;
}

GroundState LandDetector::Update(const LandDetectorInputs& in) {
  if (!in.f_B.allFinite() || !in.w_B.allFinite() || !in.R_NB.allFinite()) return state_;
  last_t_ = in.t;
  if (first_t_ < 0.0) first_t_ = in.t;
  const double f = in.f_B.norm();
  const bool still = in.w_B.norm() < p_.rest_rate && std::abs(f - p_.gravity) < p_.rest_accel;
  if (!still) rest_since_ = -1.0;
  else if (rest_since_ < 0.0) rest_since_ = in.t;
  // Standing still, the specific force points up: its angle from the up axis is the tilt.
  if (f > 0.5 * p_.gravity) rest_tilt_ = std::acos(std::clamp(in.f_B.dot(p_.up_B) / f, -1.0, 1.0));

  switch (state_) {
    case GroundState::kOnGround:
      if (in.motors_on) state_ = GroundState::kFlying;
      break;
    case GroundState::kFlying: {
      if (!in.motors_on) {
        // Stopped in the air (the accelerometer reads free fall once the rotors have spun
        // down), or down (a landing's end: it comes to rest).
        if (motors_off_t_ < 0.0) motors_off_t_ = in.t;
        if (landing_) {  // the task manager stopped them at the touchdown it detected
          state_ = GroundState::kOnGround;
          motors_off_t_ = -1.0;
        } else if (f < p_.free_fall_accel) {
          state_ = GroundState::kFalling;
          peak_accel_ = 0.0;
          motors_off_t_ = -1.0;
        } else if (at_rest() || in.t - motors_off_t_ > 1.0) {
          state_ = GroundState::kOnGround;
          motors_off_t_ = -1.0;
        }
        break;
      }
      motors_off_t_ = -1.0;
      landing_ = in.landing;
      if (f > p_.crash_accel) {
        Crash(Format("impact of %.1f g in flight", f / p_.gravity));
        break;
      }
      // Tipped: the body's up axis from the estimated attitude, against the world's up.
      const double tilt = std::acos(std::clamp(-(in.R_NB * p_.up_B).z(), -1.0, 1.0));
      if (p_.check_tilt_in_flight && tilt > p_.crash_tilt_rad) {
        if (tipped_since_ < 0.0) tipped_since_ = in.t;
        if (in.t - tipped_since_ >= p_.crash_tilt_time_s)
          Crash(Format("tipped %.0f deg (limit %.0f) in flight", tilt * 180 / M_PI, p_.crash_tilt_rad * 180 / M_PI));
      } else {
        tipped_since_ = -1.0;
      }
      break;
    }
    case GroundState::kFalling:
      peak_accel_ = std::max(peak_accel_, f);
      // Down: the impact, or at rest wherever it came to lie. A fall is a crash either way.
      if (f > p_.crash_accel || at_rest())
        Crash(Format("fell with its motors stopped (impact of %.1f g)", peak_accel_ / p_.gravity));
      break;
    case GroundState::kCrashed:
      break;
  }
  return state_;
}

}  // namespace uav::control
