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

struct StereoRange::Impl {
  explicit Impl(const StereoRig& rig) : rectifier(rig) {}
  StereoRangeParams params;
  StereoRectifier rectifier;
  cv::Size small;  // matching resolution
  cv::Ptr<cv::StereoSGBM> matcher;
};

StereoRange::StereoRange(const StereoRig& rig, const StereoRangeParams& p) : impl_(std::make_unique<Impl>(rig)) {
  Require(p.downscale == 1 || p.downscale == 2 || p.downscale == 4, "downscale must be 1, 2 or 4");
  Require(p.num_disparities >= 16 && p.num_disparities <= 256 && p.num_disparities % 16 == 0,
          "num_disparities must be a multiple of 16 in 16..256");
  Require(p.block_size >= 3 && p.block_size <= 21 && p.block_size % 2 == 1, "block_size must be odd, 3..21");
  Require(std::isfinite(p.corridor_half_width_m) && p.corridor_half_width_m > 0, "corridor_half_width_m must be positive");
  Require(std::isfinite(p.corridor_half_height_m) && p.corridor_half_height_m > 0, "corridor_half_height_m must be positive");
  Require(std::isfinite(p.max_range_m) && p.max_range_m > 0, "max_range_m must be positive");
  Require(p.min_points >= 1, "min_points must be at least 1");
  Require(std::isfinite(p.texture_threshold) && p.texture_threshold >= 0, "texture_threshold must not be negative");
  Impl& m = *impl_;
  m.params = p;
  const RectifiedGeometry& g = m.rectifier.geometry();
  m.small = cv::Size(g.width / p.downscale, g.height / p.downscale);
  // Semi-global matching (smoothness carries weakly textured surfaces such as a person's
  // clothes); left-right consistency, uniqueness and speckle filtering drop ambiguous and
  // isolated matches that would otherwise pose as near obstacles. Featureless surfaces (a plain
  // wall, thesis 4.4) are masked by a texture test in Process() instead of matching their noise;
  // the laser grid (thesis 4.2) gives them back texture.
  const int block = p.block_size;
  m.matcher = cv::StereoSGBM::create(0, p.num_disparities, block, 8 * block * block, 32 * block * block,
                                     /*disp12MaxDiff=*/1, /*preFilterCap=*/31, /*uniquenessRatio=*/15,
                                     /*speckleWindowSize=*/100, /*speckleRange=*/2, cv::StereoSGBM::MODE_SGBM);
}

StereoRange::~StereoRange() = default;
StereoRange::StereoRange(StereoRange&&) noexcept = default;

int StereoRange::BlindColumns() const { return impl_->params.num_disparities * impl_->params.downscale; }

StereoRangeResult StereoRange::RangeFromPoints(const std::vector<Eigen::Vector3d>& p_L, const StereoRangeParams& p) {
  StereoRangeResult r;
  std::vector<double> z;
  for (const Eigen::Vector3d& q : p_L)
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
  const cv::Mat rect[2] = {left_rect, right_rect};
  cv::Mat grey, small[2];
  for (int i = 0; i < 2; ++i) {
    if (rect[i].channels() == 3) cv::cvtColor(rect[i], grey, cv::COLOR_BGR2GRAY);
    else grey = rect[i];
    if (m.params.downscale == 1) small[i] = grey.clone();
    else cv::resize(grey, small[i], m.small, 0, 0, cv::INTER_AREA);
  }
  cv::Mat disparity16;
  m.matcher->compute(small[0], small[1], disparity16);
  // Texture: mean |d/dx| over the matching window of the left image, in grey levels per pixel.
  cv::Mat gradient, texture;
  cv::Sobel(small[0], gradient, CV_32F, 1, 0, 3, 0.25);
  cv::boxFilter(cv::abs(gradient), texture, CV_32F, cv::Size(m.params.block_size, m.params.block_size));

  StereoRangeResult r;
  r.depth_m = cv::Mat::zeros(m.small, CV_32F);
  std::vector<Eigen::Vector3d> points;
  points.reserve(static_cast<size_t>(m.small.area()) / 4);
  const RectifiedGeometry& g = m.rectifier.geometry();
  const double s = m.params.downscale;
  int valid = 0;
  for (int v = 0; v < disparity16.rows; ++v) {
    const int16_t* d16 = disparity16.ptr<int16_t>(v);
    float* depth = r.depth_m.ptr<float>(v);
    const float* tex = texture.ptr<float>(v);
    for (int u = 0; u < disparity16.cols; ++u) {
      if (d16[u] <= 0) continue;  // invalid (negative) or at infinity
      if (tex[u] < m.params.texture_threshold) continue;
      ++valid;
      const double d = d16[u] / 16.0;
      // Matching-resolution pixels and disparities scale by s to the full-resolution geometry.
      const Eigen::Vector3d p_L = g.Triangulate(u * s, v * s, d * s);
      depth[u] = static_cast<float>(g.f_px * g.baseline_m / (d * s));
      points.push_back(p_L);
    }
  }
  StereoRangeResult corridor = RangeFromPoints(points, m.params);
  r.obstacle = corridor.obstacle;
  r.range_m = corridor.range_m;
  r.corridor_points = corridor.corridor_points;
  r.valid_fraction = static_cast<double>(valid) / m.small.area();
  return r;
}

}  // namespace uav::vision
