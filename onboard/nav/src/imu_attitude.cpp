#include "uav/nav/imu_attitude.hpp"

#include <algorithm>
#include <cmath>

namespace uav::nav {
namespace {

constexpr double kGravity = 9.80665;

// The rotation of angle |w| dt about w (the exponential map), as a unit quaternion.
Eigen::Quaterniond Exp(const Eigen::Vector3d& w, double dt) {
  const Eigen::Vector3d r = w * dt;
  const double angle = r.norm();
  if (angle < 1e-12) return Eigen::Quaterniond(1, r.x() / 2, r.y() / 2, r.z() / 2).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle));
}

}  // namespace

bool ImuAttitude::Update(int64_t t_us, const Eigen::Vector3d& gyro_B, const Eigen::Vector3d& accel_B) {
  if (!gyro_B.allFinite() || !accel_B.allFinite() || (last_t_us_ >= 0 && t_us <= last_t_us_)) return false;
  const double dt = last_t_us_ < 0 ? 0.0 : (t_us - last_t_us_) * 1e-6;
  last_t_us_ = t_us;
  if (first_t_us_ < 0) first_t_us_ = t_us;
  if (!aligned_) {
    // Level from the mean specific force (at rest it is -g along N's down, seen in B), heading 0.
    accel_sum_B_ += accel_B;
    ++accel_samples_;
    if ((t_us - first_t_us_) * 1e-6 < p_.level_s) return true;
    const Eigen::Vector3d up_B = (accel_sum_B_ / accel_samples_).normalized();  // -down_N in B
    // R_NB^T (0, 0, -1) = up_B: roll and pitch from it (z-y-x angles with psi = 0).
    const double phi = std::atan2(-up_B.y(), -up_B.z());
    const double theta = std::atan2(up_B.x(), std::hypot(up_B.y(), up_B.z()));
    q_NB_ = Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX());
    aligned_ = true;
    aligned_t_us_ = t_us;
    return true;
  }
  if (dt <= 0 || dt > p_.max_dt_s) return true;  // a gap: hold the attitude, integrate from here
  // The gyro over the step, then gravity's correction at its end (where the sample was taken),
  // where the specific force is gravity's (not accelerating).
  q_NB_ = (q_NB_ * Exp(gyro_B - bias_B_, dt)).normalized();
  const double f = accel_B.norm();
  if (std::abs(f - kGravity) < p_.accel_gate * kGravity) {
    const Eigen::Vector3d measured_up_B = accel_B / f;
    const Eigen::Vector3d predicted_up_B = q_NB_.conjugate() * Eigen::Vector3d(0, 0, -1);
    const Eigen::Vector3d e = measured_up_B.cross(predicted_up_B);  // rotate the estimate toward it
    bias_B_ -= p_.ki * e * dt;
    q_NB_ = (q_NB_ * Exp(p_.kp * e, dt)).normalized();
  }
  return true;
}

Eigen::Matrix3d ImuAttitude::Covariance() const {
  constexpr double kLevelSigma = 0.5 * 3.14159265358979 / 180;  // gravity holds roll and pitch to about half a degree
  constexpr double kYawDrift = 0.002;                           // [rad/s] a MEMS gyro's yaw bias left over
  const double since_s = aligned_ ? std::max(0.0, (last_t_us_ - aligned_t_us_) * 1e-6) : 0.0;
  const double yaw_sigma = kLevelSigma + kYawDrift * since_s;
  return Eigen::Vector3d(kLevelSigma * kLevelSigma, kLevelSigma * kLevelSigma, yaw_sigma * yaw_sigma).asDiagonal();
}

}  // namespace uav::nav
