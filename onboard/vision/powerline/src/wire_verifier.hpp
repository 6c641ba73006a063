#pragma once
// The learned check on a detected wire (not in the thesis): a random forest (OpenCV's RTrees)
// over a few measurements of the curve and of the image along it gives the probability that the
// curve is a wire. Trained by uav-powerlines-train on the real photos with pixel masks; the model
// ships in resources/models/wire_verifier.yml and is compiled into the library.
#include <algorithm>
#include <array>
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "uav/vision/power_line_detector.hpp"

namespace cv::ml {
class RTrees;
}  // namespace cv::ml

namespace uav::vision::detail {

// Per curve: its shape (span over the diagonal, support, flank spread, width, sag, pieces), the
// background test's two sides (their difference over the wire's contrast, the contrast, the
// share of samples with the median's polarity, whether it is darker), the thin-structure
// response on the curve and beside it (their medians and ratio, the share of samples where the
// response is an edge), and the texture of its background.
inline constexpr int kWireFeatures = 15;

// Along the curve every 3 px (samples with both strips inside the image): the grey of the strips
// 8 px wide beyond each flank, from `beyond` px out, their medians, and the wire's contrast
// against their mean (the grey between the flanks, 1 px either side, that stands out most).
// What the background test (step 7) reads, and part of what the verifier measures.
struct StripsBeside {
  Eigen::Vector2d p, n;  // the sample and the curve's normal there
  std::vector<double> left_strip, right_strip;
  double left = 0.0, right = 0.0, contrast = 0.0;
};
std::vector<StripsBeside> ReadStripsBeside(const cv::Mat& gray, const WireCurve& w, double beyond);
// The median (the upper one of an even count); T{} for none.
template <typename T>
T Median(std::vector<T> x) {
  if (x.empty()) return T{};
  std::nth_element(x.begin(), x.begin() + x.size() / 2, x.end());
  return x[x.size() / 2];
}
// The grey (or response) of the 8-bit image's pixel nearest p; false outside the image.
bool ValueAt(const cv::Mat& image, const Eigen::Vector2d& p, double* value);
using WireFeatureVector = std::array<float, kWireFeatures>;
WireFeatureVector MeasureWire(const cv::Mat& gray, const cv::Mat& thin, const WireCurve& w);

class WireVerifier {
 public:
  // The model compiled into the library. Throws std::runtime_error if it does not load.
  static const WireVerifier& Embedded();
  // From a model file written by uav-powerlines-train.
  static WireVerifier FromFile(const std::string& path);
  double Probability(const WireFeatureVector& f) const;

 private:
  explicit WireVerifier(cv::Ptr<cv::ml::RTrees> forest);
  cv::Ptr<cv::ml::RTrees> forest_;
};

}  // namespace uav::vision::detail
