// CamShift (thesis 3.7, Bradski's Continuously Adaptive Mean Shift) with OpenCV's mean shift for
// the window's location and the thesis's closed-form moments (Eq. 3.41-3.53) for the box; a
// correlation filter on gradients (correlation_tracker.hpp) for targets without a distinct colour.
#include "uav/vision/target_tracker.hpp"

#include "correlation_tracker.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <opencv2/tracking.hpp>
#include <opencv2/video/tracking.hpp>

namespace uav::vision {
namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("tracker: " + what);
}

// Side of a uniformly filled box whose mass has standard deviation sigma along that side:
// a uniform distribution over L has variance L^2 / 12.
constexpr double kSideOverSigma = 3.4641016151377544;  // sqrt(12)

// The search window reaches this fraction of the box's size beyond it on each side, so the
// next frame's motion stays inside it (thesis 3.7.1, step 3: "slightly larger").
constexpr double kWindowMargin = 0.25;

// Back-projection values below this (of 255) are set to zero: colours the histogram gives little
// weight (the surroundings' hues left after background weighting, sensor noise) would otherwise
// add up over a large window and let the moments' box grow into the background.
constexpr double kMinProbability = 32.0;

struct Moments {
  double m00 = 0.0;
  cv::RotatedRect box;
};

// Eq. 3.41-3.53 over `window` of the probability image: centroid, orientation and the two
// axes. The orientation is half of atan2(b, a - c) (Eq. 3.48 as printed misplaces a bracket).
Moments WindowMoments(const cv::Mat& probability, const cv::Rect& window) {
  Moments out;
  const cv::Moments m = cv::moments(probability(window), false);
  out.m00 = m.m00;
  if (m.m00 <= 0) return out;
  const double xc = m.m10 / m.m00, yc = m.m01 / m.m00;               // Eq. 3.44-3.45
  const double a = m.m20 / m.m00 - xc * xc;                          // Eq. 3.51
  const double b = 2.0 * (m.m11 / m.m00 - xc * yc);
  const double c = m.m02 / m.m00 - yc * yc;
  const double root = std::sqrt(b * b + (a - c) * (a - c));
  const double l = std::sqrt(std::max(0.0, 0.5 * ((a + c) + root)));  // Eq. 3.52
  const double w = std::sqrt(std::max(0.0, 0.5 * ((a + c) - root)));  // Eq. 3.53
  const double theta = 0.5 * std::atan2(b, a - c);                   // Eq. 3.48
  out.box = cv::RotatedRect(cv::Point2f(static_cast<float>(window.x + xc), static_cast<float>(window.y + yc)),
                            cv::Size2f(static_cast<float>(kSideOverSigma * l), static_cast<float>(kSideOverSigma * w)),
                            static_cast<float>(theta * 180.0 / M_PI));
  return out;
}

cv::Rect Clip(const cv::Rect& r, const cv::Size& size) { return r & cv::Rect(0, 0, size.width, size.height); }

cv::Rect Centred(cv::Point2f centre, cv::Size2f size) {
  return cv::Rect(static_cast<int>(std::lround(centre.x - 0.5f * size.width)),
                  static_cast<int>(std::lround(centre.y - 0.5f * size.height)),
                  std::max(1, static_cast<int>(std::lround(size.width))), std::max(1, static_cast<int>(std::lround(size.height))));
}

}  // namespace

TrackerKind ParseTrackerKind(const std::string& name) {
  if (name == "camshift") return TrackerKind::kCamShift;
  if (name == "kcf") return TrackerKind::kKcf;
  if (name == "csrt") return TrackerKind::kCsrt;
  if (name == "auto") return TrackerKind::kAuto;
  if (name == "dcf") return TrackerKind::kCorrelation;
  throw std::invalid_argument("unknown tracker '" + name + "' (auto, camshift, dcf, kcf, csrt)");
}
SearchWindowMode ParseSearchWindowMode(const std::string& name) {
  if (name == "adaptive") return SearchWindowMode::kAdaptive;
  if (name == "static") return SearchWindowMode::kStatic;
  throw std::invalid_argument("unknown search window '" + name + "' (adaptive, static)");
}
const char* Name(TrackerKind kind) {
  switch (kind) {
    case TrackerKind::kCamShift: return "camshift";
    case TrackerKind::kKcf: return "kcf";
    case TrackerKind::kCsrt: return "csrt";
    case TrackerKind::kAuto: return "auto";
    case TrackerKind::kCorrelation: return "dcf";
  }
  return "?";
}
const char* Name(SearchWindowMode mode) { return mode == SearchWindowMode::kAdaptive ? "adaptive" : "static"; }

