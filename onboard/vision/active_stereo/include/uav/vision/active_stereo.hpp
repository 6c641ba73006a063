#pragma once
// Active stereo (thesis ch. 4): a laser grating projects its own dots onto featureless surfaces;
// both cameras see them, and each matched dot is a 3-D point. Pipeline (4.3): an intensity
// threshold, contours, a circle fit with an area filter, the dot centres rectified, a search
// along the epipolar line in a disparity window with ambiguous matches rejected, linear
// triangulation by SVD (Eq. 4.1-4.11), K-means on the points, and the height over the ground
// cluster with each cluster's spread. Plain class: images and poses in, points and height out.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

#include "uav/shared/active_stereo.hpp"
#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct ActiveStereoParams {
  double threshold_dn = 60.0;        // a dot pixel is this much brighter than the image's median [DN]
  double min_dot_area_px = 3.0;      // circle fit's area outside these: noise or a reflection, not a dot
  double max_dot_area_px = 300.0;
  double max_bright_fraction = 0.15; // more of the image above the threshold: glare, too bright to see dots
  double min_disparity_px = 20.0;    // thesis 4.3.2: search 20..150 px left of the left dot ...
  double max_disparity_px = 150.0;
  double row_tolerance_px = 10.0;    // ... and within 10 px of its row
  // A second candidate whose row offset is within this of the best one's: ambiguous, rejected.
  // A rectified true match sits within a few tenths of a pixel of its row; any dot pattern this
  // dense repeats within about 3 px of a row inside the window (Minkowski: the window's 20 x 260
  // px strip holds a lattice point once the pattern's cell is under 1300 px^2), so 1 px.
  double ambiguity_margin_px = 1.0;
  int max_clusters = 4;              // K-means: k grows up to this ...
  double cluster_spread_m = 0.05;    // ... until every cluster's vertical spread is below this
  int min_points = 20;               // fewer triangulated dots: no height
  int min_ground_points = 6;         // the ground cluster needs this many points
  void Validate() const;             // throws std::invalid_argument naming the value
};

struct LaserPoint {
  cv::Point2f left_px;               // dot centre in the (raw) left image [px]
  double disparity_px = 0.0;         // rectified
  Eigen::Vector3d p_C = Eigen::Vector3d::Zero();  // [m] left camera frame
  double down_m = 0.0;               // [m] below the body origin along gravity
  int cluster = -1;
};


struct ActiveStereoResult {
  bool healthy = false;              // false: no height, `reason` says why
  std::string reason;
  int left_dots = 0, right_dots = 0; // dots found in each image
  int ambiguous = 0;                 // left dots with more than one candidate (rejected)
  std::vector<LaserPoint> points;    // triangulated
  std::vector<DotCluster> clusters;  // K-means clusters (shared with the report the vehicle sends)
  double height_m = 0.0;             // [m] of the body origin over the ground cluster, along gravity
  double height_sigma_m = 0.0;       // [m] standard error of that mean
};

class ActiveStereo {
 public:
  // Throws std::invalid_argument naming a bad rig or parameter.
  ActiveStereo(const StereoRig& rig, const ActiveStereoParams& params);
  ~ActiveStereo();
  ActiveStereo(ActiveStereo&&) noexcept;

  // One pair (raw, 8-bit grey or BGR, the rig's size). T_BL: the left camera's mount in the body;
  // R_NB: the body's attitude (only roll and pitch matter: heights are along gravity). Bad
  // images (empty, wrong size or type, blank, too bright) give healthy = false with the reason.
  ActiveStereoResult Process(const cv::Mat& left, const cv::Mat& right, const Eigen::Isometry3d& T_BL,
                             const Eigen::Matrix3d& R_NB) const;

  // The dot centres of one image [px] (threshold, contours, circle fit, area filter); empty with
  // `problem` set when the image cannot show dots.
  std::vector<cv::Point2f> FindDots(const cv::Mat& image, std::string* problem) const;

  const ActiveStereoParams& params() const;
  const RectifiedGeometry& geometry() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Keeps the ground the height is measured to from pair to pair, in the navigation frame: the
// dots' farthest cluster is the floor only while it stays at the floor's level. Over a table or
// ledge wider than the dot pattern no dot reaches the floor; the pair then has no height (the
// reason says the floor is hidden) rather than a spike, and the INS carries on with its other
// sensors. A new level under the vehicle for relock_s becomes the ground.
class GroundTracker {
 public:
  explicit GroundTracker(double max_step_m = 0.2, double relock_s = 3.0);
  // z_N: the body's down position from the navigation solution at the pair [m].
  void Apply(ActiveStereoResult* result, double z_N, int64_t utime);

 private:
  double max_step_m_, relock_s_;
  std::optional<double> floor_N_, candidate_N_;
  int64_t candidate_since_ = 0;
};

// Eq. 4.8-4.11: the point X with x = P X, x' = P' X for two 3x4 projection matrices, solved in
// least squares by SVD.
Eigen::Vector3d TriangulateLinear(const Eigen::Matrix<double, 3, 4>& P, const Eigen::Matrix<double, 3, 4>& P_prime,
                                  const Eigen::Vector2d& x, const Eigen::Vector2d& x_prime);

}  // namespace uav::vision
