#include "correlation_tracker.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace uav::vision::detail {
namespace {

constexpr int kSignedBins = 18;              // Felzenszwalb et al.'s 18 signed orientations
constexpr int kUnsignedBins = kSignedBins / 2;
constexpr float kHogClip = 0.2f;             // as Dalal-Triggs and Felzenszwalb
constexpr int kPeakExclusionCells = 5;       // PSR: the sidelobe excludes 11 x 11 cells round the peak
constexpr int kWarmUpFrames = 5;             // frames taken as sure while the PSR level settles
constexpr float kSurroundWeight = 0.2f;      // the surroundings' weight in the learned sample
constexpr double kMinInViewShare = 0.5;
constexpr double kWholeImageTargetPx = 10.0;
constexpr int kWholeImageCandidates = 3;
constexpr double kMinMemoryContrast = 0.05;
// Drift: somewhere else resembles the selection by at least this much more than the box does.
constexpr double kDriftMargin = 0.5;
// The farthest a target moves between frames, in its mean side: a runner crossing a drone's view
// at 10 frames/s moves about 0.6 of its width a frame.
constexpr double kReachPerFrame = 1.0;
constexpr double kSureLevelRate = 0.05, kUnsureLevelRate = 0.02;

// |z|^2 of a complex (2-channel) spectrum.
cv::Mat SquaredMagnitude(const cv::Mat& z) {
  cv::Mat out(z.size(), CV_32F);
  for (int r = 0; r < z.rows; ++r) {
    const float* p = z.ptr<float>(r);
    float* o = out.ptr<float>(r);
    for (int q = 0; q < z.cols; ++q) o[q] = p[2 * q] * p[2 * q] + p[2 * q + 1] * p[2 * q + 1];
  }
  return out;
}

// DSST's scale filter terms for a d x S spectrum (one feature per row, scales along it):
// numerator = X .* conj(label) row by row, denominator = sum over rows of |X|^2 (Eq. 5).
void ScaleTerms(const cv::Mat& spectra, const cv::Mat& label, cv::Mat& numerator, cv::Mat& denominator) {
  numerator.create(spectra.size(), CV_32FC2);
  denominator = cv::Mat::zeros(1, spectra.cols, CV_32F);
  const float* g = label.ptr<float>(0);
  float* den = denominator.ptr<float>(0);
  for (int r = 0; r < spectra.rows; ++r) {
    const float* x = spectra.ptr<float>(r);
    float* n = numerator.ptr<float>(r);
    for (int q = 0; q < spectra.cols; ++q) {
      const float a = x[2 * q], b = x[2 * q + 1], c = g[2 * q], d = g[2 * q + 1];
      n[2 * q] = a * c + b * d;
      n[2 * q + 1] = b * c - a * d;
      den[q] += a * a + b * b;
    }
  }
}

// Offset of a parabola's vertex through three samples around a peak, in samples.
double ParabolaPeak(double left, double centre, double right) {
  const double curvature = left - 2 * centre + right;
  return curvature < 0 ? 0.5 * (left - right) / curvature : 0.0;
}

}  // namespace

CorrelationTracker::CorrelationTracker(const CorrelationParams& params) : p_(params) {}

