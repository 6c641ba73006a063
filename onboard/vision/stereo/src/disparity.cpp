#include "uav/vision/disparity.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/disparity_filter.hpp>

namespace uav::vision {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("disparity: " + what);
}
}  // namespace

MatcherKind ParseMatcherKind(const std::string& text) {
  if (text == "bm") return MatcherKind::kBlockMatching;
  if (text == "sgbm") return MatcherKind::kSemiGlobal;
  throw std::invalid_argument("unknown matcher '" + text + "' (bm or sgbm)");
}

const char* MatcherKindName(MatcherKind kind) { return kind == MatcherKind::kBlockMatching ? "bm" : "sgbm"; }

void DisparityParams::Validate() const {
  Require(downscale == 1 || downscale == 2 || downscale == 4, "downscale must be 1, 2 or 4");
  Require(num_disparities >= 16 && num_disparities <= 512 && num_disparities % 16 == 0,
          "num_disparities must be a multiple of 16 in 16..512, got " + std::to_string(num_disparities));
  Require(block_size >= 5 && block_size <= 21 && block_size % 2 == 1,
          "block_size must be odd, 5..21, got " + std::to_string(block_size));
  Require(lr_max_diff_px >= 0 && lr_max_diff_px <= 16, "lr_max_diff_px must be 0..16");
  Require(std::isfinite(wls_lambda) && wls_lambda > 0, "wls_lambda must be positive");
  Require(std::isfinite(wls_sigma_color) && wls_sigma_color > 0, "wls_sigma_color must be positive");
  Require(std::isfinite(texture_threshold) && texture_threshold >= 0, "texture_threshold must not be negative");
}

cv::Mat DisparityMap::FullResolution16U(const cv::Size& full) const {
  cv::Mat scaled;
  // Invalid (negative) disparities become 0; valid ones scale with the resolution.
  d16.convertTo(scaled, CV_32F, downscale);
  cv::threshold(scaled, scaled, 0, 0, cv::THRESH_TOZERO);
  cv::Mat out;
  if (scaled.size() != full) cv::resize(scaled, scaled, full, 0, 0, cv::INTER_NEAREST);
  scaled.convertTo(out, CV_16U);
  return out;
}

double DisparityMap::ValidFraction() const {
  if (d16.empty()) return 0.0;
  return static_cast<double>(cv::countNonZero(d16 > 0)) / static_cast<double>(d16.total());
}

DisparityErrors CompareDisparity(const cv::Mat& estimate_x16, const cv::Mat& truth_px, double bad_threshold_px) {
  Require(estimate_x16.size() == truth_px.size(), "estimate and ground truth differ in size");
  Require(truth_px.type() == CV_32F, "ground truth must be CV_32F");
  cv::Mat estimate;
  estimate_x16.convertTo(estimate, CV_32F, 1.0 / 16.0);
  DisparityErrors e;
  long invalid = 0, bad = 0, valid = 0;
  double sum = 0;
  for (int v = 0; v < truth_px.rows; ++v) {
    const float* t = truth_px.ptr<float>(v);
    const float* d = estimate.ptr<float>(v);
    for (int u = 0; u < truth_px.cols; ++u) {
      if (!(t[u] > 0)) continue;
      ++e.pixels;
      if (!(d[u] > 0)) {
        ++invalid;
        continue;
      }
      const double error = std::abs(d[u] - t[u]);
      ++valid;
      sum += error;
      if (error > bad_threshold_px) ++bad;
    }
  }
  if (e.pixels > 0) {
    e.bad_fraction = static_cast<double>(bad + invalid) / static_cast<double>(e.pixels);
    e.invalid_fraction = static_cast<double>(invalid) / static_cast<double>(e.pixels);
  }
  if (valid > 0) e.mean_abs_error_px = sum / static_cast<double>(valid);
  return e;
}

struct DisparityMatcher::Impl {
  DisparityParams params;
  cv::Ptr<cv::StereoMatcher> left;
  cv::Ptr<cv::StereoMatcher> right;                     // WLS only
  cv::Ptr<cv::ximgproc::DisparityWLSFilter> wls;        // WLS only
};

