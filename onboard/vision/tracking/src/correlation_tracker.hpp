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
// - Colour: Staple's (Bertinetto et al. 2016) per-pixel P(target | colour) from histograms of the
//   target and its surroundings (32 bins per BGR channel), averaged over a target-sized box at each
//   displacement and merged with the shape's response. Shape holds the box where colour is
//   ambiguous; colour holds it where a runner's changing shape is not.
// - Scale: DSST's separate one-dimensional scale filter over 33 scales 2 % apart, and a second
//   such filter over the aspect ratio at a constant area (a car turning away, a runner's stride):
//   DSST keeps the selection's aspect, which a target that turns or strides does not.
// - Occlusion, drift and loss: the peak-to-sidelobe ratio (PSR, Bolme et al.) and the colour
//   score each measure how sure a detection is against their running levels. Below a share of
//   either the filter stops learning (an occluder, the grass a drifting box slides onto, is not
//   learned as the target) and windows around the last sure position are searched; a detection
//   there as sure as the target's usual, in shape and in colour, relocks the track. Lost, the
//   whole image is searched where the target's colours are densest.
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
  // The aspect filter: ratios tried per frame (width x f, height / f), 2 % apart. An aspect ratio
  // changes a few percent a second: 17 samples (+-16 %) are plenty, and each costs a HOG sample.
  // 9 and 33 scored within the sequences' own spread (mean AUC over the four real sets 76.0,
  // 75.6 with 17, 76.0 with 33; 74.8 without the filter); 33 took twice the time of 17.
  int aspects = 17;
  double scale_learning_rate = 0.025;  // DSST's
  double scale_model_area_px = 512.0;  // the scale filter's samples are resampled to this area
  double max_aspect_change = 2.0;      // the aspect ratio stays within this factor of the selection's
  // Staple's colour model (Bertinetto et al. 2016): weight of the colour score in the merged
  // response, and its histograms' learning rate per sure frame (Staple's 0.3 and 0.04).
  double colour_weight = 0.3;
  double colour_learning_rate = 0.04;
  // A detection is sure when its PSR and its colour score are each at least this share of their
  // running levels over sure frames; one found by re-detection, away from the track, needs the
  // larger share.
  double sure_share = 0.5;
  double relock_share = 0.6;
  // Hue of the kept memory of the selection: TargetTracker sets TrackerParams' (CamShift's) bins
  // and thresholds.
  int hue_bins = 30;
  int min_saturation = 60;
  int min_value = 40;
};

struct CorrelationDetection {
  cv::Rect2d box;         // pixels
  double psr = 0.0;       // peak-to-sidelobe ratio of the translation response
  double colour = 0.0;    // mean P(target | colour) over the box, 0..1
  // 0..1: how much the box still looks like the operator's selection by the selection's own
  // colours (1 where those did not tell it from its surroundings).
  double resemblance = 1.0;
  // 0..1: the lowest of the PSR and the colour score, each against its running level over sure
  // frames, and the resemblance. Drift onto the background shows in the colour before the shape.
  double confidence = 0;
  bool sure = false;      // learned from; false while occluded or lost
  bool drifted = false;   // the selection's colours are elsewhere: the box is on the background
};

class CorrelationTracker {
 public:
  explicit CorrelationTracker(const CorrelationParams& params = {});
  // `bgr` CV_8UC3; `box` inside it with sides of at least 4 px (the caller checks).
  void Start(const cv::Mat& bgr, const cv::Rect2d& box);
  // `search_whole_image`: the target is lost; look for it wherever its colours are.
  CorrelationDetection Update(const cv::Mat& bgr, bool search_whole_image = false);

 private:
  struct Found {
    cv::Point2d centre;
    double psr = 0.0;
    double colour = 0.0;  // mean P(target | colour) over the box found
    double resemblance = 1.0;  // Resemblance() there
  };
  void Features(const cv::Mat& patch, std::vector<cv::Mat>& channels) const;
  cv::Mat Resampled(const cv::Mat& grey, cv::Point2d centre, cv::Size2d size, cv::Size out) const;
  void TranslationSpectra(const cv::Mat& grey, cv::Point2d centre, const cv::Mat& window, std::vector<cv::Mat>& spectra) const;
  // A one-dimensional size filter (DSST's scale filter): over the scales, or over the aspect
  // ratio at a constant area.
  enum class SizeAxis { kScale, kAspect };
  struct SizeFilter {
    int samples = 0;                // sizes tried per frame
    std::vector<double> factors;    // step^k, k = -(samples-1)/2 .. (samples-1)/2
    std::vector<float> window;      // Hann window over the samples
    cv::Mat label_spectrum;         // Gaussian label over the samples, transformed
    cv::Mat numerator, denominator;
    void Setup(int count, double step);
  };
  cv::Mat SizeSpectra(const cv::Mat& grey, SizeAxis axis) const;
  double EstimateSizeChange(const cv::Mat& grey, SizeAxis axis) const;
  cv::Size2d TargetSize() const;
  Found Detect(const cv::Mat& grey, const cv::Mat& bgr, cv::Point2d centre) const;
  struct ColourRegions {
    cv::Rect inner, target, outer;
  };
  ColourRegions RegionsAt(cv::Point2d centre, cv::Size image_size) const;
  cv::Mat HueBins(const cv::Mat& bgr) const;
  cv::Mat HueDensity(const cv::Mat& bgr) const;
  double MemoryDensity(const cv::Mat& bgr, const cv::Rect& area) const;
  double Resemblance(const cv::Mat& bgr, cv::Point2d centre) const;
  bool ColourTellsTarget() const;
  void Histograms(const cv::Mat& bgr, std::vector<float>& fg, std::vector<float>& bg) const;
  cv::Mat Likelihood(const cv::Mat& bgr) const;
  cv::Mat ColourResponse(const cv::Mat& bgr, cv::Point2d centre) const;
  std::vector<cv::Point2d> WholeImageCandidates(const cv::Mat& bgr) const;
  void LearnColour(const cv::Mat& bgr, double rate);
  void Learn(const cv::Mat& grey, double rate, double scale_rate);
  cv::Size2d Window() const;

  CorrelationParams p_;
  cv::Point2d centre_;       // target centre now [px]
  cv::Point2d last_sure_;    // where the target was last seen for sure
  cv::Size2d start_size_;    // the selection's size [px]
  double scale_ = 1.0;       // target size = start_size_ x scale_, its width x aspect_, height / aspect_
  double aspect_ = 1.0;
  double min_scale_ = 0.1, max_scale_ = 10.0;
  double template_ratio_ = 1.0;  // image pixels per template pixel at scale 1
  cv::Size template_, cells_;
  cv::Mat cosine_window_, learning_window_, label_spectrum_;
  std::vector<cv::Mat> numerator_;  // per channel, complex
  cv::Mat denominator_;             // real
  cv::Size scale_model_;
  SizeFilter size_filters_[2];  // by SizeAxis
  std::vector<float> foreground_, background_;  // colour histograms, normalised
  std::vector<float> target_probability_;       // per colour bin: P(target | colour)
  std::vector<float> memory_probability_;       // per hue bin: the selection's, kept (Start)
  double memory_inside_ = 0.0, memory_around_ = 0.0;  // its means over the selection, around it
  bool colour_unique_ = false;  // nothing else in view resembled the selection when it was picked
  cv::Mat grey_;
  double psr_level_ = 0.0;  // running PSR of sure frames
  double colour_level_ = 0.0;  // running colour score of sure frames
  int sure_frames_ = 0;
  int frames_unsure_ = 0;  // since the last sure frame
};

}  // namespace uav::vision::detail