void TrackerParams::Validate() const {
  Require(hue_bins >= 4 && hue_bins <= 180, "hue_bins must be 4..180");
  Require(min_saturation >= 0 && min_saturation <= 255, "min_saturation must be 0..255");
  Require(min_value >= 0 && min_value <= max_value && max_value <= 255, "need 0 <= min_value <= max_value <= 255");
  Require(max_iterations >= 1 && max_iterations <= 100, "max_iterations must be 1..100");
  Require(std::isfinite(epsilon_px) && epsilon_px > 0, "epsilon_px must be positive");
  Require(std::isfinite(lost_confidence) && lost_confidence >= 0 && lost_confidence < 1, "lost_confidence must be in [0, 1)");
  Require(std::isfinite(lost_after_s) && lost_after_s >= 0, "lost_after_s must be finite and >= 0");
  Require(std::isfinite(reacquire_confidence) && reacquire_confidence >= lost_confidence && reacquire_confidence <= 1,
          "reacquire_confidence must be in [lost_confidence, 1]");
  Require(std::isfinite(min_side_px) && min_side_px >= 1, "min_side_px must be at least 1");
  Require(std::isfinite(auto_min_colour_coverage) && auto_min_colour_coverage >= 0 && auto_min_colour_coverage <= 1,
          "auto_min_colour_coverage must be in [0, 1]");
}

struct TargetTracker::Impl {
  TrackerParams p;
  TrackState state = TrackState::kIdle;
  TrackerKind method = TrackerKind::kCamShift;  // what tracks now (kAuto's choice)
  std::string method_reason;
  cv::Size image_size;
  // CamShift.
  cv::Mat histogram;
  double reference_density = 0.0;  // mean probability over the selection
  cv::Size2f reference_size;       // the selection's size: the whole-image search's window
  cv::Rect window;
  double confident_at_s = 0.0;  // the last frame at or above lost_confidence
  double now_s = 0.0;
  cv::Mat hsv, mask, probability;
  // KCF / CSRT.
  cv::Ptr<cv::Tracker> opencv;
  // The correlation filter, on grey.
  std::unique_ptr<detail::CorrelationTracker> correlation;
  bool drifted = false;  // the correlation filter's last frame: the box on the background
  std::string lost_reason;
  double colour_coverage = 0.0;  // share of the selection CamShift's probability image covers

  // CamShift's model of the target (thesis 3.7): the background-weighted hue histogram, the
  // reference density and the first window. "" on success, else why it cannot track.
  std::string TrainCamShift(const cv::Mat& bgr, const cv::Rect& roi, const std::vector<cv::Point2f>& polygon) {
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
    cv::inRange(hsv, cv::Scalar(0, p.min_saturation, p.min_value), cv::Scalar(180, 255, p.max_value), mask);
    cv::Mat selection = cv::Mat::zeros(bgr.size(), CV_8U);
    selection(roi).setTo(255);
    if (polygon.size() >= 3) {
      std::vector<cv::Point> corners;
      for (const cv::Point2f& q : polygon) corners.emplace_back(static_cast<int>(std::lround(q.x)), static_cast<int>(std::lround(q.y)));
      cv::Mat clicked = cv::Mat::zeros(bgr.size(), CV_8U);
      cv::fillConvexPoly(clicked, corners, cv::Scalar(255));
      selection &= clicked;
    }
    cv::Mat train = mask & selection;
    const int usable = cv::countNonZero(train);
    if (usable < std::max(16.0, 0.1 * roi.area()))
      return "the target has too little colour to track (" + std::to_string(usable) + " of " +
             std::to_string(roi.area()) + " pixels saturated and bright enough)";
    const int channels[] = {0};
    const int bins[] = {p.hue_bins};
    const float hue_range[] = {0, 180};
    const float* ranges[] = {hue_range};
    cv::calcHist(&hsv, 1, channels, train, histogram, 1, bins, ranges);
    // Background-weighted histogram (Comaniciu, Ramesh and Meer 2003): hues common in a ring
    // around the selection (the box's corners hold some of them too) are scaled down by
    // min(1, h_min / h_background), so the probability image does not pull the window into the
    // surroundings.
    cv::Mat ring = cv::Mat::zeros(bgr.size(), CV_8U);
    const cv::Rect around = Clip(cv::Rect(roi.x - roi.width, roi.y - roi.height, 3 * roi.width, 3 * roi.height), image_size);
    ring(around).setTo(255);
    ring(roi).setTo(0);
    ring &= mask;
    if (cv::countNonZero(ring) > 0) {
      cv::Mat background;
      cv::calcHist(&hsv, 1, channels, ring, background, 1, bins, ranges);
      float smallest = std::numeric_limits<float>::infinity();
      for (int b = 0; b < p.hue_bins; ++b)
        if (background.at<float>(b) > 0) smallest = std::min(smallest, background.at<float>(b));
      for (int b = 0; b < p.hue_bins; ++b)
        if (background.at<float>(b) > 0) histogram.at<float>(b) *= std::min(1.0f, smallest / background.at<float>(b));
    }
    if (!(cv::norm(histogram, cv::NORM_INF) > 0)) return "the target's colours are those of its surroundings";
    cv::normalize(histogram, histogram, 0, 255, cv::NORM_MINMAX);
    Probability(bgr);
    // The target inside the selection: the moments' box there (a loose selection shrinks to the
    // coloured object), and its density, which later frames' confidence is measured against.
    const Moments m = WindowMoments(probability, roi);
    const double area = static_cast<double>(m.box.size.width) * m.box.size.height;
    if (!(m.m00 > 0 && area >= 1.0)) return "the selection holds none of the colours that tell the target from its surroundings";
    reference_density = m.m00 / area;
    const cv::Rect target = Clip(m.box.boundingRect(), image_size);
    reference_size = cv::Size2f(static_cast<float>(std::max(target.width, 1)), static_cast<float>(std::max(target.height, 1)));
    window = Clip(Centred(m.box.center, cv::Size2f(target.width * (1 + 2 * kWindowMargin), target.height * (1 + 2 * kWindowMargin))),
                    image_size);
    // kAuto's test: the share of the selection whose hue, after the background weighting, still
    // says "target". A ball or a painted car fills most of its box; a runner whose only
    // distinct colour is a shirt, or jeans among blue signs, fills little of it.
    colour_coverage = static_cast<double>(cv::countNonZero(probability(roi))) / roi.area();
    return "";
  }

