#pragma once
// A discriminative correlation-filter tracker on gradient shape, for targets whose colour does not
// tell them from their surroundings (grey cars, people in dark clothes, buildings): CamShift's hue
// histogram (thesis 3.7) cannot hold those. Internal to uav_onboard_tracking; TargetTracker is the
// public face.
//
// The method, from the literature it follows:
// - Translation: a multi-channel linear correlation filter learned in the Fourier domain (MOSSE,
//   Bolme et al. 2010; its multi-channel form in DSST, Danelljan et al. 2014, Eq. 4-6) on a window
//   (1 + padding) times the target, resampled to a fixed template size.
// - Features: HOG cells in Felzenszwalb et al.'s layout (2010: 18 signed and 9 unsigned orientation
//   bins per 4 x 4 cell, normalised by the surrounding cells' gradient energy, clipped at 0.2) plus
//   the cell's mean grey. Gradients make the filter indifferent to colour and to lighting.
// - Scale: DSST's separate one-dimensional scale filter over 33 scales 2 % apart.
// - Occlusion and loss: the peak-to-sidelobe ratio (PSR, Bolme et al.) measures how sure each
//   detection is. Below a share of its running level the filter stops learning (an occluder is not
//   learned as the target) and windows around the last sure position are searched; a detection
//   there as sure as the target's usual relocks the track.
#include <vector>

#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

namespace uav::vision::detail {

struct CorrelationParams {
  double padding = 1.5;           // search window = target x (1 + padding) each way (KCF's 1.5)
  double template_px = 96.0;      // the window is resampled to about this many pixels square
  int cell_px = 4;                // HOG cell side
  double label_sigma = 0.1;       // Gaussian label's sigma over the target's size (KCF's 0.1)
  double regularisation = 1e-2;   // lambda in the filter's denominator
  double learning_rate = 0.01;    // model update per sure frame (Staple's 0.01)
  int scales = 33;                // DSST's scale filter: scales tried per frame
  double scale_step = 1.02;       // ratio between neighbouring scales
  double scale_learning_rate = 0.025;  // DSST's
  double scale_model_area_px = 512.0;  // the scale filter's samples are resampled to this area
  // A detection is sure when its PSR is at least this share of the running PSR of sure frames;
  // one found by re-detection, away from the track, needs the larger share.
  double sure_psr_share = 0.5;
  double relock_psr_share = 0.6;
};

struct CorrelationDetection {
  cv::Rect2d box;         // pixels
  double psr = 0.0;       // peak-to-sidelobe ratio of the translation response
  double confidence = 0;  // psr against the running level of sure frames, 0..1
  bool sure = false;      // learned from; false while occluded or lost
};

class CorrelationTracker {
 public:
  explicit CorrelationTracker(const CorrelationParams& params = {});
  // `grey` CV_8UC1; `box` inside it with sides of at least 4 px (the caller checks).
  void Start(const cv::Mat& grey, const cv::Rect2d& box);
  CorrelationDetection Update(const cv::Mat& grey);

 private:
  struct Found {
    cv::Point2d centre;
    double psr = 0.0;
  };
  void Features(const cv::Mat& patch, std::vector<cv::Mat>& channels) const;
  cv::Mat Resampled(const cv::Mat& grey, cv::Point2d centre, cv::Size2d size, cv::Size out) const;
  void TranslationSpectra(const cv::Mat& grey, cv::Point2d centre, const cv::Mat& window, std::vector<cv::Mat>& spectra) const;
  cv::Mat ScaleSpectra(const cv::Mat& grey) const;
  Found Detect(const cv::Mat& grey, cv::Point2d centre) const;
  double EstimateScaleChange(const cv::Mat& grey) const;
  void Learn(const cv::Mat& grey, double rate, double scale_rate);
  cv::Size2d Window() const;

  CorrelationParams p_;
  cv::Point2d centre_;       // target centre now [px]
  cv::Point2d last_sure_;    // where the target was last seen for sure
  cv::Size2d start_size_;    // the selection's size [px]
  double scale_ = 1.0;       // target size = start_size_ x scale_
  double min_scale_ = 0.1, max_scale_ = 10.0;
  double template_ratio_ = 1.0;  // image pixels per template pixel at scale 1
  cv::Size template_, cells_;
  cv::Mat cosine_window_, learning_window_, label_spectrum_;
  std::vector<cv::Mat> numerator_;  // per channel, complex
  cv::Mat denominator_;             // real
  cv::Size scale_model_;
  std::vector<double> scale_factors_;
  std::vector<float> scale_window_;
  cv::Mat scale_label_spectrum_, scale_numerator_, scale_denominator_;
  double psr_level_ = 0.0;  // running PSR of sure frames
  int sure_frames_ = 0;
};

}  // namespace uav::vision::detail
