#pragma once
// Dense disparity of a rectified pair (thesis 3.5.1): block matching (fast, misses weakly
// textured areas), OpenCV's semi-global matching (smooths along paths and carries weak texture)
// or our own semi-global matcher on census costs (the fastest at 128 disparities), selectable,
// always with a left-right consistency check, optionally followed by the
// edge-aware weighted-least-squares filter (opencv-contrib ximgproc), and a texture mask so
// that featureless surfaces give no depth instead of matched noise (thesis 4.4).
#include <memory>
#include <string>

#include <opencv2/core/mat.hpp>

namespace uav::vision {

enum class MatcherKind { kBlockMatching, kSemiGlobal, kCensusSemiGlobal };
// "bm", "sgbm" (OpenCV's) or "census" (ours); throws std::invalid_argument naming the text otherwise.
MatcherKind ParseMatcherKind(const std::string& text);
const char* MatcherKindName(MatcherKind kind);

struct DisparityParams {
  MatcherKind matcher = MatcherKind::kSemiGlobal;
  int downscale = 2;                 // match at 1/downscale resolution (1, 2 or 4)
  int num_disparities = 64;          // [px] search range at matching resolution, multiple of 16, 16..512
  int block_size = 5;                // [px] matching window at matching resolution, odd, 5..21 (thesis 3.2.1);
                                     // census matches 9 x 7 windows and uses it for the sub-pixel step only
  int lr_max_diff_px = 1;            // left-right check: left and right disparities agree within this [px]
  bool wls_filter = false;           // edge-aware WLS filtering with a right-view confidence (bm, sgbm)
  double wls_lambda = 8000.0;        // WLS smoothness (ximgproc's default)
  double wls_sigma_color = 1.5;      // WLS edge sensitivity (ximgproc's default)
  double texture_threshold = 2.0;    // [grey levels/px] minimum mean |dI/dx| over the window; 0: off
  bool subpixel_refinement = true;   // refine each disparity on the images (no pixel locking)
  // Throws std::invalid_argument naming the bad field.
  void Validate() const;
};

// Disparity of the rectified left image at matching resolution: CV_16S, disparity x 16
// (OpenCV's fixed point), negative where invalid. Full-resolution pixel (u, v) and disparity d
// are downscale times the matching-resolution ones.
struct DisparityMap {
  cv::Mat d16;
  int downscale = 1;
  // Disparity at full resolution, x 16, 0 where invalid, CV_16U of the full image size (the
  // 16-bit PNG format of uav-stereo --disparity).
  cv::Mat FullResolution16U(const cv::Size& full) const;
  double ValidFraction() const;
  // A dense map for display and for scoring against ground truth, not for the obstacle chain
  // (a filled pixel is a guess, not a measurement). A pixel without disparity is most often
  // occluded, i.e. it shows the surface behind: it takes the smaller (farther) of the nearest
  // valid disparities to its left and right on its row (Hirschmueller's occlusion filling),
  // then a 3 x 3 median removes the streaks that row-wise filling leaves.
  DisparityMap Densified() const;
};

// A disparity map against ground truth (Middlebury's measure): over the pixels with a known
// true disparity, the share whose estimate is missing or off by more than bad_threshold_px.
struct DisparityErrors {
  long pixels = 0;               // pixels with ground truth
  double bad_fraction = 0.0;     // missing or wrong, of `pixels`
  double invalid_fraction = 0.0; // missing, of `pixels`
  double bad_valid_fraction = 0.0;  // off by more than bad_threshold_px, of the pixels given a value
  double mean_abs_error_px = 0.0;  // over the valid estimates
};
// estimate_x16: CV_16U or CV_16S, disparity x 16, <= 0 invalid; truth_px: CV_32F, 0 unknown.
// Throws std::invalid_argument when the sizes differ.
DisparityErrors CompareDisparity(const cv::Mat& estimate_x16, const cv::Mat& truth_px, double bad_threshold_px = 1.0);

class DisparityMatcher {
 public:
  // Throws std::invalid_argument naming the bad field.
  explicit DisparityMatcher(const DisparityParams& params);
  ~DisparityMatcher();
  DisparityMatcher(DisparityMatcher&&) noexcept;

  // A rectified pair, 8-bit BGR or grey, equal sizes divisible by downscale. Throws
  // std::invalid_argument naming what is wrong with the images.
  DisparityMap Compute(const cv::Mat& left_rect, const cv::Mat& right_rect) const;
  const DisparityParams& params() const;
  // Nearest depth the search range covers at full-resolution focal length f [px], baseline b [m].
  double MinDepth(double f_px, double baseline_m) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
