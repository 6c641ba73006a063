#pragma once
// Generic obstacles from a stereo pair (thesis 3.5): disparity (3.5.1), reprojection with Q
// (Eq. 3.10-3.11), a range gate where the error model's depth error passes a limit (3.2,
// Eq. 3.6-3.7), a voxel grid, removal of the ground plane, Euclidean clustering with a minimum
// cluster size, and per cluster a vertical cylinder (centre, radius, top and bottom) inflated by
// a safety margin, with its uncertainty from the error model; a cluster with a thin lowest part
// under a wide one (a tree seen whole) gives two, its trunk and its crown. A plain class: the STEREO worker
// feeds it rendered (later: captured) pairs, uav-stereo feeds it files.
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/vision/disparity.hpp"
#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct ObstacleParams {
  DisparityParams disparity;
  double sigma_d_px = 0.20;          // [px] disparity precision at matching resolution (uav-stereo-error: 0.20 at 320x240)
  double calibration_px = 0.5;       // [px] pixel position error p (Eq. 3.4-3.5)
  double max_depth_sigma_m = 0.3;    // range gate: points deeper than where the model's dZ reaches this are dropped
  double max_disparity_step_px = 1.0; // [px] at matching resolution: a larger step to a neighbour is a depth edge, dropped
  double voxel_leaf_m = 0.05;        // voxel grid edge
  double ground_tolerance_m = 0.15;  // points this close to the ground plane are ground
  double max_ground_tilt_deg = 10.0; // the ground plane's normal is this close to vertical
  double cluster_tolerance_m = 0.2;  // Euclidean clustering distance
  int min_cluster_voxels = 20;       // smaller clusters are noise, not obstacles
  double safety_margin_m = 0.5;      // added to each cylinder's radius (thesis 3.5)
  // Throws std::invalid_argument naming the bad field.
  void Validate() const;
};

// One obstacle as a vertical cylinder in the world frame W (z down: NED onboard).
struct ObstacleCylinder {
  Eigen::Vector3d centre_W = Eigen::Vector3d::Zero();  // on the axis, half-way between top and bottom
  double radius_m = 0.0;         // the seen object's horizontal half-extent
  double safety_radius_m = 0.0;  // radius_m + safety margin: what the vehicle keeps out of
  double top_m = 0.0;            // [m] z of the highest point (W z down: top_m < bottom_m)
  double bottom_m = 0.0;         // [m] z of the lowest point (the ground where it stands on it)
  double range_m = 0.0;          // [m] horizontal distance from the camera to the surface (centre - radius)
  Eigen::Matrix2d cov_xy = Eigen::Matrix2d::Zero();  // [m^2] horizontal covariance of the centre (Eq. 3.4-3.7)
  int voxels = 0;
  // The part of a cluster above its trunk (a tree's crown, split off the thin part under it), and
  // round (no deeper than wide beyond the depth noise): it stands on that trunk, not on the
  // ground, so the space under it is free.
  bool on_trunk = false;
};

struct StereoStageTimes {
  double disparity_ms = 0, reproject_ms = 0, voxel_ms = 0, ground_ms = 0, cluster_ms = 0, cylinders_ms = 0;
};

struct StereoObstacles {
  std::vector<ObstacleCylinder> obstacles;  // nearest first
  std::vector<Eigen::Vector3f> points_L;    // every reprojected point, left camera frame (C axes)
  std::vector<Eigen::Vector3f> cloud_W;     // range-gated voxel cloud in W, ground included
  DisparityMap disparity;
  double gate_depth_m = 0.0;                // [m] the range gate from the error model
  double ground_z_m = 0.0;                  // [m] z of the ground plane in W; NaN when none found
  StereoStageTimes times;
};

class StereoObstacleDetector {
 public:
  // Throws std::invalid_argument naming the bad field of the geometry or the parameters.
  StereoObstacleDetector(const RectifiedGeometry& geometry, const ObstacleParams& params);
  ~StereoObstacleDetector();
  StereoObstacleDetector(StereoObstacleDetector&&) noexcept;

  // A rectified pair of the geometry's size and the left camera's pose in W (its rotation says
  // where vertical is). Throws std::invalid_argument naming a bad image or a non-finite pose.
  StereoObstacles Process(const cv::Mat& left_rect, const cv::Mat& right_rect, const Eigen::Isometry3d& T_WL) const;

  const RectifiedGeometry& geometry() const;
  const ObstacleParams& params() const;
  // The margin kept beyond each obstacle's radius (obs_margin, changed in flight). Throws
  // std::invalid_argument for a negative or non-finite margin. Not while Process runs.
  void SetSafetyMargin(double margin_m);
  // The error model at matching resolution and the range gate it gives.
  const StereoErrorModel& error_model() const;
  double GateDepth() const;
  // W for a camera without a pose: level, at the origin, looking along W's x (north).
  static Eigen::Isometry3d LevelCameraPose();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
