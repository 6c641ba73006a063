#pragma once
// Tracking the operator's target in a camera's images (thesis 3.7). CamShift on a hue histogram
// of the selected box (Eq. 3.41-3.53), with a confidence from the back-projection mass, loss
// detection and re-acquisition by a whole-image search, for targets with a colour of their own;
// a correlation filter on gradient shape (HOG cells, DSST's scale filter, re-detection after
// occlusion) for targets without one; OpenCV's KCF and CSRT (opencv-contrib) selectable for
// comparison. Plain class: frames in, boxes out, no threads or messages.
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

namespace cv {
class Mat;
}

namespace uav::vision {

// kAuto: CamShift where the selection's colour stands out from its surroundings (fastest, thesis
// 3.7), the correlation filter (kCorrelation, "dcf") where it does not (grey cars, people in dark
// clothes, buildings): never a refusal for a box of reasonable size. The method chosen is
// reported (TargetTracker::method()). The values are trk_tracker's.
enum class TrackerKind { kCamShift, kKcf, kCsrt, kAuto, kCorrelation };
// CamShift's search window: adaptive follows the target's size and orientation from its moments
// (thesis 3.7.1); static keeps the selection's size and only moves (thesis 3.7.3 compares both).
enum class SearchWindowMode { kAdaptive, kStatic };

// Names as on the command line and in parameters; Parse* throw std::invalid_argument naming
// the accepted values.
TrackerKind ParseTrackerKind(const std::string& name);
SearchWindowMode ParseSearchWindowMode(const std::string& name);
const char* Name(TrackerKind kind);
const char* Name(SearchWindowMode mode);

struct TrackerParams {
  TrackerKind kind = TrackerKind::kAuto;
  SearchWindowMode window = SearchWindowMode::kAdaptive;
  int hue_bins = 30;              // histogram bins over OpenCV's hue range 0..180
  int min_saturation = 60;        // pixels greyer than this carry no reliable hue: masked out
  int min_value = 40;             // nor do pixels darker than this
  int max_value = 255;
  int max_iterations = 10;        // mean-shift iterations per frame
  double epsilon_px = 0.5;        // stop when the window moves less than this
  double lost_confidence = 0.3;   // below this the frame counts towards losing the target
  // [s] how long the confidence may stay under lost_confidence before the state is LOST: a
  // time, not a frame count, so the rule is the same for the 10 Hz gimbal camera (3 frames, as
  // the thesis's simulator) and a 30 frames/s video (a runner's 0.2 s dip behind a pole is not
  // a loss there either).
  double lost_after_s = 0.3;
  double reacquire_confidence = 0.5;  // a whole-image candidate must reach this to lock again
  double min_side_px = 4.0;       // a selection or box smaller than this each way is rejected/lost
  // kAuto takes CamShift when at least this share of the selection keeps a hue that tells the
  // target from its surroundings (CamShift's probability image after background weighting);
  // below it, the colour does not hold the target and the correlation filter tracks.
  double auto_min_colour_coverage = 0.5;
  // Throws std::invalid_argument naming the first value out of range.
  void Validate() const;
};

enum class TrackState { kIdle, kTracking, kLost };

struct TrackResult {
  TrackState state = TrackState::kIdle;
  // The target: rotated box in pixels (centre, size, angle in degrees clockwise from the image's
  // x axis, as cv::RotatedRect); the search window the next frame starts from.
  cv::RotatedRect box;
  cv::Rect search_window;
  // 0..1. CamShift: back-projection density in the box against the selection's; the correlation
  // filter: the lowest of its shape's and colour's scores against their running levels and the
  // box's resemblance to the selection; KCF, CSRT: 1 or 0.
  double confidence = 0.0;
  // Lost: why, in words for the operator ("" while tracking).
  std::string lost_reason;
};

class TargetTracker {
 public:
  explicit TargetTracker(const TrackerParams& params);
  ~TargetTracker();
  TargetTracker(TargetTracker&&) noexcept;
  TargetTracker& operator=(TargetTracker&&) noexcept;

  // Learns the target from `box` (pixels) in `bgr` (CV_8UC3). With `polygon` (the operator's
  // four clicks, thesis 3.7.3) only pixels inside it train the histogram. Throws
  // std::invalid_argument naming what is wrong: an empty or non-BGR image, a non-finite box, one
  // outside the image or smaller than min_side_px, a target with no usable hue (grey or dark).
  // `t_s` is the frame's time in seconds (any origin, finite, never decreasing).
  void Start(const cv::Mat& bgr, double t_s, const cv::Rect2d& box, const std::vector<cv::Point2f>& polygon = {});
  // Tracks into the next frame (same size as the first) taken at `t_s`. Idle until started.
  TrackResult Update(const cv::Mat& bgr, double t_s);
  void Stop();
  TrackState state() const;
  // The method tracking now (kAuto's choice), and why it was chosen ("" when it was asked for).
  TrackerKind method() const;
  const std::string& method_reason() const;
  const TrackerParams& params() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