// DSST's scale filter: sizes step^k, k = -(S-1)/2 .. (S-1)/2; a Gaussian label over them whose
// sigma is DSST's (sqrt(33) / 4 = 1.44 steps) whatever the count.
void CorrelationTracker::SizeFilter::Setup(int count, double step) {
  samples = count;
  factors.resize(count);
  window.resize(count);
  cv::Mat label(1, count, CV_32F);
  const double sigma = std::sqrt(33.0) * 0.25;
  for (int n = 0; n < count; ++n) {
    const double k = n - (count - 1) / 2.0;
    factors[n] = std::pow(step, k);
    window[n] = static_cast<float>(0.5 - 0.5 * std::cos(2 * CV_PI * (n + 1) / (count + 1)));
    label.at<float>(n) = static_cast<float>(std::exp(-0.5 * k * k / (sigma * sigma)));
  }
  cv::dft(label, label_spectrum, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
}

cv::Size2d CorrelationTracker::Window() const {
  const cv::Size2d target = TargetSize();
  return {target.width * (1 + p_.padding), target.height * (1 + p_.padding)};
}

void CorrelationTracker::Features(const cv::Mat& patch, std::vector<cv::Mat>& channels) const {
  cv::Mat f, gx, gy, magnitude, angle;
  patch.convertTo(f, CV_32F, 1.0 / 255);
  cv::Sobel(f, gx, CV_32F, 1, 0, 1);  // centred differences, as HOG
  cv::Sobel(f, gy, CV_32F, 0, 1, 1);
  cv::cartToPolar(gx, gy, magnitude, angle);
  const int c = p_.cell_px, cw = f.cols / c, ch = f.rows / c;
  // Each pixel's magnitude votes into its cell's two nearest signed orientations.
  std::vector<float> histogram(static_cast<size_t>(cw) * ch * kSignedBins, 0.0f);
  const float per_bin = static_cast<float>(kSignedBins / (2 * CV_PI));
  for (int y = 0; y < ch * c; ++y) {
    const float* m = magnitude.ptr<float>(y);
    const float* a = angle.ptr<float>(y);
    float* row = &histogram[static_cast<size_t>(y / c) * cw * kSignedBins];
    for (int x = 0; x < cw * c; ++x) {
      const float t = a[x] * per_bin - 0.5f;
      const int b0 = static_cast<int>(std::floor(t));
      const float w = t - b0;
      float* h = row + (x / c) * kSignedBins;
      h[(b0 + kSignedBins) % kSignedBins] += m[x] * (1 - w);
      h[(b0 + 1) % kSignedBins] += m[x] * w;
    }
  }
  // Each cell is normalised by the gradient energy of the 3 x 3 cells around it.
  cv::Mat energy(ch, cw, CV_32F), norm;
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      const float* h = &histogram[(static_cast<size_t>(y) * cw + x) * kSignedBins];
      float e = 0;
      for (int b = 0; b < kUnsignedBins; ++b) e += (h[b] + h[b + kUnsignedBins]) * (h[b] + h[b + kUnsignedBins]);
      energy.at<float>(y, x) = e;
    }
  cv::boxFilter(energy, norm, -1, cv::Size(3, 3), cv::Point(-1, -1), false, cv::BORDER_REPLICATE);
  cv::sqrt(norm + 1e-6f, norm);
  channels.resize(kSignedBins + kUnsignedBins + 1);
  for (cv::Mat& m : channels) m.create(ch, cw, CV_32F);
  for (int y = 0; y < ch; ++y)
    for (int x = 0; x < cw; ++x) {
      const float* h = &histogram[(static_cast<size_t>(y) * cw + x) * kSignedBins];
      const float k = 1.0f / norm.at<float>(y, x);
      for (int b = 0; b < kSignedBins; ++b) channels[b].at<float>(y, x) = std::min(h[b] * k, kHogClip);
      for (int b = 0; b < kUnsignedBins; ++b)
        channels[kSignedBins + b].at<float>(y, x) = std::min((h[b] + h[b + kUnsignedBins]) * k, kHogClip);
    }
  cv::Mat grey;
  cv::resize(f(cv::Rect(0, 0, cw * c, ch * c)), grey, cv::Size(cw, ch), 0, 0, cv::INTER_AREA);
  grey -= cv::mean(grey)[0];
  grey.copyTo(channels.back());
}

cv::Mat CorrelationTracker::Resampled(const cv::Mat& grey, cv::Point2d centre, cv::Size2d size, cv::Size out) const {
  const int w = std::max(1, static_cast<int>(std::lround(size.width)));
  const int h = std::max(1, static_cast<int>(std::lround(size.height)));
  const cv::Rect wanted(static_cast<int>(std::lround(centre.x - w / 2.0)), static_cast<int>(std::lround(centre.y - h / 2.0)), w, h);
  const cv::Rect inside = wanted & cv::Rect(0, 0, grey.cols, grey.rows);
  cv::Mat patch;
  if (inside.area() == 0)
    patch = cv::Mat(h, w, grey.type(), cv::mean(grey));
  else  // beyond the image edge: its last pixels repeated
    cv::copyMakeBorder(grey(inside), patch, inside.y - wanted.y, wanted.br().y - inside.br().y, inside.x - wanted.x,
                       wanted.br().x - inside.br().x, cv::BORDER_REPLICATE);
  cv::Mat resampled;
  cv::resize(patch, resampled, out, 0, 0, w > out.width ? cv::INTER_AREA : cv::INTER_LINEAR);
  return resampled;
}

void CorrelationTracker::TranslationSpectra(const cv::Mat& grey, cv::Point2d centre, const cv::Mat& window,
                                            std::vector<cv::Mat>& spectra) const {
  std::vector<cv::Mat> channels;
  Features(Resampled(grey, centre, Window(), template_), channels);
  spectra.resize(channels.size());
  for (size_t l = 0; l < channels.size(); ++l) cv::dft(channels[l].mul(window), spectra[l], cv::DFT_COMPLEX_OUTPUT);
}

// DSST's scale sample: the target at each of the scales, resampled to the scale model's size, one
// column of HOG features per scale (weighted by a Hann window over the scales), transformed along
// the scales. Along the aspect axis the width grows by each factor and the height shrinks by it.
cv::Mat CorrelationTracker::SizeSpectra(const cv::Mat& grey, SizeAxis axis) const {
  cv::Mat samples;
  std::vector<cv::Mat> channels;
  const cv::Size2d target = TargetSize();
  const SizeFilter& filter = size_filters_[static_cast<int>(axis)];
  for (int n = 0; n < filter.samples; ++n) {
    const double f = filter.factors[n], fy = axis == SizeAxis::kScale ? f : 1.0 / f;
    Features(Resampled(grey, centre_, cv::Size2d(target.width * f, target.height * fy), scale_model_), channels);
    // HOG alone, as DSST's: the mean grey of a bigger sample is more of the background's, and
    // it pulled the box of a runner on bright grass smaller frame by frame (person11: to 0.6 of
    // the selection in 240 frames, 0.73 without it).
    channels.pop_back();
    if (samples.empty()) samples.create(static_cast<int>(channels.size() * channels[0].total()), filter.samples, CV_32F);
    int row = 0;
    for (const cv::Mat& m : channels)
      for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x) samples.at<float>(row++, n) = m.at<float>(y, x) * filter.window[n];
  }
  cv::Mat spectra;
  cv::dft(samples, spectra, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
  return spectra;
}

