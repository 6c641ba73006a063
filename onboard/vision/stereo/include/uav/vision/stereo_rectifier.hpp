#pragma once
// A calibrated stereo rig and its rectification (thesis 3.5): both images are warped so that a
// scene point appears on the same row in each, displaced by the disparity d along the row, and
// the rectified left frame gives depth Z = f b / d (Eq. 3.10-3.11). Shared by every stereo
// algorithm (forward clearance, power lines), so that each one rectifies the same way.
#include <memory>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/shared/camera_intrinsics.hpp"

namespace uav::vision {

struct StereoRig {
  CameraIntrinsics left;
  CameraIntrinsics right;
  // Pose of the right camera in the left camera frame (C: x right, y down, z forward); a
  // parallel rig with baseline b has identity rotation and translation (b, 0, 0).
  Eigen::Isometry3d T_LR = Eigen::Isometry3d::Identity();
};

// The rectified pair's pinhole geometry: both cameras share f and the principal point, the
// right one sits baseline_m along the rectified x axis.
struct RectifiedGeometry {
  int width = 0, height = 0;  // [px]
  double f_px = 0.0;          // [px]
  double cx = 0.0, cy = 0.0;  // [px] principal point of the rectified left image
  double baseline_m = 0.0;    // [m]
  Eigen::Matrix3d R_L_rect = Eigen::Matrix3d::Identity();  // rectified left frame in the left camera frame

  // Point in the left camera frame of rectified left pixel (u, v) with disparity d > 0 [px]
  // (Eq. 3.11: Z = f b / d, X = (u - cx) Z / f, Y = (v - cy) Z / f, then rotated back).
  Eigen::Vector3d Triangulate(double u, double v, double d) const;
  // Depth standard deviation for a disparity standard deviation sigma_d at depth z (thesis 3.2,
  // Eq. 3.6-3.7: dZ = Z^2 / (f b) dd).
  double DepthSigma(double z_m, double sigma_d_px) const { return z_m * z_m / (f_px * baseline_m) * sigma_d_px; }
};

class StereoRectifier {
 public:
  // Throws std::invalid_argument naming the bad field (intrinsics, sizes, baseline, pose).
  explicit StereoRectifier(const StereoRig& rig);
  ~StereoRectifier();
  StereoRectifier(StereoRectifier&&) noexcept;

  // Rectifies a pair of 8-bit BGR or grey images of the rig's size (the channel count is kept).
  // Throws std::invalid_argument for an empty image, a size or type that does not match.
  void Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat* left_rect, cv::Mat* right_rect) const;
  // The same checks alone, for algorithms handed an already rectified pair.
  void CheckPair(const cv::Mat& left, const cv::Mat& right) const;
  const RectifiedGeometry& geometry() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
