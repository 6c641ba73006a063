#pragma once
// The thesis's 9-state Kalman filter fusing visual odometry with the IMU (5.7, Eq. 5.33-5.45):
// state x = [p_N, v_N, beta] (NED position [m], velocity [m/s], accelerometer bias in N
// [m/s^2]), input u = a_N (the IMU's acceleration in N, gravity removed, at 50 Hz), measurement
// y = p_N from visual odometry (10 Hz). A plain class; the IMU thread runs it beside the INS, and
// its track is the "VO" track the GCS draws beside GPS and the truth.
#include <Eigen/Core>

namespace uav::nav {

struct VoImuFilterParams {
  double accel_noise = 0.3;     // [m/s^2] 1 sigma of a_N (Q of Eq. 5.39, from flight logs)
  double bias_walk = 0.01;      // [m/s^2/sqrt(s)] the bias's random walk
  double max_dt_s = 0.5;        // a longer step is not integrated (the filter is re-seeded)
};

class VoImuFilter {
 public:
  static constexpr int kStates = 9;
  using Vector = Eigen::Matrix<double, kStates, 1>;
  using Matrix = Eigen::Matrix<double, kStates, kStates>;

  explicit VoImuFilter(const VoImuFilterParams& p = {}) : p_(p) {}

  // Starts at a known position and velocity (the INS's when odometry begins).
  void Reset(const Eigen::Vector3d& p_N, const Eigen::Vector3d& v_N, double sigma_p_m, double sigma_v_mps);
  bool initialized() const { return initialized_; }

  // x' = A x + B u over dt (Eq. 5.43-5.44, discretised to first order). A non-finite input or a
  // step outside (0, max_dt_s] is refused and returns false.
  bool Predict(const Eigen::Vector3d& a_N, double dt_s);
  // y = C x + w (Eq. 5.45) with 1-sigma noise sigma_m per axis; gated at `gate_sigma` (0: none).
  // Returns false when refused (not finite, or beyond the gate).
  bool Correct(const Eigen::Vector3d& p_N, double sigma_m, double gate_sigma = 0.0);

  Eigen::Vector3d p_N() const { return x_.segment<3>(0); }
  Eigen::Vector3d v_N() const { return x_.segment<3>(3); }
  Eigen::Vector3d bias_N() const { return x_.segment<3>(6); }
  const Matrix& covariance() const { return P_; }

 private:
  VoImuFilterParams p_;
  bool initialized_ = false;
  Vector x_ = Vector::Zero();
  Matrix P_ = Matrix::Identity();
};

}  // namespace uav::nav