cv::Size2d CorrelationTracker::TargetSize() const {
  return {start_size_.width * scale_ * aspect_, start_size_.height * scale_ / aspect_};
}

namespace {
constexpr int kColourShift = 3;  // Staple's 32 bins per BGR channel
constexpr int kColourBins = 1 << (3 * (8 - kColourShift));
inline int ColourBin(const uchar* p) {
  return ((p[0] >> kColourShift) << (2 * (8 - kColourShift))) | ((p[1] >> kColourShift) << (8 - kColourShift)) | (p[2] >> kColourShift);
}
}  // namespace

// Staple's regions around `centre`: the target's box shrunk by a tenth of its mean side each way
// (its pixels are the target's), the box, and the box grown by half its mean side each way (its
// pixels outside the box are the surroundings').
CorrelationTracker::ColourRegions CorrelationTracker::RegionsAt(cv::Point2d centre, cv::Size image_size) const {
  const cv::Size2d size = TargetSize();
  const double avg = 0.5 * (size.width + size.height);
  const cv::Rect image(cv::Point(), image_size);
  const auto centred = [&](double w, double h) {
    return cv::Rect(static_cast<int>(std::lround(centre.x - w / 2)), static_cast<int>(std::lround(centre.y - h / 2)),
                    static_cast<int>(std::lround(w)), static_cast<int>(std::lround(h)));
  };
  ColourRegions r;
  r.inner = centred(std::max(1.0, size.width - 0.2 * avg), std::max(1.0, size.height - 0.2 * avg)) & image;
  r.target = centred(size.width, size.height);
  r.outer = centred(size.width + avg, size.height + avg) & image;
  return r;
}

// The normalised histograms of the target's pixels and of its surroundings' (RegionsAt).
void CorrelationTracker::Histograms(const cv::Mat& bgr, std::vector<float>& fg, std::vector<float>& bg) const {
  const auto [inner, target, outer] = RegionsAt(centre_, bgr.size());
  fg.assign(kColourBins, 0.0f);
  bg.assign(kColourBins, 0.0f);
  double nf = 0, nb = 0;
  for (int y = outer.y; y < outer.br().y; ++y) {
    const uchar* row = bgr.ptr<uchar>(y);
    for (int x = outer.x; x < outer.br().x; ++x) {
      const cv::Point at(x, y);
      if (inner.contains(at)) {
        fg[ColourBin(row + 3 * x)] += 1;
        ++nf;
      } else if (!target.contains(at)) {
        bg[ColourBin(row + 3 * x)] += 1;
        ++nb;
      }
    }
  }
  if (nf > 0)
    for (float& v : fg) v /= static_cast<float>(nf);
  if (nb > 0)
    for (float& v : bg) v /= static_cast<float>(nb);
}

void CorrelationTracker::LearnColour(const cv::Mat& bgr, double rate) {
  std::vector<float> fg, bg;
  Histograms(bgr, fg, bg);
  if (foreground_.empty() || rate >= 1.0) {
    foreground_ = fg;
    background_ = bg;
  } else {
    for (int i = 0; i < kColourBins; ++i) {
      foreground_[i] = static_cast<float>((1 - rate) * foreground_[i] + rate * fg[i]);
      background_[i] = static_cast<float>((1 - rate) * background_[i] + rate * bg[i]);
    }
  }
  // Staple's per-colour P(target | colour) = rho_O / (rho_O + rho_B); 0 for colours never seen.
  target_probability_.resize(kColourBins);
  for (int i = 0; i < kColourBins; ++i) {
    const float f = foreground_[i], g = background_[i];
    target_probability_[i] = f + g > 0 ? f / (f + g) : 0.0f;
  }
}

// Staple's colour score (Bertinetto et al. 2016): each pixel's P(target | colour) from the two
// histograms, averaged over a target-sized box at each displacement; laid out as the translation
// response (zero displacement at [0, 0], wrapped), one value per cell.
cv::Mat CorrelationTracker::Likelihood(const cv::Mat& bgr) const {
  cv::Mat likelihood(bgr.size(), CV_32F);
  for (int y = 0; y < bgr.rows; ++y) {
    const uchar* p = bgr.ptr<uchar>(y);
    float* l = likelihood.ptr<float>(y);
    for (int x = 0; x < bgr.cols; ++x) l[x] = target_probability_[ColourBin(p + 3 * x)];
  }
  return likelihood;
}

