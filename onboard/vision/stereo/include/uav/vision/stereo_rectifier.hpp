#pragma once
// A calibrated stereo rig and its rectification (thesis 3.5): both images are warped so that a
// scene point appears on the same row in each, displaced by the disparity d along the row, and
// the rectified left frame gives depth Z = f b / d (Eq. 3.10-3.11). Shared by every stereo
// algorithm (forward clearance, power lines), so that each one rectifies the same way.
#include <array>
#include <memory>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/vision/stereo_error_model.hpp"

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
  // The reprojection matrix of Eq. 3.10 for disparities at 1/downscale resolution: Q (u, v, d, 1)
  // is the homogeneous point in the rectified left frame (Eq. 3.11); c_xl = c_xr after
  // rectification. Row-major 4x4.
  std::array<double, 16> Q(int downscale = 1) const;
  // The error model of thesis 3.2 for disparities at 1/downscale resolution.
  StereoErrorModel ErrorModel(double sigma_d_px, double calibration_px, int downscale = 1) const;
  // A pair that is already rectified (Middlebury, KITTI): focal length and baseline known,
  // principal point at the image centre unless given. Throws std::invalid_argument naming a
  // non-finite or non-positive value.
  static RectifiedGeometry OfRectifiedPair(int width, int height, double f_px, double baseline_m,
                                           double cx = -1.0, double cy = -1.0);
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
  // Raw pixel positions of one camera's image to the rectified image (for sparse features, where
  // warping the whole image is waste).
  enum class Side { kLeft, kRight };
  std::vector<cv::Point2f> RectifyPoints(const std::vector<cv::Point2f>& raw_px, Side side) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
