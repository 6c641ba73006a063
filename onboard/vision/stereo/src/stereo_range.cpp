#include "uav/vision/stereo_range.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

namespace uav::vision {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("stereo range: " + what);
}
}  // namespace

namespace {
DisparityParams MatchingOf(const StereoRangeParams& p) {
  DisparityParams d;
  d.matcher = MatcherKind::kSemiGlobal;
  d.downscale = p.downscale;
  d.num_disparities = p.num_disparities;
  d.block_size = p.block_size;
  d.texture_threshold = p.texture_threshold;
  return d;
}
}  // namespace

struct StereoRange::Impl {
  Impl(const StereoRig& rig, const StereoRangeParams& p) : params(p), rectifier(rig), matcher(MatchingOf(p)) {}
  StereoRangeParams params;
  StereoRectifier rectifier;
  DisparityMatcher matcher;
};

StereoRange::StereoRange(const StereoRig& rig, const StereoRangeParams& p) {
  Require(std::isfinite(p.corridor_half_width_m) && p.corridor_half_width_m > 0, "corridor_half_width_m must be positive");
  Require(std::isfinite(p.corridor_half_height_m) && p.corridor_half_height_m > 0, "corridor_half_height_m must be positive");
  Require(std::isfinite(p.max_range_m) && p.max_range_m > 0, "max_range_m must be positive");
  Require(p.min_points >= 1, "min_points must be at least 1");
  impl_ = std::make_unique<Impl>(rig, p);
}

StereoRange::~StereoRange() = default;
StereoRange::StereoRange(StereoRange&&) noexcept = default;

int StereoRange::BlindColumns() const { return impl_->params.num_disparities * impl_->params.downscale; }

StereoRangeResult StereoRange::RangeFromPoints(const std::vector<Eigen::Vector3f>& p_L, const StereoRangeParams& p) {
  StereoRangeResult r;
  std::vector<double> z;
  for (const Eigen::Vector3f& q : p_L)
    if (q.z() > 0 && q.z() <= p.max_range_m && std::abs(q.x()) <= p.corridor_half_width_m &&
        std::abs(q.y()) <= p.corridor_half_height_m)
      z.push_back(q.z());
  r.corridor_points = static_cast<int>(z.size());
  if (r.corridor_points >= p.min_points) {
    std::nth_element(z.begin(), z.begin() + (p.min_points - 1), z.end());
    r.obstacle = true;
    r.range_m = z[p.min_points - 1];
  }
  return r;
}

const StereoRectifier& StereoRange::rectifier() const { return impl_->rectifier; }

StereoRangeResult StereoRange::Process(const cv::Mat& left, const cv::Mat& right) const {
  cv::Mat left_rect, right_rect;
  impl_->rectifier.Rectify(left, right, &left_rect, &right_rect);
  return ProcessRectified(left_rect, right_rect);
}

StereoRangeResult StereoRange::ProcessRectified(const cv::Mat& left_rect, const cv::Mat& right_rect) const {
  const Impl& m = *impl_;
  m.rectifier.CheckPair(left_rect, right_rect);
  const DisparityMap disparity = m.matcher.Compute(left_rect, right_rect);
  const cv::Mat& disparity16 = disparity.d16;
  StereoRangeResult r;
  r.depth_m = cv::Mat::zeros(disparity16.size(), CV_32F);
  std::vector<Eigen::Vector3f> points;
  points.reserve(disparity16.total() / 4);
  const RectifiedGeometry& g = m.rectifier.geometry();
  const double s = m.params.downscale;
  int valid = 0;
  for (int v = 0; v < disparity16.rows; ++v) {
    const int16_t* d16 = disparity16.ptr<int16_t>(v);
    float* depth = r.depth_m.ptr<float>(v);
    for (int u = 0; u < disparity16.cols; ++u) {
      if (d16[u] <= 0) continue;  // invalid (negative) or at infinity
      ++valid;
      const double d = d16[u] / 16.0;
      // Matching-resolution pixels and disparities scale by s to the full-resolution geometry.
      const Eigen::Vector3d p_L = g.Triangulate(u * s, v * s, d * s);
      depth[u] = static_cast<float>(g.f_px * g.baseline_m / (d * s));
      points.push_back(p_L.cast<float>());
    }
  }
  StereoRangeResult corridor = RangeFromPoints(points, m.params);
  r.obstacle = corridor.obstacle;
  r.range_m = corridor.range_m;
  r.corridor_points = corridor.corridor_points;
  r.valid_fraction = static_cast<double>(valid) / static_cast<double>(disparity16.total());
  return r;
}

}  // namespace uav::vision