  void Probability(const cv::Mat& bgr) {
    cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
    cv::inRange(hsv, cv::Scalar(0, p.min_saturation, p.min_value), cv::Scalar(180, 255, p.max_value), mask);
    const int channels[] = {0};
    const float hue_range[] = {0, 180};
    const float* ranges[] = {hue_range};
    cv::calcBackProject(&hsv, 1, channels, histogram, probability, ranges);
    probability &= mask;
    cv::threshold(probability, probability, kMinProbability - 1, 0, cv::THRESH_TOZERO);
  }

  // Mean shift from `start`, then the moments where it settled; the confidence is the density
  // inside the moment box against the selection's.
  TrackResult ShiftFrom(cv::Rect start) {
    TrackResult r;
    start = Clip(start, image_size);
    if (start.area() == 0) return r;
    cv::meanShift(probability, start, cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, p.max_iterations, p.epsilon_px));
    const Moments m = WindowMoments(probability, start);
    r.box = m.box;
    const double area = static_cast<double>(m.box.size.width) * m.box.size.height;
    if (m.m00 > 0 && area >= 1.0) r.confidence = std::min(1.0, m.m00 / area / reference_density);
    // Next window (adaptive): the box's bounds with a margin; static: the selection's size.
    const cv::Rect bounds = m.m00 > 0 ? m.box.boundingRect() : start;
    const cv::Size2f size = p.window == SearchWindowMode::kAdaptive
                                ? cv::Size2f(bounds.width * (1 + 2 * kWindowMargin), bounds.height * (1 + 2 * kWindowMargin))
                                : reference_size;
    r.search_window = Clip(Centred(m.m00 > 0 ? m.box.center : (cv::Point2f(start.tl()) + cv::Point2f(start.br())) * 0.5f, size), image_size);
    if (r.search_window.area() == 0) r.search_window = start;
    if (m.box.size.width < p.min_side_px || m.box.size.height < p.min_side_px) r.confidence = 0.0;
    return r;
  }

  // Whole-image search: the window of the selection's size holding the most probability mass.
  TrackResult SearchEverywhere() {
    cv::Mat mass;
    const cv::Size k(std::max(1, static_cast<int>(reference_size.width)), std::max(1, static_cast<int>(reference_size.height)));
    cv::boxFilter(probability, mass, CV_32F, k);
    cv::Point best;
    cv::minMaxLoc(mass, nullptr, nullptr, nullptr, &best);
    return ShiftFrom(Centred(cv::Point2f(best), reference_size));
  }

  // The confidence has been low for lost_after_s (the last confident frame that long ago; the
  // small tolerance takes 3 frames at 10 Hz as 0.3 s whatever the rounding of their times).
  bool LowForLong() const { return now_s - confident_at_s >= p.lost_after_s - 1e-6; }

  TrackResult UpdateCamShift(const cv::Mat& bgr) {
    Probability(bgr);
    TrackResult r = ShiftFrom(window);
    if (r.confidence < p.lost_confidence || state == TrackState::kLost) {
      TrackResult found = SearchEverywhere();
      if (found.confidence >= p.reacquire_confidence && found.confidence > r.confidence) r = found;
    }
    if (r.confidence >= (state == TrackState::kLost ? p.reacquire_confidence : p.lost_confidence)) {
      confident_at_s = now_s;
      state = TrackState::kTracking;
      window = r.search_window;
    } else if (LowForLong()) {
      state = TrackState::kLost;  // keep the last window; the whole image is searched each frame
    }
    r.state = state;
    if (state == TrackState::kLost) r.search_window = cv::Rect(0, 0, image_size.width, image_size.height);
    return r;
  }

  // As CamShift's: confidence (the PSR against its level) under lost_confidence for
  // lost_after_s loses the target (occluded, out of view). Between that and a sure detection
  // the filter follows without learning (a changed gait, a partial occlusion). Lost, it
  // searches around where it was last seen until sure again.
  TrackResult UpdateCorrelation(const cv::Mat& bgr) {
    const detail::CorrelationDetection d = correlation->Update(bgr, state == TrackState::kLost);
    drifted = d.drifted;
    if (d.sure) {
      confident_at_s = now_s;
      state = TrackState::kTracking;
    } else if (d.confidence >= p.lost_confidence && state == TrackState::kTracking) {
      confident_at_s = now_s;
    } else if (LowForLong()) {
      state = TrackState::kLost;
    }
    TrackResult r;
    r.state = state;
    r.confidence = d.confidence;
    r.box = cv::RotatedRect(cv::Point2f(static_cast<float>(d.box.x + 0.5 * d.box.width), static_cast<float>(d.box.y + 0.5 * d.box.height)),
                            cv::Size2f(static_cast<float>(d.box.width), static_cast<float>(d.box.height)), 0.0f);
    r.search_window = Clip(Centred(r.box.center, cv::Size2f(r.box.size.width * 2.5f, r.box.size.height * 2.5f)), image_size);
    return r;
  }

  TrackResult UpdateOpenCv(const cv::Mat& bgr) {
    TrackResult r;
    cv::Rect box;
    const bool ok = opencv->update(bgr, box);
    state = ok ? TrackState::kTracking : TrackState::kLost;
    r.state = state;
    r.confidence = ok ? 1.0 : 0.0;
    r.box = cv::RotatedRect(cv::Point2f(box.x + 0.5f * box.width, box.y + 0.5f * box.height),
                            cv::Size2f(static_cast<float>(box.width), static_cast<float>(box.height)), 0.0f);
    r.search_window = box;
    return r;
  }
};

