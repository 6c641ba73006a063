#include "uav/vision/stereo_rectifier.hpp"

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
  if (!ok) throw std::invalid_argument("stereo rig: " + what);
}
}  // namespace

Eigen::Vector3d RectifiedGeometry::Triangulate(double u, double v, double d) const {
  const double z = f_px * baseline_m / d;
  return R_L_rect * Eigen::Vector3d((u - cx) * z / f_px, (v - cy) * z / f_px, z);
}

std::array<double, 16> RectifiedGeometry::Q(int downscale) const {
  const double s = downscale;
  // Eq. 3.10 in the rectified frame with z forward: X = (u - cx), Y = (v - cy), Z = f, W = d / B.
  return {1, 0, 0, -cx / s,  //
          0, 1, 0, -cy / s,  //
          0, 0, 0, f_px / s,  //
          0, 0, 1.0 / baseline_m, 0};
}

StereoErrorModel RectifiedGeometry::ErrorModel(double sigma_d_px, double calibration_px, int downscale) const {
  StereoErrorModel m;
  m.f_px = f_px / downscale;
  m.baseline_m = baseline_m;
  m.sigma_d_px = sigma_d_px;
  m.calibration_px = calibration_px;
  m.Validate();
  return m;
}

RectifiedGeometry RectifiedGeometry::OfRectifiedPair(int width, int height, double f_px, double baseline_m, double cx,
                                                     double cy) {
  Require(width >= 16 && height >= 16, "image size must be at least 16x16");
  Require(std::isfinite(f_px) && f_px > 0, "focal length must be a positive number of pixels");
  Require(std::isfinite(baseline_m) && baseline_m > 0, "baseline must be a positive number of metres");
  Require(std::isfinite(cx) && std::isfinite(cy), "principal point must be finite");
  RectifiedGeometry g;
  g.width = width;
  g.height = height;
  g.f_px = f_px;
  g.baseline_m = baseline_m;
  g.cx = cx < 0 ? 0.5 * (width - 1) : cx;
  g.cy = cy < 0 ? 0.5 * (height - 1) : cy;
  return g;
}

struct StereoRectifier::Impl {
  RectifiedGeometry geometry;
  cv::Mat map_lx, map_ly, map_rx, map_ry;
  cv::Mat K1, D1, R1, P1, K2, D2, R2, P2;
  bool already_rectified = false;  // the images pass as they are (no maps)
};

