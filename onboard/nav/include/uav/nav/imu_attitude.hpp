#pragma once
// Attitude from an IMU alone, for a vehicle without a magnetometer or GPS (a recorded camera and
// IMU rig on the bench): the gyro integrated on the rotation group, its drift in roll and pitch
// pulled toward the measured gravity with a proportional-integral feedback that also estimates
// the gyro bias (Mahony, Hamel and Pflimlin, "Nonlinear complementary filters on the special
// orthogonal group", IEEE TAC 2008; the thesis's INS does the same job with a magnetometer, 2.3.3).
// The heading is the gyro's alone: it starts at 0 (north is where the body's x pointed) and
// drifts with the yaw bias, which gravity cannot see. Frames: N (NED), B the IMU's axes.
#include <cstdint>

#include <Eigen/Geometry>

namespace uav::nav {

struct ImuAttitudeParams {
  double kp = 1.0;        // [1/s] gravity's pull on roll and pitch
  double ki = 0.02;       // [1/s^2] gravity's pull on the gyro bias
  double level_s = 0.5;   // [s] the accelerometer averaged this long to level the start
  double max_dt_s = 0.1;  // a longer gap between samples is not integrated (the bias holds)
  // Where |f| differs from g by more than this fraction, the vehicle accelerates: gravity is not
  // trusted that sample.
  double accel_gate = 0.1;
};

class ImuAttitude {
 public:
  explicit ImuAttitude(const ImuAttitudeParams& p = {}) : p_(p) {}

  // One IMU sample at `t_us`: the angular rate [rad/s] and the specific force [m/s^2] in B.
  // Returns false for a non-finite sample or one that does not move time forward (ignored).
  bool Update(int64_t t_us, const Eigen::Vector3d& gyro_B, const Eigen::Vector3d& accel_B);

  bool aligned() const { return aligned_; }          // levelled: level_s of samples seen
  Eigen::Quaterniond q_NB() const { return q_NB_; }  // identity until aligned
  Eigen::Vector3d gyro_bias_B() const { return bias_B_; }
  int64_t utime() const { return last_t_us_; }
  // [rad^2] a small rotation's covariance in B: roll and pitch held by gravity, the heading's
  // growing with the time since alignment at the gyro's uncorrected bias (about 0.01 rad/s for
  // a MEMS gyro before the feedback has found it, 0.001 after).
  Eigen::Matrix3d Covariance() const;

 private:
  ImuAttitudeParams p_;
  bool aligned_ = false;
  Eigen::Quaterniond q_NB_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bias_B_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_sum_B_ = Eigen::Vector3d::Zero();
  int accel_samples_ = 0;
  int64_t first_t_us_ = -1, last_t_us_ = -1, aligned_t_us_ = -1;
};

}  // namespace uav::nav
