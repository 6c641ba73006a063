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
constexpr int kRedetectReach = 1;
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

cv::Size2d CorrelationTracker::Window() const {
  return {start_size_.width * (1 + p_.padding) * scale_, start_size_.height * (1 + p_.padding) * scale_};
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
    patch = cv::Mat(h, w, CV_8U, cv::Scalar(cv::mean(grey)[0]));
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
// column of features per scale (weighted by a Hann window over the scales), transformed along
// the scales.
cv::Mat CorrelationTracker::ScaleSpectra(const cv::Mat& grey) const {
  cv::Mat samples;
  std::vector<cv::Mat> channels;
  for (int n = 0; n < p_.scales; ++n) {
    const double s = scale_ * scale_factors_[n];
    Features(Resampled(grey, centre_, cv::Size2d(start_size_.width * s, start_size_.height * s), scale_model_), channels);
    if (samples.empty()) samples.create(static_cast<int>(channels.size() * channels[0].total()), p_.scales, CV_32F);
    int row = 0;
    for (const cv::Mat& m : channels)
      for (int y = 0; y < m.rows; ++y)
        for (int x = 0; x < m.cols; ++x) samples.at<float>(row++, n) = m.at<float>(y, x) * scale_window_[n];
  }
  cv::Mat spectra;
  cv::dft(samples, spectra, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
  return spectra;
}

void CorrelationTracker::Start(const cv::Mat& grey, const cv::Rect2d& box) {
  centre_ = last_sure_ = cv::Point2d(box.x + box.width / 2, box.y + box.height / 2);
  start_size_ = box.size();
  scale_ = 1.0;
  psr_level_ = 0.0;
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
  // DSST's scale filter: scales a^n, n = -(S-1)/2 .. (S-1)/2; a Gaussian label over them.
  scale_factors_.resize(p_.scales);
  scale_window_.resize(p_.scales);
  cv::Mat scale_label(1, p_.scales, CV_32F);
  const double scale_sigma = p_.scales / std::sqrt(33.0) * 0.25;  // DSST's 1/4 at 33 scales
  for (int n = 0; n < p_.scales; ++n) {
    const double k = n - (p_.scales - 1) / 2.0;
    scale_factors_[n] = std::pow(p_.scale_step, k);
    scale_window_[n] = static_cast<float>(0.5 - 0.5 * std::cos(2 * CV_PI * (n + 1) / (p_.scales + 1)));
    scale_label.at<float>(n) = static_cast<float>(std::exp(-0.5 * k * k / (scale_sigma * scale_sigma)));
  }
  cv::dft(scale_label, scale_label_spectrum_, cv::DFT_ROWS | cv::DFT_COMPLEX_OUTPUT);
  const double shrink = std::min(1.0, std::sqrt(p_.scale_model_area_px / box.area()));
  scale_model_ = cv::Size(std::max(2 * c, static_cast<int>(box.width * shrink) / c * c),
                          std::max(2 * c, static_cast<int>(box.height * shrink) / c * c));
  min_scale_ = std::max(4.0 / box.width, 4.0 / box.height);
  max_scale_ = std::min(grey.cols / box.width, grey.rows / box.height);
  Learn(grey, 1.0, 1.0);
}

CorrelationTracker::Found CorrelationTracker::Detect(const cv::Mat& grey, cv::Point2d centre) const {
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
  cv::Mat response;
  cv::dft(sum, response, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT);
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
  const double px_per_cell = p_.cell_px * template_ratio_ * scale_;
  found.centre = centre + cv::Point2d(dx * px_per_cell, dy * px_per_cell);
  found.centre.x = std::clamp(found.centre.x, 0.0, grey.cols - 1.0);
  found.centre.y = std::clamp(found.centre.y, 0.0, grey.rows - 1.0);
  return found;
}

double CorrelationTracker::EstimateScaleChange(const cv::Mat& grey) const {
  const cv::Mat z = ScaleSpectra(grey);
  cv::Mat sum = cv::Mat::zeros(1, z.cols, CV_32FC2);
  float* o = sum.ptr<float>(0);
  for (int r = 0; r < z.rows; ++r) {
    const float* x = z.ptr<float>(r);
    const float* a = scale_numerator_.ptr<float>(r);
    for (int q = 0; q < z.cols; ++q) {  // Z .* conj(A)
      o[2 * q] += x[2 * q] * a[2 * q] + x[2 * q + 1] * a[2 * q + 1];
      o[2 * q + 1] += x[2 * q + 1] * a[2 * q] - x[2 * q] * a[2 * q + 1];
    }
  }
  const float* d = scale_denominator_.ptr<float>(0);
  for (int q = 0; q < z.cols; ++q) {
    const float k = 1.0f / (d[q] + static_cast<float>(p_.regularisation));
    o[2 * q] *= k;
    o[2 * q + 1] *= k;
  }
  cv::Mat response;
  cv::dft(sum, response, cv::DFT_INVERSE | cv::DFT_SCALE | cv::DFT_REAL_OUTPUT | cv::DFT_ROWS);
  cv::Point best;
  cv::minMaxLoc(response, nullptr, nullptr, nullptr, &best);
  return scale_factors_[best.x];
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
  cv::Mat scale_numerator, scale_denominator;
  ScaleTerms(ScaleSpectra(grey), scale_label_spectrum_, scale_numerator, scale_denominator);
  if (first || scale_rate >= 1.0) {
    scale_numerator_ = scale_numerator;
    scale_denominator_ = scale_denominator;
  } else {
    scale_numerator_ = (1 - scale_rate) * scale_numerator_ + scale_rate * scale_numerator;
    scale_denominator_ = (1 - scale_rate) * scale_denominator_ + scale_rate * scale_denominator;
  }
}

CorrelationDetection CorrelationTracker::Update(const cv::Mat& grey) {
  const cv::Rect2d image(0, 0, grey.cols, grey.rows);
  const auto box_at = [&](cv::Point2d centre) {
    const cv::Size2d size(start_size_.width * scale_, start_size_.height * scale_);
    return cv::Rect2d(centre.x - size.width / 2, centre.y - size.height / 2, size.width, size.height);
  };
  // A target mostly beyond the image edge has left the view: nothing there is the target.
  const auto in_view = [&](cv::Point2d centre) {
    const cv::Rect2d box = box_at(centre);
    return (box & image).area() >= kMinInViewShare * box.area();
  };
  Found found = Detect(grey, centre_);
  bool sure = (sure_frames_ < kWarmUpFrames || found.psr >= p_.sure_psr_share * psr_level_) && in_view(found.centre);
  if (!sure) {
    // Occluded, or lost: half a window and a whole window around where it was last seen for
    // sure. A detection away from the track must be as sure as the target usually is.
    const cv::Size2d window = Window();
    for (int reach = 1; reach <= kRedetectReach; ++reach)
      for (const cv::Point step : {cv::Point(1, 0), cv::Point(-1, 0), cv::Point(0, 1), cv::Point(0, -1), cv::Point(1, 1),
                                   cv::Point(-1, 1), cv::Point(1, -1), cv::Point(-1, -1)}) {
        const cv::Point2d at = last_sure_ + cv::Point2d(step.x * reach * 0.5 * window.width, step.y * reach * 0.5 * window.height);
        if (!image.contains(at)) continue;
        const Found candidate = Detect(grey, at);
        if (candidate.psr >= p_.relock_psr_share * psr_level_ && candidate.psr > found.psr && in_view(candidate.centre)) {
          found = candidate;
          sure = true;
        }
      }
  }
  centre_ = found.centre;
  // The PSR level follows sure frames quickly and the others slowly: a lasting change of
  // appearance (a walker setting off, the camera turning, light) lowers it within a few frames,
  // a brief occlusion hardly.
  if (!sure && sure_frames_ >= kWarmUpFrames && in_view(found.centre))
    psr_level_ += kUnsureLevelRate * (found.psr - psr_level_);
  if (sure) {
    last_sure_ = centre_;
    psr_level_ = sure_frames_ < kWarmUpFrames ? (psr_level_ * sure_frames_ + found.psr) / (sure_frames_ + 1)
                                              : psr_level_ + kSureLevelRate * (found.psr - psr_level_);
    ++sure_frames_;
    scale_ = std::clamp(scale_ * EstimateScaleChange(grey), min_scale_, max_scale_);
    Learn(grey, p_.learning_rate, p_.scale_learning_rate);
  }
  CorrelationDetection out;
  out.box = box_at(centre_);
  out.psr = found.psr;
  out.sure = sure;
  out.confidence = psr_level_ > 0 ? std::clamp(found.psr / psr_level_, 0.0, 1.0) : 1.0;
  return out;
}

}  // namespace uav::vision::detail