StereoRectifier::StereoRectifier(const StereoRig& rig) : impl_(std::make_unique<Impl>()) {
  ValidateIntrinsics(rig.left);
  ValidateIntrinsics(rig.right);
  Require(rig.left.width == rig.right.width && rig.left.height == rig.right.height,
          "left and right images must have the same size");
  Require(rig.T_LR.matrix().allFinite(), "rig pose must be finite");
  const double baseline = rig.T_LR.translation().norm();
  Require(baseline > 0.01 && baseline < 10.0, "baseline must be 0.01..10 m, got " + std::to_string(baseline));
  const cv::Size size(rig.left.width, rig.left.height);
  // A pair already rectified (KITTI, EuRoC's rectified products, a calibrated camera's own
  // output): the same pinhole both sides, no distortion, the right camera straight along x.
  // Its images are used as they are: resampling them would only blur them.
  const auto undistorted = [](const CameraIntrinsics& k) {
    return std::all_of(k.distortion.begin(), k.distortion.end(), [](double d) { return d == 0.0; });
  };
  const Eigen::Vector3d t = rig.T_LR.translation();
  if (undistorted(rig.left) && undistorted(rig.right) && rig.left.fx == rig.left.fy && rig.left.fx == rig.right.fx &&
      rig.left.fy == rig.right.fy && rig.left.cx == rig.right.cx && rig.left.cy == rig.right.cy &&
      rig.T_LR.linear().isIdentity(1e-12) && std::abs(t.y()) < 1e-9 * baseline && std::abs(t.z()) < 1e-9 * baseline && t.x() > 0) {
    Impl& m = *impl_;
    m.already_rectified = true;
    m.K1 = m.P1 = m.K2 = m.P2 = CameraMatrix(rig.left);
    m.D1 = m.D2 = Distortion(rig.left);
    m.R1 = m.R2 = cv::Mat::eye(3, 3, CV_64F);
    m.geometry = RectifiedGeometry::OfRectifiedPair(size.width, size.height, rig.left.fx, t.x(), rig.left.cx, rig.left.cy);
    return;
  }
  // OpenCV's convention: p_R = R p_L + T.
  const Eigen::Isometry3d T_RL = rig.T_LR.inverse();
  cv::Mat R, T;
  cv::eigen2cv(Eigen::Matrix3d(T_RL.linear()), R);
  cv::eigen2cv(Eigen::Vector3d(T_RL.translation()), T);
  cv::Mat R1, R2, P1, P2, Q;
  const cv::Mat K1 = CameraMatrix(rig.left), K2 = CameraMatrix(rig.right);
  const cv::Mat D1 = Distortion(rig.left), D2 = Distortion(rig.right);
  cv::stereoRectify(K1, D1, K2, D2, size, R, T, R1, R2, P1, P2, Q, cv::CALIB_ZERO_DISPARITY, 0.0);
  Require(std::abs(P2.at<double>(1, 3)) < 1e-9,
          "the baseline is vertical in the image; mount the pair side by side along the image x axis");
  Impl& m = *impl_;
  m.K1 = K1, m.D1 = D1, m.R1 = R1, m.P1 = P1, m.K2 = K2, m.D2 = D2, m.R2 = R2, m.P2 = P2;
  cv::initUndistortRectifyMap(K1, D1, R1, P1, size, CV_32FC1, m.map_lx, m.map_ly);
  cv::initUndistortRectifyMap(K2, D2, R2, P2, size, CV_32FC1, m.map_rx, m.map_ry);
  RectifiedGeometry& g = m.geometry;
  g.width = size.width;
  g.height = size.height;
  g.f_px = P1.at<double>(0, 0);
  g.cx = P1.at<double>(0, 2);
  g.cy = P1.at<double>(1, 2);
  g.baseline_m = -P2.at<double>(0, 3) / P2.at<double>(0, 0);
  Require(g.baseline_m > 0, "the right camera must sit to the right of the left one (x > 0 in the left frame)");
  Eigen::Matrix3d R1e;
  cv::cv2eigen(R1, R1e);
  g.R_L_rect = R1e.transpose();  // R1 rotates the left frame into the rectified frame
}

StereoRectifier::~StereoRectifier() = default;
StereoRectifier::StereoRectifier(StereoRectifier&&) noexcept = default;

const RectifiedGeometry& StereoRectifier::geometry() const { return impl_->geometry; }

std::vector<cv::Point2f> StereoRectifier::RectifyPoints(const std::vector<cv::Point2f>& raw_px, Side side) const {
  std::vector<cv::Point2f> out;
  if (raw_px.empty()) return out;
  const Impl& m = *impl_;
  if (side == Side::kLeft) cv::undistortPoints(raw_px, out, m.K1, m.D1, m.R1, m.P1);
  else cv::undistortPoints(raw_px, out, m.K2, m.D2, m.R2, m.P2);
  return out;
}

void StereoRectifier::CheckPair(const cv::Mat& left, const cv::Mat& right) const {
  const RectifiedGeometry& g = impl_->geometry;
  for (const cv::Mat* image : {&left, &right}) {
    Require(!image->empty(), "empty image");
    Require(image->cols == g.width && image->rows == g.height,
            "image is " + std::to_string(image->cols) + "x" + std::to_string(image->rows) + ", the rig's cameras are " +
                std::to_string(g.width) + "x" + std::to_string(g.height));
    Require(image->type() == CV_8UC3 || image->type() == CV_8UC1, "images must be 8-bit BGR or grey");
  }
}

void StereoRectifier::Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat* left_rect, cv::Mat* right_rect) const {
  CheckPair(left, right);
  const Impl& m = *impl_;
  if (m.already_rectified) {
    *left_rect = left;
    *right_rect = right;
    return;
  }
  cv::remap(left, *left_rect, m.map_lx, m.map_ly, cv::INTER_LINEAR);
  cv::remap(right, *right_rect, m.map_rx, m.map_ry, cv::INTER_LINEAR);
}

}  // namespace uav::vision
