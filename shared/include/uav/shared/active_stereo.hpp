#pragma once
// Active stereo's report (thesis ch. 4) as plain data: what the vehicle measures and publishes
// (active_stereo_t) and the GCS plots and draws. Decoded once, here.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/signals.hpp"

namespace uav {

struct LaserDotReport {
  double u = 0.0, v = 0.0;  // left image position, 0..1 of width and height
  double down_m = 0.0;      // [m] below the body origin along gravity
  int cluster = 0;
};

struct DotCluster {
  Eigen::Vector3d centre_B = Eigen::Vector3d::Zero();  // [m] body frame (FRD)
  double down_m = 0.0;    // [m] mean depth below the body origin along gravity
  double spread_m = 0.0;  // [m] vertical standard deviation
  int points = 0;
  bool ground = false;
};

struct ActiveStereoReport {
  int64_t utime = 0;
  std::string camera;
  bool healthy = false;   // false: no height, reason says why
  std::string reason;
  double height_m = 0.0;  // [m] over the ground cluster, along gravity
  double height_sigma_m = 0.0;
  int left_dots = 0, right_dots = 0, ambiguous = 0;
  std::vector<LaserDotReport> dots;
  std::vector<DotCluster> clusters;
};

// Its signals (the height over the ground and the dot counts): group "ASTEREO".
template <>
struct ReportSignals<ActiveStereoReport> {
  static constexpr std::string_view kGroup = "ASTEREO";
  static const std::vector<Signal<ActiveStereoReport>>& Table();
};

}  // namespace uav