DisparityMatcher::DisparityMatcher(const DisparityParams& p) : impl_(std::make_unique<Impl>()) {
  p.Validate();
  Impl& m = *impl_;
  m.params = p;
  const int block = p.block_size;
  if (p.matcher == MatcherKind::kSemiGlobal) {
    // Penalties as OpenCV's stereo_match sample (P1 = 8 w^2, P2 = 32 w^2 for grey images);
    // disp12MaxDiff is SGBM's left-right consistency check; uniqueness and speckle filtering
    // drop ambiguous and isolated matches that would otherwise pose as near obstacles.
    m.left = cv::StereoSGBM::create(0, p.num_disparities, block, 8 * block * block, 32 * block * block,
                                    p.lr_max_diff_px, /*preFilterCap=*/31, /*uniquenessRatio=*/10,
                                    /*speckleWindowSize=*/100, /*speckleRange=*/2, cv::StereoSGBM::MODE_SGBM);
  } else {
    cv::Ptr<cv::StereoBM> bm = cv::StereoBM::create(p.num_disparities, block);
    bm->setPreFilterCap(31);
    bm->setTextureThreshold(10);
    bm->setUniquenessRatio(15);
    bm->setSpeckleWindowSize(100);
    bm->setSpeckleRange(2);
    bm->setDisp12MaxDiff(p.lr_max_diff_px);  // BM's left-right consistency check
    m.left = bm;
  }
  if (p.wls_filter) {
    m.wls = cv::ximgproc::createDisparityWLSFilter(m.left);
    m.wls->setLambda(p.wls_lambda);
    m.wls->setSigmaColor(p.wls_sigma_color);
    m.right = cv::ximgproc::createRightMatcher(m.left);
  }
}

DisparityMatcher::~DisparityMatcher() = default;
DisparityMatcher::DisparityMatcher(DisparityMatcher&&) noexcept = default;

const DisparityParams& DisparityMatcher::params() const { return impl_->params; }

double DisparityMatcher::MinDepth(double f_px, double baseline_m) const {
  const DisparityParams& p = impl_->params;
  return f_px * baseline_m / (static_cast<double>(p.num_disparities - 1) * p.downscale);
}

DisparityMap DisparityMatcher::Compute(const cv::Mat& left_rect, const cv::Mat& right_rect) const {
  const Impl& m = *impl_;
  const DisparityParams& p = m.params;
  for (const cv::Mat* image : {&left_rect, &right_rect}) {
    Require(!image->empty(), "empty image");
    Require(image->type() == CV_8UC3 || image->type() == CV_8UC1, "images must be 8-bit BGR or grey");
  }
  Require(left_rect.size() == right_rect.size(),
          "left image is " + std::to_string(left_rect.cols) + "x" + std::to_string(left_rect.rows) + ", right is " +
              std::to_string(right_rect.cols) + "x" + std::to_string(right_rect.rows));
  Require(left_rect.cols % p.downscale == 0 && left_rect.rows % p.downscale == 0,
          "image size must be divisible by downscale " + std::to_string(p.downscale));
  const cv::Size small(left_rect.cols / p.downscale, left_rect.rows / p.downscale);
  Require(small.width > p.num_disparities + p.block_size, "image too narrow for the disparity search range");
  const cv::Mat rect[2] = {left_rect, right_rect};
  cv::Mat image[2];
  for (int i = 0; i < 2; ++i) {
    cv::Mat grey;
    if (rect[i].channels() == 3) cv::cvtColor(rect[i], grey, cv::COLOR_BGR2GRAY);
    else grey = rect[i];
    if (p.downscale == 1) image[i] = grey;
    else cv::resize(grey, image[i], small, 0, 0, cv::INTER_AREA);
  }
  DisparityMap out;
  out.downscale = p.downscale;
  m.left->compute(image[0], image[1], out.d16);
  if (m.wls) {
    cv::Mat right16, filtered;
    m.right->compute(image[1], image[0], right16);
    m.wls->filter(out.d16, image[0], filtered, right16);
    out.d16 = filtered;
  }
  // Columns left of the search range have no partner in the right image.
  out.d16.colRange(0, std::min(p.num_disparities, small.width)).setTo(-16);
  if (p.texture_threshold > 0) {
    // Texture: mean |dI/dx| over the matching window, in grey levels per pixel.
    cv::Mat gradient, texture;
    cv::Sobel(image[0], gradient, CV_32F, 1, 0, 3, 0.25);
    cv::boxFilter(cv::abs(gradient), texture, CV_32F, cv::Size(p.block_size, p.block_size));
    out.d16.setTo(-16, texture < p.texture_threshold);
  }
  return out;
}

}  // namespace uav::vision
