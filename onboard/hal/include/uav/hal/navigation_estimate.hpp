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
  // [m] in the odometry frame O (REP-105's odom): NED axes; the horizontal position integrated
  // from the estimated velocity alone, so it never jumps with a GPS or vision correction; the
  // height is p_N's. It drifts from p_N slowly (GPS's wander: about a metre a minute). What the
  // vehicle maps around itself (the obstacle map) is kept in O, so a wall stays where it was seen
  // relative to the vehicle while the GPS fix wanders. An estimator that has no smoother
  // position sets it to p_N.
  Eigen::Vector3d p_O = Eigen::Vector3d::Zero();
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
  Eigen::Isometry3d T_OB() const {  // body pose in the odometry frame
    Eigen::Isometry3d T = T_NB();
    T.translation() = p_O;
    return T;
  }
  // O's origin in N: a point q_O is q_O + p_NO() in N (the axes are the same).
  Eigen::Vector3d p_NO() const { return p_N - p_O; }
};

}  // namespace uav::hal
