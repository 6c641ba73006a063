#pragma once
// Obstacles and the decimated point cloud from the stereo pair (thesis 3.5), as plain data: what
// the vehicle's STEREO thread produces and the GCS draws. obstacles_t and point_cloud_t are
// their wire forms; they are decoded once, here.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav {

// A vertical cylinder in local NED [m].
struct Obstacle {
  Eigen::Vector2d p_NE = Eigen::Vector2d::Zero();  // axis position
  double top_down_m = 0.0, bottom_down_m = 0.0;    // top < bottom (down is positive)
  double radius_m = 0.0;
  double safety_radius_m = 0.0;                    // radius + margin
  double range_m = 0.0;                            // horizontal distance from the vehicle to the surface
  Eigen::Matrix2d cov_NE = Eigen::Matrix2d::Zero();  // [m^2] of the axis position
  std::array<double, 4> image_box{};               // x0 y0 x1 y1, normalised 0..1 of the camera image
};

struct Obstacles {
  int64_t utime = 0;          // [us] vehicle clock of the stereo pair
  std::string camera;
  bool healthy = true;
  std::string reason;         // why not healthy
  double range_gate_m = 0.0;
  double nearest_m = -1.0;    // < 0: none
  std::vector<Obstacle> obstacles;  // nearest first
};

struct PointCloud {
  int64_t utime = 0;
  Eigen::Vector3d origin_N = Eigen::Vector3d::Zero();  // [m] where the vehicle was (the points are sent relative to it)
  std::vector<Eigen::Vector3f> p_N;                    // [m] local NED
};

}  // namespace uav
