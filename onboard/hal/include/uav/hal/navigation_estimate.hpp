#pragma once
// What the flight stack knows about its own state: the navigation solution the IMU thread
// publishes (thesis 2.3.2). Control reads this, never the simulator's truth. Declared in hal so
// that the estimators (nav) and their readers (control, app) share it without linking each other.
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/shared/frames.hpp"

namespace uav::hal {

struct VehicleEstimate {
  int64_t utime = 0;
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // [m] NED from home
  Eigen::Vector3d v_N = Eigen::Vector3d::Zero();  // [m/s]
  Eigen::Quaterniond q_NB = Eigen::Quaterniond::Identity();
  EulerAngles euler;                              // of q_NB, z-y-x (Eq. 5.51)
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();  // [rad/s]
  Eigen::Vector3d f_B = Eigen::Vector3d::Zero();  // [m/s^2] specific force
  // [rad^2] the estimator's attitude covariance, of a small rotation dth_B with
  // R_NB(true) = R_NB(estimate) Exp(dth_B)
  Eigen::Matrix3d attitude_covariance_B = Eigen::Matrix3d::Zero();
  double altitude() const { return -p_N.z(); }    // [m] above home
  Eigen::Isometry3d T_NB() const {                // body pose in local NED
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = q_NB.toRotationMatrix();
    T.translation() = p_N;
    return T;
  }
};

}  // namespace uav::hal