cv::Mat CorrelationTracker::ColourResponse(const cv::Mat& bgr, cv::Point2d centre) const {
  const cv::Mat likelihood = Likelihood(Resampled(bgr, centre, Window(), template_));
  // The window is resampled to the template whatever its size and aspect: the target keeps its
  // size in the template.
  const cv::Size box(std::max(1, static_cast<int>(std::lround(start_size_.width / template_ratio_))),
                     std::max(1, static_cast<int>(std::lround(start_size_.height / template_ratio_))));
  cv::Mat mean_in_box, per_cell;
  cv::boxFilter(likelihood, mean_in_box, -1, box, cv::Point(-1, -1), true, cv::BORDER_CONSTANT);
  cv::resize(mean_in_box, per_cell, cells_, 0, 0, cv::INTER_AREA);
  cv::Mat wrapped(cells_, CV_32F);
  for (int r = 0; r < cells_.height; ++r)
    for (int q = 0; q < cells_.width; ++q)
      wrapped.at<float>((r - cells_.height / 2 + cells_.height) % cells_.height, (q - cells_.width / 2 + cells_.width) % cells_.width) =
          per_cell.at<float>(r, q);
  return wrapped;
}

void CorrelationTracker::Start(const cv::Mat& bgr, const cv::Rect2d& box) {
  cv::cvtColor(bgr, grey_, cv::COLOR_BGR2GRAY);
  const cv::Mat& grey = grey_;
  centre_ = last_sure_ = cv::Point2d(box.x + box.width / 2, box.y + box.height / 2);
  start_size_ = box.size();
  scale_ = aspect_ = 1.0;
  psr_level_ = colour_level_ = 0.0;
  frames_unsure_ = 0;
  sure_frames_ = 0;
  const cv::Size2d window = Window();
  template_ratio_ = std::sqrt(window.area()) / p_.template_px;
  const int c = p_.cell_px;
  template_ = cv::Size(std::max(2, static_cast<int>(std::lround(window.width / template_ratio_ / c))) * c,
                       std::max(2, static_cast<int>(std::lround(window.height / template_ratio_ / c))) * c);
  cells_ = cv::Size(template_.width / c, template_.height / c);
  cv::createHanningWindow(cosine_window_, cells_, CV_32F);
  // The filter learns the target, not its surroundings: outside the target's box the sample is
  // weighted down to kSurroundWeight (a box-shaped stand-in for CSR-DCF's spatial reliability
  // map, Lukezic et al. 2017). A static background would otherwise pull the response's peak to
  // zero displacement, behind a target crossing a hovering camera's view.
  {
    cv::Mat inside(cells_, CV_32F, cv::Scalar(kSurroundWeight));
    const cv::Size2d target_cells(box.width / template_ratio_ / c, box.height / template_ratio_ / c);
    const cv::Rect core(static_cast<int>(std::lround((cells_.width - target_cells.width) / 2)),
                        static_cast<int>(std::lround((cells_.height - target_cells.height) / 2)),
                        std::max(1, static_cast<int>(std::lround(target_cells.width))),
                        std::max(1, static_cast<int>(std::lround(target_cells.height))));
    inside(core & cv::Rect(0, 0, cells_.width, cells_.height)).setTo(1.0);
    cv::GaussianBlur(inside, inside, cv::Size(3, 3), 0);
    learning_window_ = cosine_window_.mul(inside);
  }
  // The label: a Gaussian peak at zero shift (wrapped to the corners), so the response's peak is
  // the target's displacement.
  const double sigma = p_.label_sigma * std::sqrt(box.area()) / template_ratio_ / c;
  cv::Mat label(cells_, CV_32F);
  for (int r = 0; r < cells_.height; ++r)
    for (int q = 0; q < cells_.width; ++q) {
      const int dy = r <= cells_.height / 2 ? r : r - cells_.height;
      const int dx = q <= cells_.width / 2 ? q : q - cells_.width;
      label.at<float>(r, q) = static_cast<float>(std::exp(-0.5 * (dx * dx + dy * dy) / (sigma * sigma)));
    }
  cv::dft(label, label_spectrum_, cv::DFT_COMPLEX_OUTPUT);
  size_filters_[static_cast<int>(SizeAxis::kScale)].Setup(p_.scales, p_.scale_step);
  size_filters_[static_cast<int>(SizeAxis::kAspect)].Setup(p_.aspects, p_.scale_step);
  const double shrink = std::min(1.0, std::sqrt(p_.scale_model_area_px / box.area()));
  scale_model_ = cv::Size(std::max(2 * c, static_cast<int>(box.width * shrink) / c * c),
                          std::max(2 * c, static_cast<int>(box.height * shrink) / c * c));
  min_scale_ = std::max(4.0 / box.width, 4.0 / box.height);
  max_scale_ = std::min(grey.cols / box.width, grey.rows / box.height);
  Learn(grey, 1.0, 1.0);
  LearnColour(bgr, 1.0);
  // The long-term memory: the operator's selection as it was, never learned over. Hue alone
  // (thesis 3.7's CamShift model), so that light changing is not drift: per hue bin, how much more
  // the selection holds it than its surroundings, (f - b) / (f + b) clipped at 0. Grass inside
  // and outside the box scores 0, a blue shirt 1; greys and dark pixels carry no reliable hue
  // and score 0.
  const ColourRegions regions = RegionsAt(centre_, bgr.size());
  const cv::Mat hue_of = HueBins(bgr(regions.outer));
  const cv::Point origin = regions.outer.tl();
  const int nbins = p_.hue_bins;
  std::vector<double> fg(nbins, 0.0), bg(nbins, 0.0);
  double nf = 0, nb = 0;
  for (int y = 0; y < hue_of.rows; ++y)
    for (int x = 0; x < hue_of.cols; ++x) {
      const cv::Point at = origin + cv::Point(x, y);
      const int bin = hue_of.at<short>(y, x);
      const bool inside = regions.inner.contains(at), around = !regions.target.contains(at);
      nf += inside;
      nb += around;
      if (bin < 0) continue;
      if (inside) fg[bin] += 1;
      if (around) bg[bin] += 1;
    }
  memory_probability_.assign(nbins, 0.0f);
  for (int i = 0; i < nbins; ++i) {
    const double f = nf > 0 ? fg[i] / nf : 0, g = nb > 0 ? bg[i] / nb : 0;
    memory_probability_[i] = f + g > 0 ? static_cast<float>(std::max(0.0, (f - g) / (f + g))) : 0.0f;
  }
  memory_inside_ = MemoryDensity(bgr, regions.inner);
  cv::Mat ring_density = HueDensity(bgr(regions.outer));
  cv::Mat ring_mask(ring_density.size(), CV_8U, cv::Scalar(255));
  ring_mask((regions.target - origin) & cv::Rect(cv::Point(), ring_mask.size())).setTo(0);
  memory_around_ = cv::mean(ring_density, ring_mask)[0];
  // Colour can find the target anywhere only if nothing else in view looked like it when it was
  // picked: with a look-alike about (two runners in the same shirt) it is found again only near
  // where it was lost.
  colour_unique_ = ColourTellsTarget();
  const cv::Size2d size = TargetSize();
  for (const cv::Point2d& at : WholeImageCandidates(bgr))
    if (std::abs(at.x - centre_.x) > size.width || std::abs(at.y - centre_.y) > size.height)
      colour_unique_ = colour_unique_ && Resemblance(bgr, at) < p_.relock_share;
}

