#include "wire_verifier.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/ml.hpp>

namespace uav::vision::detail {

extern const char* const kEmbeddedWireVerifierYaml;  // generated from resources/models/wire_verifier.yml

namespace {


}  // namespace

WireFeatureVector MeasureWire(const cv::Mat& gray, const cv::Mat& thin, const WireCurve& w) {
  const double diag = std::hypot(gray.cols, gray.rows), span = w.u_max - w.u_min;
  // The background is read 8 px wide beyond the widest wire's flank, as the background test reads it.
  const double beyond = std::max(0.5 * w.width_px, 8.0) + 2.0;
  std::vector<double> side_difference, contrast, ridge, flank, texture;
  int samples = 0, edges = 0;
  for (const StripsBeside& s : ReadStripsBeside(gray, w, beyond)) {
    double g, peak = 0.0;
    for (double t = -0.5 * w.width_px - 1.5; t <= 0.5 * w.width_px + 1.5; t += 0.5)
      if (ValueAt(thin, s.p + t * s.n, &g)) peak = std::max(peak, g);
    side_difference.push_back(s.left - s.right);
    contrast.push_back(s.contrast);
    ridge.push_back(peak);
    ++samples;
    edges += peak > 7.0;
    double beside = 0.0;
    int beside_n = 0;
    for (const double t : {-beyond - 4.0, beyond + 4.0})
      if (ValueAt(thin, s.p + t * s.n, &g)) beside += g, ++beside_n;
    if (beside_n > 0) flank.push_back(beside / beside_n);
    double mean = 0.0, sq = 0.0;
    for (const double x : s.left_strip) mean += x;
    for (const double x : s.right_strip) mean += x;
    const double strips = static_cast<double>(s.left_strip.size() + s.right_strip.size());
    mean /= strips;
    for (const double x : s.left_strip) sq += (x - mean) * (x - mean);
    for (const double x : s.right_strip) sq += (x - mean) * (x - mean);
    texture.push_back(std::sqrt(sq / strips));
  }
  const double median_contrast = Median(contrast), median_ridge = Median(ridge), median_flank = Median(flank);
  int polarity = 0;
  for (const double c : contrast) polarity += (c > 0) == (median_contrast > 0);
  return {static_cast<float>(span / diag),
          static_cast<float>(w.support),
          static_cast<float>(w.rms_px),
          static_cast<float>(w.width_px),
          static_cast<float>(std::abs(w.b(2)) * span * span / 4.0),
          static_cast<float>(w.segments),
          static_cast<float>(std::abs(Median(side_difference)) / (std::abs(median_contrast) + 1e-3)),
          static_cast<float>(std::abs(median_contrast)),
          static_cast<float>(contrast.empty() ? 0.0 : static_cast<double>(polarity) / static_cast<double>(contrast.size())),
          static_cast<float>(median_ridge),
          static_cast<float>(median_flank),
          static_cast<float>(median_ridge / (median_flank + 1.0)),
          static_cast<float>(samples > 0 ? static_cast<double>(edges) / samples : 0.0),
          static_cast<float>(Median(texture)),
          static_cast<float>(median_contrast < 0 ? 1.0 : 0.0)};
}

WireVerifier::WireVerifier(cv::Ptr<cv::ml::RTrees> forest) : forest_(std::move(forest)) {}

const WireVerifier& WireVerifier::Embedded() {
  static const WireVerifier verifier = [] {
    cv::Ptr<cv::ml::RTrees> forest = cv::Algorithm::loadFromString<cv::ml::RTrees>(kEmbeddedWireVerifierYaml);
    if (forest.empty() || !forest->isTrained() || forest->getVarCount() != kWireFeatures)
      throw std::runtime_error("the wire verifier compiled into the library does not load as a forest over " +
                               std::to_string(kWireFeatures) + " measurements");
    return WireVerifier(forest);
  }();
  return verifier;
}

WireVerifier WireVerifier::FromFile(const std::string& path) {
  cv::Ptr<cv::ml::RTrees> forest = cv::Algorithm::load<cv::ml::RTrees>(path);
  if (forest.empty() || !forest->isTrained() || forest->getVarCount() != kWireFeatures)
    throw std::runtime_error(path + ": not a wire verifier (a random forest over " + std::to_string(kWireFeatures) +
                             " measurements, as uav-powerlines-train writes)");
  return WireVerifier(forest);
}

double WireVerifier::Probability(const WireFeatureVector& f) const {
  // The share of the trees voting "wire".
  const cv::Mat sample(1, kWireFeatures, CV_32F, const_cast<float*>(f.data()));
  cv::Mat votes;
  forest_->getVotes(sample, votes, 0);
  double wire = 0.0, all = 0.0;
  for (int j = 0; j < votes.cols; ++j) {
    all += votes.at<int>(1, j);
    if (votes.at<int>(0, j) == 1) wire = votes.at<int>(1, j);
  }
  return all > 0 ? wire / all : 0.0;
}

}  // namespace uav::vision::detail
