#pragma once
// Our own semi-global matcher (Hirschmueller 2008, on census costs as Zabih and Woodfill 1994),
// written for two cores: OpenCV's three-way SGBM alone takes the whole 25 ms budget at 640 x 480
// with 128 disparities. Internal to uav_onboard_stereo; DisparityMatcher is the public face.
#include <opencv2/core/mat.hpp>

namespace uav::vision::detail {

struct CensusSgmParams {
  int num_disparities = 128;  // [px], multiple of 16
  // Penalties in census bits (a cost is 0..62), P2 = 4 P1 as in OpenCV's stereo_match sample.
  // On opencv-doc's Aloe pair (its only pair with ground truth) P1 10-25 and P2 60-120 all lie
  // within 2.5 points of bad pixels of each other; a lower P2 keeps depth edges sharper.
  int p1 = 20;                // penalty of a 1 px disparity step between neighbours
  int p2 = 80;                // penalty of a larger step
  int uniqueness_pct = 10;    // the best cost must beat every other (beyond +-1 px) by this share
  int lr_max_diff_px = 1;     // left-right check
  // Isolated blobs are removed as OpenCV's SGBM does (its speckle filter): up to this many
  // pixels differing from their surround by more than speckle_range_px. A mismatched patch
  // must not pose as a near obstacle. 0: off.
  int speckle_window_px = 100;
  int speckle_range_px = 2;
};

// Left disparity of a rectified 8-bit grey pair: CV_16S, disparity x 16, -16 where invalid
// (no unique minimum, failed left-right check, partner outside the right image, a speckle).
cv::Mat CensusSemiGlobalMatch(const cv::Mat& left8, const cv::Mat& right8, const CensusSgmParams& params);

}  // namespace uav::vision::detail