// Each pixel's hue bin, -1 where saturation or value is too low for a reliable hue (CV_16S).
cv::Mat CorrelationTracker::HueBins(const cv::Mat& bgr) const {
  cv::Mat bins(bgr.size(), CV_16S);
  cv::Mat hsv;
  cv::cvtColor(bgr, hsv, cv::COLOR_BGR2HSV);
  for (int y = 0; y < hsv.rows; ++y) {
    const uchar* p = hsv.ptr<uchar>(y);
    short* b = bins.ptr<short>(y);
    for (int x = 0; x < hsv.cols; ++x)
      b[x] = p[3 * x + 1] >= p_.min_saturation && p[3 * x + 2] >= p_.min_value
                 ? static_cast<short>(std::min(p_.hue_bins - 1, p[3 * x] * p_.hue_bins / 180))
                 : static_cast<short>(-1);
  }
  return bins;
}

// Each pixel's memory score (CV_32F).
cv::Mat CorrelationTracker::HueDensity(const cv::Mat& bgr) const {
  const cv::Mat bins = HueBins(bgr);
  cv::Mat density(bins.size(), CV_32F);
  for (int y = 0; y < bins.rows; ++y) {
    const short* b = bins.ptr<short>(y);
    float* d = density.ptr<float>(y);
    for (int x = 0; x < bins.cols; ++x) d[x] = b[x] < 0 ? 0.0f : memory_probability_[b[x]];
  }
  return density;
}

double CorrelationTracker::MemoryDensity(const cv::Mat& bgr, const cv::Rect& area) const {
  const cv::Rect inside = area & cv::Rect(0, 0, bgr.cols, bgr.rows);
  return inside.area() > 0 ? cv::mean(HueDensity(bgr(inside)))[0] : 0.0;
}

bool CorrelationTracker::ColourTellsTarget() const { return memory_inside_ - memory_around_ >= kMinMemoryContrast; }

double CorrelationTracker::Resemblance(const cv::Mat& bgr, cv::Point2d centre) const {
  if (!ColourTellsTarget()) return 1.0;
  const double contrast = memory_inside_ - memory_around_;
  const double here = MemoryDensity(bgr, RegionsAt(centre, bgr.size()).inner);
  return std::clamp((here - memory_around_) / contrast, 0.0, 1.0);
}

