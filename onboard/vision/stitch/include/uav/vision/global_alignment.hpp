#pragma once
// Global alignment of a stitched map (a joint adjustment of every frame's placement, as OpenCV's
// stitcher and OpenDroneMap do after matching; the thesis's 6.5 names it as the fix for drift).
//
// Each frame k has a base placement B_k (image pixel -> map pixel: the navigation solution's
// ground projection, or where registration alone put it) and is moved by a similarity about its
// own centre c_k in map pixels, and tilted:
//   x' = c_k + (t_k + exp(s_k) R(theta_k) d) / (1 + g_k . d),  d = B_k p - c_k
// A camera leaning by a small angle a over flat ground sees the ground nearer on one side: its
// footprint's scale grows across it by a d / h (h the height above ground in map pixels), which
// g_k is; a similarity alone leaves that as a step of a pixel or two at the seams.
// The unknowns [t_k (2), theta_k, s_k, g_k (2)] are found by least squares (Ceres, sparse Cholesky):
//   - matched points of two frames land on the same map pixel (Huber loss, then once more
//     without the matches left further than `outlier_px` from agreeing: parallax, moving things);
//   - a navigation prior per frame: |t_k| to nav_position_sigma_m, theta_k to nav_yaw_sigma_rad,
//     s_k to nav_scale_sigma, g_k h_k to nav_tilt_sigma_rad (the navigation solution's own
//     uncertainty; the tilt's also without a navigation prior);
//   - the navigation's error changes slowly: t_k - t_{k-1} to nav_drift_sigma_m, so a frame no
//     image ties follows its neighbours instead of jumping by its own error.
// A pair whose matches disagree, at the start, by more than the navigation prior allows between
// its two frames (3 sigma of min(sqrt 2 nav_position_sigma_m, nav_drift_sigma_m sqrt(frames
// apart)), plus outlier_px) is left out whole: its "ground" was something that moved.
// Without any prior (a map without poses), the first frame holds the gauge.
// Plain data in, plain data out: no OpenCV, no messages.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav::vision {

struct AlignmentParams {
  double nav_position_sigma_m = 2.0;   // [m] navigation's horizontal error (GPS-grade), 1 sigma; (0, 1000]
  double nav_drift_sigma_m = 0.3;      // [m] change of that error between consecutive frames; (0, 100]
  double nav_yaw_sigma_rad = 0.02;     // [rad] heading error; (0, 1]
  double nav_scale_sigma = 0.005;      // relative height-above-ground error from frame to frame (baro); (0, 1]
  double nav_tilt_sigma_rad = 0.01;    // [rad] camera roll and pitch error (attitude and mount); (0, 0.5]
  double match_loss_px = 1.5;          // [map px] Huber loss scale of a match residual; (0, 100]
  double outlier_px = 4.0;             // [map px] matches further than this after the first solve are dropped; (0, 1000]
  int max_iterations = 50;             // per solve; 1..1000
};
// Throws std::invalid_argument naming the parameter out of its range.
void ValidateAlignmentParams(const AlignmentParams& params);

struct AlignmentFrame {
  Eigen::Matrix3d H_base = Eigen::Matrix3d::Identity();  // image pixel -> map pixel before the move
  Eigen::Matrix3d H_start = Eigen::Matrix3d::Identity(); // the placement to start from (the live map's)
  Eigen::Vector2d centre_px = Eigen::Vector2d::Zero();  // image pixel the move turns about (the principal point)
  double focal_px = 1.0;  // [image px] the camera's focal length: with H_base, the height above ground in map px
  bool nav_prior = false;  // the base is the navigation solution's placement
};

// Points seen in frames a and b (undistorted image pixels), paired index by index.
struct FrameMatches {
  int a = 0, b = 0;
  bool cross = false;  // frames from different passes (not neighbours in time)
  std::vector<Eigen::Vector2d> p_a, p_b;
};

struct ResidualStats {
  int matches = 0;
  double median_px = 0.0, p95_px = 0.0;  // [map px] distance between a match's two placements
};

struct AlignmentSolution {
  bool ok = false;
  std::string message;  // Ceres's summary line, or why it did not run
  std::vector<Eigen::Matrix3d> H_map_img;  // per frame, the adjusted placement
  int iterations = 0;
  int matches_used = 0, matches_dropped = 0;
  std::vector<bool> pair_used;  // per FrameMatches: false when the navigation prior's gate left it out
  int pairs_rejected = 0;
};

// gsd_m: map metres per pixel (turns the metre sigmas into pixels). Throws
// std::invalid_argument for a match naming a frame that does not exist or non-finite data.
AlignmentSolution AlignFrames(const std::vector<AlignmentFrame>& frames, const std::vector<FrameMatches>& matches,
                              double gsd_m, const AlignmentParams& params);

// How far apart the two placements put each match: over the cross-pass pairs only, or over all.
ResidualStats MatchResiduals(const std::vector<Eigen::Matrix3d>& H_map_img, const std::vector<FrameMatches>& matches,
                             bool cross_only);

}  // namespace uav::vision
