#include "uav/nav/vo_imu_filter.hpp"

#include <cmath>

#include <Eigen/Dense>

namespace uav::nav {

void VoImuFilter::Reset(const Eigen::Vector3d& p_N, const Eigen::Vector3d& v_N, double sigma_p_m, double sigma_v_mps) {
  x_.setZero();
  x_.segment<3>(0) = p_N;
  x_.segment<3>(3) = v_N;
  P_.setZero();
  P_.diagonal().segment<3>(0).setConstant(sigma_p_m * sigma_p_m);
  P_.diagonal().segment<3>(3).setConstant(sigma_v_mps * sigma_v_mps);
  P_.diagonal().segment<3>(6).setConstant(0.1 * 0.1);
  initialized_ = p_N.allFinite() && v_N.allFinite();
}

bool VoImuFilter::Predict(const Eigen::Vector3d& a_N, double dt) {
  if (!initialized_ || !a_N.allFinite() || !(dt > 0.0) || dt > p_.max_dt_s) return false;
  // Eq. 5.43-5.44: p' = v, v' = a - beta, beta' = 0.
  Matrix F = Matrix::Identity();
  F.block<3, 3>(0, 3) = Eigen::Matrix3d::Identity() * dt;
  F.block<3, 3>(3, 6) = -Eigen::Matrix3d::Identity() * dt;
  x_.segment<3>(0) += x_.segment<3>(3) * dt + 0.5 * (a_N - x_.segment<3>(6)) * dt * dt;
  x_.segment<3>(3) += (a_N - x_.segment<3>(6)) * dt;
  P_ = F * P_ * F.transpose();
  // Q (Eq. 5.39): the acceleration noise drives velocity (and position), the bias walks.
  const double qa = p_.accel_noise * p_.accel_noise;
  for (int i = 0; i < 3; ++i) {
    P_(i, i) += 0.25 * qa * dt * dt * dt * dt;
    P_(3 + i, 3 + i) += qa * dt * dt;
    P_(i, 3 + i) += 0.5 * qa * dt * dt * dt;
    P_(3 + i, i) += 0.5 * qa * dt * dt * dt;
    P_(6 + i, 6 + i) += p_.bias_walk * p_.bias_walk * dt;
  }
  return true;
}

bool VoImuFilter::Correct(const Eigen::Vector3d& y, double sigma_m, double gate_sigma) {
  if (!initialized_ || !y.allFinite() || !(sigma_m > 0.0) || !std::isfinite(sigma_m)) return false;
  // Eq. 5.45: C picks the position.
  Eigen::Matrix<double, 3, kStates> C = Eigen::Matrix<double, 3, kStates>::Zero();
  C.block<3, 3>(0, 0).setIdentity();
  const Eigen::Vector3d innovation = y - C * x_;
  const Eigen::Matrix3d S = C * P_ * C.transpose() + Eigen::Matrix3d::Identity() * sigma_m * sigma_m;
  if (gate_sigma > 0.0 && innovation.dot(S.ldlt().solve(innovation)) > gate_sigma * gate_sigma * 3.0) return false;
  const Eigen::Matrix<double, kStates, 3> K = P_ * C.transpose() * S.inverse();
  x_ += K * innovation;
  P_ = (Matrix::Identity() - K * C) * P_;
  P_ = 0.5 * (P_ + P_.transpose());
  return true;
}

}  // namespace uav::nav
