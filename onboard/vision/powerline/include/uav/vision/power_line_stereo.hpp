#pragma once
// Power lines in 3-D from a stereo pair (thesis 3.6, Fig. 3.28: disparity along the detected
// wire). Wires are detected in the rectified left image; each fitted curve is cut into pieces,
// and each piece's window (along the wire and across it, on the thin-structure response) is
// slid along the rows of the right image to the disparity of best normalised cross-correlation.
// A wire has no texture along it, so the window follows the wire instead of being a square
// block, and reaches across to the wires strung beside it: their pattern only lines up at the
// right shift, where one wire alone would match its neighbour as well. A piece nearly parallel to the
// baseline has no measurable disparity and is left unranged; so is one whose best match is not
// clearly better than a second one. A wire's disparity is affine along its image (its points lie
// on a plane, so inverse depth is affine in the image, thesis Eq. 3.11), which a robust line fit
// over the pieces enforces. Depth uncertainty follows the error model of thesis 3.2 (Eq. 3.6-3.7).
#include <memory>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

#include "uav/vision/power_line_detector.hpp"
#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct WireRangingParams {
  double min_range_m = 1.5;             // [m] nearest wire searched for (largest disparity)
  double max_range_m = 60.0;            // [m] farthest (smallest disparity)
  int pieces = 12;                      // each curve is ranged in this many pieces
  double min_baseline_angle_deg = 8.0;  // pieces closer than this to the baseline direction are not ranged
  double window_half_width_px = 12.0;   // [px] matching window across the wire, either side
  double min_correlation = 0.6;         // weakest normalised cross-correlation accepted as a match
  double max_ambiguity = 0.8;           // a second match this strong (relative to the best) is ambiguous
  double disparity_sigma_px = 0.25;     // [px] matching precision behind the depth uncertainty
  double max_fit_residual_px = 0.75;    // [px] pieces off the wire's disparity line by more are outliers
  double max_slope_deg = 45.0;          // a "wire" rising more steeply from level is a pole or a trunk
  double vertical_image_deg = 10.0;     // following the image of the vertical within this ...
  double vertical_share = 0.8;          // ... over this share of its length makes it a pole or a trunk

  // Throws std::invalid_argument naming the field when a value is out of its range.
  void Validate() const;
};

// One detected wire, in 3-D where it could be ranged.
struct Wire3D {
  WireCurve curve;                      // in the rectified left image
  std::vector<Eigen::Vector2d> image_px;  // the curve in the original left image (for display)
  std::vector<Eigen::Vector3d> p_L;     // 3-D polyline [m] in the left camera frame; empty: not ranged
  std::vector<double> sigma_m;          // depth standard deviation of each p_L point [m]
  int pieces = 0, ranged_pieces = 0;    // pieces tried, pieces whose disparity was kept
  double range_m = -1.0;                // [m] nearest polyline point from the left camera; < 0: not ranged
  double range_sigma_m = 0.0;           // [m] its standard deviation
  bool vertical = false;                // a pole, a mast or a trunk: an obstacle, not a wire
  bool ranged() const { return !p_L.empty(); }
};

class PowerLineStereo {
 public:
  // Throws std::invalid_argument naming the bad rig or parameter.
  PowerLineStereo(const StereoRig& rig, const PowerLineParams& detection = {}, const WireRangingParams& ranging = {});
  ~PowerLineStereo();
  PowerLineStereo(PowerLineStereo&&) noexcept;

  // Left and right 8-bit BGR images of the rig's size. Throws std::invalid_argument for an empty
  // image, a size or a type that does not match. Longest wires first. With the direction of
  // gravity in the left camera frame (`down_L`, unit; zero when the attitude is not known),
  // vertical structures are marked (`vertical`): poles, masts and tree trunks are thin and
  // straight too, but no wire rises more than max_slope_deg from level (its 3-D polyline) or runs
  // toward the vertical's vanishing point in the image. Marks on a surface are dropped.
  std::vector<Wire3D> Process(const cv::Mat& left, const cv::Mat& right,
                              const Eigen::Vector3d& down_L = Eigen::Vector3d::Zero()) const;
  // The same on a BGR pair already rectified for this rig (by any StereoRectifier of it).
  std::vector<Wire3D> ProcessRectified(const cv::Mat& left_rect, const cv::Mat& right_rect,
                                       const Eigen::Vector3d& down_L = Eigen::Vector3d::Zero()) const;
  const RectifiedGeometry& geometry() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
