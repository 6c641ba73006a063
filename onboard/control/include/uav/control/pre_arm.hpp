#pragma once
// Pre-arm checks (as PX4's and ArduPilot's arming checks): each has a name and, when it fails, a
// reason the operator can act on. The control thread evaluates them every cycle on the ground;
// `arm` is refused while any fails, naming the failing ones. A command that arrives has come
// over the link, so the link needs no check of its own; the failsafes refuse arming on their own.
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"
#include "uav/shared/pre_arm.hpp"
#include "uav/shared/visual_odometry.hpp"

namespace uav::control {

// Defaults as the vehicle file's (prearm_*, fs_battery_return, fs_fence_*).
struct PreArmParams {
  int min_satellites = 6;                      // a 3-D fix from fewer is not trusted for position hold
  double max_attitude_sigma_rad = 5 * M_PI / 180;  // the INS's attitude 1-sigma must have converged below this
  double max_sensor_age_s = 0.1;               // [s] the newest IMU sample must be younger
  double battery_min = 0.25;                   // [0..1] arming at or below the return threshold is refused
  double fence_radius_m = 500, fence_alt_m = 120;
  double max_tilt_rad = 20 * M_PI / 180;       // standing still, tilted from upright at most this
  // Visual odometry runs (vo_enable): without a GPS fix the position comes from it once it sees
  // the ground (an indoor, GPS-denied start, thesis ch. 5), so a missing fix does not refuse.
  bool visual_odometry = false;
  static PreArmParams FromParameters(const ParameterSet& p);
};

struct PreArmInputs {
  int gps_fix = 0;                 // 0 none, 2 2-D, 3 3-D
  int gps_satellites = 0;
  PositionSource position_source = PositionSource::kGps;
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();     // [m] the estimate
  Eigen::Vector3d v_N = Eigen::Vector3d::Zero();     // [m/s]
  Eigen::Matrix3d attitude_covariance_B = Eigen::Matrix3d::Zero();  // [rad^2]
  double sensor_age_s = 0.0;       // [s] since the newest IMU sample
  bool sensors_finite = true;      // the IMU sample's numbers are all finite
  double battery_remaining = 1.0;  // [0..1]
  // The land detector's view (land_detector.hpp): still for its rest time, the tilt of the
  // measured gravity from upright, and a crash not yet over (its reason; "" none).
  bool at_rest = true;
  double rest_tilt_rad = 0.0;
  std::string crash;
};

// Every check, in a fixed order (gps, ins, sensors, battery, geofence, attitude, motion, crash),
// passed or failed.
std::vector<PreArmCheck> EvaluatePreArm(const PreArmInputs& in, const PreArmParams& p);

}  // namespace uav::control
