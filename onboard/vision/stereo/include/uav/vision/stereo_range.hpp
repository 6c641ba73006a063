#pragma once
// Forward clearance from the stereo pair (thesis 3.2: a 0.12 m baseline forward rig; thesis 4.2:
// the laser grid gives texture to featureless walls). Rectify both images, match them by
// semi-global matching at half resolution, triangulate, and report the range to the
// nearest obstacle in the corridor the vehicle would fly through. A plain algorithm class: the
// onboard STEREO worker feeds it rendered (later: captured) frames.
#include <memory>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/vision/disparity.hpp"
#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct StereoRangeParams {
  int downscale = 2;                     // match at 1/downscale resolution (1, 2 or 4)
  int num_disparities = 64;              // [px] search range at matching resolution, multiple of 16
  int block_size = 9;                    // [px] matching window at matching resolution, odd, 3..21
  double texture_threshold = 2.0;        // [grey levels/px] minimum mean |d/dx| over the window
  double corridor_half_width_m = 1.0;    // corridor around the optical axis: |x_C| ...
  double corridor_half_height_m = 0.5;   // ... and |y_C| [m]
  double max_range_m = 20.0;             // points farther than this are ignored
  int min_points = 100;                  // the range is the min_points-th nearest corridor point
};

struct StereoRangeResult {
  bool obstacle = false;         // at least min_points corridor points within max_range_m
  double range_m = 0.0;          // [m] along the optical axis (z_C of the left camera)
  double valid_fraction = 0.0;   // share of pixels with a disparity
  int corridor_points = 0;
  cv::Mat depth_m;               // CV_32F, left camera, rectified, matching resolution; 0 = none
};

class StereoRange {
 public:
  // Throws std::invalid_argument naming the bad field (intrinsics, baseline, parameters).
  StereoRange(const StereoRig& rig, const StereoRangeParams& params);
  ~StereoRange();
  StereoRange(StereoRange&&) noexcept;

  // Left and right 8-bit BGR or grey images of the rig's size. Throws std::invalid_argument
  // for an empty image, a size or type that does not match.
  StereoRangeResult Process(const cv::Mat& left, const cv::Mat& right) const;
  // The same on a pair rectified by rectifier() (a worker feeding several stereo algorithms
  // rectifies once).
  StereoRangeResult ProcessRectified(const cv::Mat& left_rect, const cv::Mat& right_rect) const;
  const StereoRectifier& rectifier() const;

  // Left-image columns [0, BlindColumns()) have no partner within the disparity search range:
  // obstacles seen only there (very near and far to the left) are not measured.
  int BlindColumns() const;

  // The corridor rule applied to points in the left camera frame (shared with the tests'
  // ground truth): the min_points-th smallest z of the points inside the corridor.
  static StereoRangeResult RangeFromPoints(const std::vector<Eigen::Vector3f>& p_L, const StereoRangeParams& params);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