TargetTracker::TargetTracker(const TrackerParams& params) : impl_(std::make_unique<Impl>()) {
  params.Validate();
  impl_->p = params;
}
TargetTracker::~TargetTracker() = default;
TargetTracker::TargetTracker(TargetTracker&&) noexcept = default;
TargetTracker& TargetTracker::operator=(TargetTracker&&) noexcept = default;

void TargetTracker::Start(const cv::Mat& bgr, double t_s, const cv::Rect2d& box, const std::vector<cv::Point2f>& polygon) {
  Impl& s = *impl_;
  Require(!bgr.empty(), "the image is empty");
  Require(bgr.type() == CV_8UC3, "the image must be 8-bit BGR");
  Require(std::isfinite(t_s), "the frame time is not finite");
  Require(std::isfinite(box.x) && std::isfinite(box.y) && std::isfinite(box.width) && std::isfinite(box.height),
          "the box is not finite");
  Require(box.width >= s.p.min_side_px && box.height >= s.p.min_side_px,
          "the box is " + std::to_string(box.width) + " x " + std::to_string(box.height) + " px, smaller than " +
              std::to_string(s.p.min_side_px) + " px a side");
  const cv::Rect2d image(0, 0, bgr.cols, bgr.rows);
  const cv::Rect2d inside = box & image;
  Require(inside.area() >= 0.5 * box.area(), "the box lies outside the " + std::to_string(bgr.cols) + " x " +
                                                 std::to_string(bgr.rows) + " image");
  for (const cv::Point2f& q : polygon) Require(std::isfinite(q.x) && std::isfinite(q.y), "a polygon corner is not finite");
  const cv::Rect roi(cv::Point(static_cast<int>(std::floor(inside.x)), static_cast<int>(std::floor(inside.y))),
                     cv::Point(static_cast<int>(std::ceil(inside.x + inside.width)), static_cast<int>(std::ceil(inside.y + inside.height))));
  s.image_size = bgr.size();
  s.confident_at_s = s.now_s = t_s;
  s.method_reason.clear();
  s.method = s.p.kind;
  if (s.p.kind == TrackerKind::kCamShift) {
    const std::string refused = s.TrainCamShift(bgr, roi, polygon);
    Require(refused.empty(), refused);
  } else if (s.p.kind == TrackerKind::kAuto) {
    // CamShift where the selection's colour stands out, the correlation filter where it does not.
    std::string refused = s.TrainCamShift(bgr, roi, polygon);
    if (refused.empty() && s.colour_coverage < s.p.auto_min_colour_coverage) {
      char why[160];
      std::snprintf(why, sizeof why, "its distinct colour covers %.0f %% of the box (CamShift needs %.0f %%)",
                    100 * s.colour_coverage, 100 * s.p.auto_min_colour_coverage);
      refused = why;
    }
    s.method = refused.empty() ? TrackerKind::kCamShift : TrackerKind::kCorrelation;
    if (refused.empty()) {
      char why[120];
      std::snprintf(why, sizeof why, "the target's colour stands out (it covers %.0f %% of the box)", 100 * s.colour_coverage);
      s.method_reason = why;
    } else {
      s.method_reason = refused;
    }
  }
  s.correlation.reset();
  s.drifted = false;
  s.lost_reason.clear();
  s.opencv.release();
  if (s.method == TrackerKind::kCorrelation) {
    detail::CorrelationParams cp;  // the selection's kept hue memory uses CamShift's hue model
    cp.hue_bins = s.p.hue_bins;
    cp.min_saturation = s.p.min_saturation;
    cp.min_value = s.p.min_value;
    s.correlation = std::make_unique<detail::CorrelationTracker>(cp);
    s.correlation->Start(bgr, cv::Rect2d(roi));
  } else if (s.method != TrackerKind::kCamShift) {
    if (s.method == TrackerKind::kKcf)
      s.opencv = cv::TrackerKCF::create();
    else
      s.opencv = cv::TrackerCSRT::create();
    s.opencv->init(bgr, roi);
  }
  s.state = TrackState::kTracking;
}

