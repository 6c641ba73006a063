#include "uav/vision/stereo_range.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

namespace uav::vision {

namespace {
cv::Mat CameraMatrix(const CameraIntrinsics& k) {
  return (cv::Mat_<double>(3, 3) << k.fx, 0, k.cx, 0, k.fy, k.cy, 0, 0, 1);
}
cv::Mat Distortion(const CameraIntrinsics& k) {
  return (cv::Mat_<double>(1, 5) << k.distortion[0], k.distortion[1], k.distortion[2], k.distortion[3],
          k.distortion[4]);
}
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("stereo range: " + what);
}
}  // namespace

struct StereoRange::Impl {
  StereoRangeParams params;
  cv::Size size;        // input
  cv::Size small;       // matching resolution
  cv::Mat map_lx, map_ly, map_rx, map_ry;  // full-resolution rectification maps
  cv::Mat Q;            // disparity-to-depth at matching resolution
  Eigen::Matrix3d R_L_rect = Eigen::Matrix3d::Identity();  // rectified left frame in the left frame
  cv::Ptr<cv::StereoSGBM> matcher;
};

StereoRange::StereoRange(const StereoRig& rig, const StereoRangeParams& p) : impl_(std::make_unique<Impl>()) {
  ValidateIntrinsics(rig.left);
  ValidateIntrinsics(rig.right);
  Require(rig.left.width == rig.right.width && rig.left.height == rig.right.height,
          "left and right images must have the same size");
  Require(rig.T_LR.matrix().allFinite(), "rig pose must be finite");
  const double baseline = rig.T_LR.translation().norm();
  Require(baseline > 0.01 && baseline < 10.0, "baseline must be 0.01..10 m, got " + std::to_string(baseline));
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
  m.size = cv::Size(rig.left.width, rig.left.height);
  m.small = cv::Size(m.size.width / p.downscale, m.size.height / p.downscale);

  // OpenCV's convention: p_R = R p_L + T.
  const Eigen::Isometry3d T_RL = rig.T_LR.inverse();
  cv::Mat R, T;
  cv::eigen2cv(Eigen::Matrix3d(T_RL.linear()), R);
  cv::eigen2cv(Eigen::Vector3d(T_RL.translation()), T);
  cv::Mat R1, R2, P1, P2, Q;
  const cv::Mat K1 = CameraMatrix(rig.left), K2 = CameraMatrix(rig.right);
  const cv::Mat D1 = Distortion(rig.left), D2 = Distortion(rig.right);
  cv::stereoRectify(K1, D1, K2, D2, m.size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0);
  cv::initUndistortRectifyMap(K1, D1, R1, P1, m.size, CV_32FC1, m.map_lx, m.map_ly);
  cv::initUndistortRectifyMap(K2, D2, R2, P2, m.size, CV_32FC1, m.map_rx, m.map_ry);
  // Q at matching resolution: pixel coordinates and disparities both shrink by s, so the
  // offsets, the focal length and the principal-point difference term scale by s.
  const double s = 1.0 / p.downscale;
  m.Q = Q.clone();
  m.Q.at<double>(0, 3) *= s;  // -cx
  m.Q.at<double>(1, 3) *= s;  // -cy
  m.Q.at<double>(2, 3) *= s;  // f
  m.Q.at<double>(3, 3) *= s;  // (cx - cx') / Tx
  Eigen::Matrix3d R1e;
  cv::cv2eigen(R1, R1e);
  m.R_L_rect = R1e.transpose();  // R1 rotates the left frame into the rectified frame
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

StereoRangeResult StereoRange::Process(const cv::Mat& left, const cv::Mat& right) const {
  const Impl& m = *impl_;
  for (const cv::Mat* image : {&left, &right}) {
    Require(!image->empty(), "empty image");
    Require(image->size() == m.size, "image is " + std::to_string(image->cols) + "x" + std::to_string(image->rows) +
                                         ", the rig's cameras are " + std::to_string(m.size.width) + "x" +
                                         std::to_string(m.size.height));
    Require(image->type() == CV_8UC3 || image->type() == CV_8UC1, "images must be 8-bit BGR or grey");
  }
  cv::Mat grey[2], rect, small[2];
  const cv::Mat* in[2] = {&left, &right};
  const cv::Mat* mx[2] = {&m.map_lx, &m.map_rx};
  const cv::Mat* my[2] = {&m.map_ly, &m.map_ry};
  for (int i = 0; i < 2; ++i) {
    if (in[i]->channels() == 3) cv::cvtColor(*in[i], grey[i], cv::COLOR_BGR2GRAY);
    else grey[i] = *in[i];
    cv::remap(grey[i], rect, *mx[i], *my[i], cv::INTER_LINEAR);
    if (m.params.downscale == 1) small[i] = rect.clone();
    else cv::resize(rect, small[i], m.small, 0, 0, cv::INTER_AREA);
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
  const double* Q = m.Q.ptr<double>();
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
      // [X Y Z W]^T = Q [u v d 1]^T (OpenCV reprojectImageTo3D).
      const double X = Q[0] * u + Q[3], Y = Q[5] * v + Q[7], Z = Q[11], W = Q[14] * d + Q[15];
      const Eigen::Vector3d p_rect(X / W, Y / W, Z / W);
      depth[u] = static_cast<float>(p_rect.z());
      points.push_back(m.R_L_rect * p_rect);
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