CorrelationTracker::Found CorrelationTracker::Detect(const cv::Mat& grey, const cv::Mat& bgr, cv::Point2d centre) const {
  // Response = IDFT(sum_l conj(A_l) Z_l / (B + lambda)) (DSST Eq. 6).
  std::vector<cv::Mat> z;
  TranslationSpectra(grey, centre, cosine_window_, z);
  cv::Mat sum = cv::Mat::zeros(cells_, CV_32FC2), product;
  for (size_t l = 0; l < z.size(); ++l) {
    cv::mulSpectrums(z[l], numerator_[l], product, 0, true);
    sum += product;
  }
  for (int r = 0; r < sum.rows; ++r) {
    float* s = sum.ptr<float>(r);
    const float* d = denominator_.ptr<float>(r);
    for (int q = 0; q < sum.cols; ++q) {
      const float k = 1.0f / (d[q] + static_cast<float>(p_.regularisation));
      s[2 * q] *= k;
      s[2 * q + 1] *= k;
    }
  }
  cv::Mat shape_response;
  cv::dft(sum, shape_response, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT);
  // Staple's merge (Bertinetto et al. 2016): shape and colour vote on the displacement; the
  // PSR below is the merged response's.
  const cv::Mat colour = ColourResponse(bgr, centre);
  const cv::Mat response = (1 - p_.colour_weight) * shape_response + p_.colour_weight * colour;
  double peak;
  cv::Point at;
  cv::minMaxLoc(response, nullptr, &peak, nullptr, &at);
  const auto value = [&](int r, int q) {
    return response.at<float>((r + response.rows) % response.rows, (q + response.cols) % response.cols);
  };
  double dx = at.x + ParabolaPeak(value(at.y, at.x - 1), peak, value(at.y, at.x + 1));
  double dy = at.y + ParabolaPeak(value(at.y - 1, at.x), peak, value(at.y + 1, at.x));
  if (dx > cells_.width / 2.0) dx -= cells_.width;
  if (dy > cells_.height / 2.0) dy -= cells_.height;
  // Peak-to-sidelobe ratio (Bolme et al. 2010).
  double sum_v = 0, sum_v2 = 0;
  int n = 0;
  for (int r = 0; r < response.rows; ++r)
    for (int q = 0; q < response.cols; ++q) {
      const int ry = std::min(std::abs(r - at.y), response.rows - std::abs(r - at.y));
      const int rx = std::min(std::abs(q - at.x), response.cols - std::abs(q - at.x));
      if (rx <= kPeakExclusionCells && ry <= kPeakExclusionCells) continue;
      const double v = response.at<float>(r, q);
      sum_v += v;
      sum_v2 += v * v;
      ++n;
    }
  Found found;
  const double mean = n > 0 ? sum_v / n : 0.0;
  const double spread = n > 0 ? std::sqrt(std::max(1e-12, sum_v2 / n - mean * mean)) : 1.0;
  found.psr = (peak - mean) / spread;
  found.colour = colour.at<float>(at);
  const double px_per_cell = p_.cell_px * template_ratio_ * scale_;
  found.centre = centre + cv::Point2d(dx * px_per_cell * aspect_, dy * px_per_cell / aspect_);
  found.centre.x = std::clamp(found.centre.x, 0.0, grey.cols - 1.0);
  found.centre.y = std::clamp(found.centre.y, 0.0, grey.rows - 1.0);
  found.resemblance = Resemblance(bgr, found.centre);
  return found;
}

double CorrelationTracker::EstimateSizeChange(const cv::Mat& grey, SizeAxis axis) const {
  const SizeFilter& filter = size_filters_[static_cast<int>(axis)];
  const cv::Mat z = SizeSpectra(grey, axis);
  cv::Mat sum = cv::Mat::zeros(1, z.cols, CV_32FC2);
  float* o = sum.ptr<float>(0);
  for (int r = 0; r < z.rows; ++r) {
    const float* x = z.ptr<float>(r);
    const float* a = filter.numerator.ptr<float>(r);
    for (int q = 0; q < z.cols; ++q) {  // Z .* conj(A)
      o[2 * q] += x[2 * q] * a[2 * q] + x[2 * q + 1] * a[2 * q + 1];
      o[2 * q + 1] += x[2 * q + 1] * a[2 * q] - x[2 * q] * a[2 * q + 1];
    }
  }
  const float* d = filter.denominator.ptr<float>(0);
  for (int q = 0; q < z.cols; ++q) {
    const float k = 1.0f / (d[q] + static_cast<float>(p_.regularisation));
    o[2 * q] *= k;
    o[2 * q + 1] *= k;
  }
  cv::Mat response;
  cv::dft(sum, response, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT | cv::DFT_ROWS);
  cv::Point best;
  cv::minMaxLoc(response, nullptr, nullptr, nullptr, &best);
  // Between the sampled factors by the parabola through the peak and its neighbours: a whole
  // step (2 %) taken every frame walks the aspect ratio away, half a step each way.
  if (best.x == 0 || best.x == response.cols - 1) return filter.factors[best.x];
  const float* r = response.ptr<float>(0);
  const double k = best.x - (filter.samples - 1) / 2.0 + ParabolaPeak(r[best.x - 1], r[best.x], r[best.x + 1]);
  return std::pow(p_.scale_step, k);
}