TrackResult TargetTracker::Update(const cv::Mat& bgr, double t_s) {
  Impl& s = *impl_;
  if (s.state == TrackState::kIdle) return TrackResult{};
  Require(std::isfinite(t_s) && t_s >= s.now_s, "the frame time is not finite or goes back in time");
  s.now_s = t_s;
  Require(!bgr.empty() && bgr.type() == CV_8UC3, "the image must be non-empty 8-bit BGR");
  Require(bgr.size() == s.image_size, "the image is " + std::to_string(bgr.cols) + " x " + std::to_string(bgr.rows) +
                                          ", the target was picked in " + std::to_string(s.image_size.width) + " x " +
                                          std::to_string(s.image_size.height));
  TrackResult r;
  switch (s.method) {
    case TrackerKind::kCamShift: r = s.UpdateCamShift(bgr); break;
    case TrackerKind::kCorrelation: r = s.UpdateCorrelation(bgr); break;
    default: r = s.UpdateOpenCv(bgr); break;
  }
  if (r.state != TrackState::kLost) {
    s.lost_reason.clear();
  } else if (s.lost_reason.empty()) {  // why it was lost, as it was when it was lost
    s.lost_reason = s.method == TrackerKind::kCamShift ? "the target's colour is not in view"
                    : s.drifted                        ? "the target's colours left the box for elsewhere (drift, or a look-alike)"
                    : s.method == TrackerKind::kCorrelation ? "the target is hidden or out of view"
                                                            : "OpenCV's tracker lost it";
  }
  r.lost_reason = s.lost_reason;
  return r;
}

void TargetTracker::Stop() {
  impl_->state = TrackState::kIdle;
  impl_->opencv.release();
  impl_->correlation.reset();
}
TrackState TargetTracker::state() const { return impl_->state; }
TrackerKind TargetTracker::method() const { return impl_->method; }
const std::string& TargetTracker::method_reason() const { return impl_->method_reason; }
const TrackerParams& TargetTracker::params() const { return impl_->p; }

}  // namespace uav::vision
