#pragma once
// Ground contact and crash detection (PX4's land detector and its crash check, ArduPilot's crash
// check): whether the vehicle stands on the ground at rest, flies, falls with its motors
// stopped, or has crashed. "Landed" means on the ground at rest, nothing else. A vehicle that
// hit something hard, tipped past its limit in flight or fell with its motors stopped (an
// emergency stop, a motor failure) has crashed, and stays crashed until it stands upright and
// still again; then its estimator aligns anew (the INS ran on a tumbling IMU) and it may be armed
// once the estimate has converged. Plain class fed the IMU and the estimate at the control rate.
#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"

namespace uav::control {

enum class GroundState : int8_t {
  kOnGround = 0,  // standing (or resting after a landing): not flying, not falling
  kFlying = 1,    // the rotors carry it
  kFalling = 2,   // the motors stopped in the air: in free fall
  kCrashed = 3,   // impact, a tip-over in flight, or a fall: see crash_reason()
};
const char* Name(GroundState s);  // "on the ground", "flying", "falling", "crashed"

struct LandDetectorParams {
  double gravity = 9.80665;                  // [m/s^2]
  double crash_tilt_rad = 60.0 * M_PI / 180;  // fs_crash_tilt: tipped beyond this in flight ...
  double crash_tilt_time_s = 0.5;            // ... this long is a crash (a flip, a rotor lost)
  double crash_accel = 100.0;                // fs_crash_accel [m/s^2]: a specific force beyond (10 g): an impact
  double rest_rate = 0.1;                    // [rad/s] at rest: body rates below this ...
  double rest_accel = 0.8;                   // [m/s^2] ... the specific force within this of gravity ...
  double rest_time_s = 0.5;                  // ... for this long
  double free_fall_accel = 0.5 * 9.80665;    // [m/s^2] motors stopped and the specific force below: falling
  // Which body axis points up when the vehicle stands on the ground: -z_B for a quadrotor,
  // +x_B (nose up, on its tail) for a tail-sitter, whose flight attitudes span 90 degrees (its
  // tilt in flight is not checked).
  Eigen::Vector3d up_B = Eigen::Vector3d(0, 0, -1);
  double upright_tilt_rad = 20.0 * M_PI / 180;  // prearm_max_tilt: standing upright, a crash is over
  bool check_tilt_in_flight = true;
  static LandDetectorParams FromParameters(const ParameterSet& p);
};

struct LandDetectorInputs {
  double t = 0.0;                                     // [s] vehicle clock
  Eigen::Vector3d f_B = Eigen::Vector3d::Zero();      // [m/s^2] the IMU's specific force
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();      // [rad/s] the IMU's body rates
  Eigen::Matrix3d R_NB = Eigen::Matrix3d::Identity();  // the estimated attitude
  bool motors_on = false;                             // armed and flying (rotors above idle)
  bool landing = false;  // a landing is being flown: motors that stop now stop at its touchdown
};

class LandDetector {
 public:
  explicit LandDetector(const LandDetectorParams& p = {}) : p_(p) {}
  void SetParams(const LandDetectorParams& p) { p_ = p; }
  // One step; returns the state after it. A finite input only (a refused IMU sample is skipped).
  GroundState Update(const LandDetectorInputs& in);
  GroundState state() const { return state_; }
  // Why it crashed ("impact of 8.4 g", "tipped 75 deg for 0.5 s in flight", "fell from the air
  // with its motors stopped"), "" unless crashed.
  const std::string& crash_reason() const { return crash_reason_; }
  // Still (body rates and specific force at rest) for rest_time_s, or ever since the first sample
  // (a vehicle powered on standing needs no wait; one that was moved does).
  bool at_rest() const {
    return rest_since_ >= 0.0 && (rest_since_ == first_t_ || last_t_ - rest_since_ >= p_.rest_time_s);
  }
  // The angle between the up axis and the measured gravity's direction [rad] (meaningful at rest).
  double rest_tilt_rad() const { return rest_tilt_; }
  // Standing upright (tilted at most upright_tilt_rad) and still.
  bool upright_at_rest() const { return at_rest() && rest_tilt_ <= p_.upright_tilt_rad; }
  // The crash is over (standing upright and still, the estimator aligned anew): on the ground.
  void Recover();

 private:
  void Crash(std::string reason);

  LandDetectorParams p_;
  GroundState state_ = GroundState::kOnGround;
  std::string crash_reason_;
  double last_t_ = 0.0;
  double first_t_ = -1.0;  // the first sample's time
  double rest_since_ = -1.0;
  double tipped_since_ = -1.0;
  double motors_off_t_ = -1.0;
  bool landing_ = false;  // a landing was flown while the motors last ran  // when the motors stopped, while it is not yet known where
  double rest_tilt_ = 0.0;
  double peak_accel_ = 0.0;  // while falling
};

}  // namespace uav::control