void CorrelationTracker::Learn(const cv::Mat& grey, double rate, double scale_rate) {
  std::vector<cv::Mat> x;
  TranslationSpectra(grey, centre_, learning_window_, x);
  cv::Mat denominator = cv::Mat::zeros(cells_, CV_32F), numerator;
  numerator_.resize(x.size());
  const bool first = denominator_.empty() || rate >= 1.0;
  for (size_t l = 0; l < x.size(); ++l) {
    cv::mulSpectrums(x[l], label_spectrum_, numerator, 0, true);  // A_l = X_l conj(G)
    numerator_[l] = first ? numerator.clone() : (1 - rate) * numerator_[l] + rate * numerator;
    denominator += SquaredMagnitude(x[l]);
  }
  denominator_ = first ? denominator : (1 - rate) * denominator_ + rate * denominator;
  for (const SizeAxis axis : {SizeAxis::kScale, SizeAxis::kAspect}) {
    SizeFilter& filter = size_filters_[static_cast<int>(axis)];
    cv::Mat size_numerator, size_denominator;
    ScaleTerms(SizeSpectra(grey, axis), filter.label_spectrum, size_numerator, size_denominator);
    if (first || scale_rate >= 1.0) {
      filter.numerator = size_numerator;
      filter.denominator = size_denominator;
    } else {
      filter.numerator = (1 - scale_rate) * filter.numerator + scale_rate * size_numerator;
      filter.denominator = (1 - scale_rate) * filter.denominator + scale_rate * size_denominator;
    }
  }
}

// Where the selection's colours are densest in the whole image: up to kWholeImageCandidates
// target-sized windows, best first, at least a target's size apart. The image is shrunk so the
// target is about kWholeImageTargetPx across (a person of 40 x 80 px in 1280 x 720: 320 x 180).
std::vector<cv::Point2d> CorrelationTracker::WholeImageCandidates(const cv::Mat& bgr) const {
  const cv::Size2d target = TargetSize();
  const double shrink = std::min(1.0, kWholeImageTargetPx / std::min(target.width, target.height));
  cv::Mat small;
  cv::resize(bgr, small, cv::Size(), shrink, shrink, shrink < 1 ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::Mat likelihood = HueDensity(small), mass;
  const cv::Size box(std::max(1, static_cast<int>(std::lround(target.width * shrink))),
                     std::max(1, static_cast<int>(std::lround(target.height * shrink))));
  cv::boxFilter(likelihood, mass, -1, box, cv::Point(-1, -1), true, cv::BORDER_CONSTANT);
  std::vector<cv::Point2d> candidates;
  for (int k = 0; k < kWholeImageCandidates; ++k) {
    double best;
    cv::Point at;
    cv::minMaxLoc(mass, nullptr, &best, nullptr, &at);
    candidates.emplace_back((at.x + 0.5) / shrink, (at.y + 0.5) / shrink);
    cv::rectangle(mass, cv::Rect(at.x - box.width, at.y - box.height, 2 * box.width + 1, 2 * box.height + 1), cv::Scalar(0), cv::FILLED);
  }
  return candidates;
}

CorrelationDetection CorrelationTracker::Update(const cv::Mat& bgr, bool search_whole_image) {
  cv::cvtColor(bgr, grey_, cv::COLOR_BGR2GRAY);
  const cv::Mat& grey = grey_;
  const cv::Rect2d image(0, 0, grey.cols, grey.rows);
  const auto box_at = [&](cv::Point2d centre) {
    const cv::Size2d size = TargetSize();
    return cv::Rect2d(centre.x - size.width / 2, centre.y - size.height / 2, size.width, size.height);
  };
  // A target mostly beyond the image edge has left the view: nothing there is the target.
  const auto in_view = [&](cv::Point2d centre) {
    const cv::Rect2d box = box_at(centre);
    return (box & image).area() >= kMinInViewShare * box.area();
  };
  // Sure: the shape's PSR and the colour's score both at least `share` of their levels, and the
  // box resembling the selection at least that much.
  const auto sure_at = [&](const Found& f, double share) {
    return f.psr >= share * psr_level_ && f.colour >= share * colour_level_ && f.resemblance >= share && in_view(f.centre);
  };
  Found found = Detect(grey, bgr, centre_);
  // Where the selection's colours are densest in the whole image, looked at when the box has lost
  // them or the target is lost: each candidate detected there once.
  std::vector<Found> elsewhere;
  const auto look_elsewhere = [&] {
    if (!elsewhere.empty()) return;
    for (const cv::Point2d& at : WholeImageCandidates(bgr))
      if (image.contains(at)) elsewhere.push_back(Detect(grey, bgr, at));
  };
  // Drift shows as the selection's colours leaving the box for somewhere else. Colours that have
  // faded from the box without being any denser elsewhere (a small target's blurred shirt, light
  // changing) say nothing about the track: the resemblance is then not held against it.
  if (ColourTellsTarget() && found.resemblance < p_.sure_share) {
    look_elsewhere();
    double best = 0.0;
    for (const Found& f : elsewhere) best = std::max(best, f.resemblance);
    if (best < found.resemblance + kDriftMargin) found.resemblance = 1.0;
  }
  bool sure = sure_frames_ < kWarmUpFrames ? in_view(found.centre) : sure_at(found, p_.sure_share);
  // A detection away from the track must be as sure as the target usually is, in shape and in
  // colour: grass that happens to correlate with the filter is not the runner in a blue shirt.
  const auto try_relock = [&](const Found& candidate, bool by_colour_alone) {
    const bool by_colour = by_colour_alone && ColourTellsTarget() && candidate.resemblance >= p_.relock_share &&
                           candidate.colour >= p_.relock_share * colour_level_ && in_view(candidate.centre);
    if ((sure_at(candidate, p_.relock_share) || by_colour) && (!sure || candidate.psr > found.psr)) {
      found = candidate;
      sure = true;
    }
  };
  if (!sure) {
    // Occluded, or drifting: half a window around where it was last seen for sure, as far as the
    // target can have gone since (a walker behind a post does not reappear as a window two
    // storeys up).
    const cv::Size2d window = Window(), target = TargetSize();
    const double reach = (frames_unsure_ + 1) * kReachPerFrame * 0.5 * (target.width + target.height);
    for (const cv::Point step : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1), cv::Point(1, 1),
                                 cv::Point(-1, 1), cv::Point(1, -1), cv::Point(-1, -1)}) {
      const cv::Point2d at = last_sure_ + cv::Point2d(step.x * 0.5 * window.width, step.y * 0.5 * window.height);
      if (!image.contains(at)) continue;
      const Found candidate = Detect(grey, bgr, at);
      if (cv::norm(candidate.centre - last_sure_) <= reach) try_relock(candidate, false);
    }
  }
  // Lost: wherever in the image the selection's colours are densest (the target may have moved
  // anywhere, and turned or crouched: its shape may be one the filter has not seen). Where the
  // selection's colours told it from its surroundings, those colours, in both models, are enough.
  // Away from the track only a unique match is taken: the candidate resembling the selection by
  // kDriftMargin more than any other (one blue shirt on a field, not one of many walkers in a
  // street, nor anything where colour does not tell the target at all), and only for a target
  // that had no look-alike in view when it was picked.
  if (!sure && search_whole_image) {
    look_elsewhere();
    const Found* best = nullptr;
    double runner_up = 0.0;
    for (const Found& f : elsewhere)
      if (!best || f.resemblance > best->resemblance) {
        if (best) runner_up = best->resemblance;
        best = &f;
      } else {
        runner_up = std::max(runner_up, f.resemblance);
      }
    if (best && colour_unique_ && best->resemblance >= runner_up + kDriftMargin) try_relock(Found(*best), true);
  }
  centre_ = found.centre;
  // The PSR level follows sure frames quickly and the others slowly: a lasting change of
  // appearance (a walker setting off, the camera turning, light) lowers it within a few frames,
  // a brief occlusion hardly. The colour level follows sure frames only: clothes and paint do
  // not change, and a level that sank towards the background's would take the background.
  if (!sure && sure_frames_ >= kWarmUpFrames && in_view(found.centre))
    psr_level_ += kUnsureLevelRate * (found.psr - psr_level_);
  frames_unsure_ = sure ? 0 : frames_unsure_ + 1;
  if (sure) {
    last_sure_ = centre_;
    const auto follow = [&](double& level, double value) {
      level = sure_frames_ < kWarmUpFrames ? (level * sure_frames_ + value) / (sure_frames_ + 1)
                                           : level + kSureLevelRate * (value - level);
    };
    follow(psr_level_, found.psr);
    follow(colour_level_, found.colour);
    ++sure_frames_;
    scale_ = std::clamp(scale_ * EstimateSizeChange(grey, SizeAxis::kScale), min_scale_, max_scale_);
    // Each side stays at least 4 px (the scale's own limit) whatever the aspect.
    const double lowest = std::max(1.0 / p_.max_aspect_change, 4.0 / (start_size_.width * scale_));
    const double highest = std::max(lowest, std::min(p_.max_aspect_change, start_size_.height * scale_ / 4.0));
    aspect_ = std::clamp(aspect_ * EstimateSizeChange(grey, SizeAxis::kAspect), lowest, highest);
    Learn(grey, p_.learning_rate, p_.scale_learning_rate);
    LearnColour(bgr, p_.colour_learning_rate);
  }
  CorrelationDetection out;
  out.box = box_at(centre_);
  out.psr = found.psr;
  out.colour = found.colour;
  out.sure = sure;
  // The selection's colours left the box and are clearly denser elsewhere (the fade check above
  // let the resemblance stand): drift, not a shape the filter has not seen.
  out.drifted = !sure && ColourTellsTarget() && found.resemblance < p_.sure_share;
  const double shape_confidence = psr_level_ > 0 ? std::clamp(found.psr / psr_level_, 0.0, 1.0) : 1.0;
  const double colour_confidence = colour_level_ > 0 ? std::clamp(found.colour / colour_level_, 0.0, 1.0) : 1.0;
  out.resemblance = found.resemblance;
  out.confidence = std::min({shape_confidence, colour_confidence, found.resemblance});
  return out;
}

}  // namespace uav::vision::detail
