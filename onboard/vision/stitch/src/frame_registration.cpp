#include "uav/vision/frame_registration.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace uav::vision {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("frame registration: " + what);
}
Eigen::Vector2d Apply(const Eigen::Matrix3d& H, double u, double v) {
  const Eigen::Vector3d p = H * Eigen::Vector3d(u, v, 1.0);
  return p.head<2>() / p.z();
}
}  // namespace

FrameRegistration::FrameRegistration(const RegistrationParams& p) : params_(p) {
  Require(p.max_corners >= 8 && p.max_corners <= 10000, "max_corners must be 8..10000");
  Require(p.corner_quality > 0 && p.corner_quality < 1, "corner_quality must be in (0, 1)");
  Require(p.corner_spacing_px >= 1, "corner_spacing_px must be at least 1");
  Require(p.klt_window_px >= 5 && p.klt_window_px <= 101, "klt_window_px must be 5..101");
  Require(p.klt_levels >= 0 && p.klt_levels <= 8, "klt_levels must be 0..8");
  Require(p.ransac_threshold_px > 0 && p.ransac_threshold_px < 50, "ransac_threshold_px must be in (0, 50)");
  Require(p.min_inliers >= 4, "min_inliers must be at least 4");
  Require(p.max_area_change > 0 && p.max_area_change < 1, "max_area_change must be in (0, 1)");
  Require(p.max_translation_fraction > 0 && p.max_translation_fraction <= 1, "max_translation_fraction must be in (0, 1]");
}

Registration FrameRegistration::Register(const cv::Mat& prev, const cv::Mat& cur) const {
  Require(!prev.empty() && !cur.empty(), "empty image");
  Require(prev.type() == CV_8UC1 && cur.type() == CV_8UC1, "images must be 8-bit grey");
  Require(prev.size() == cur.size(), "images must have the same size");
  Registration r;
  std::vector<cv::Point2f> p_prev, p_cur;
  cv::goodFeaturesToTrack(prev, p_prev, params_.max_corners, params_.corner_quality, params_.corner_spacing_px);
  r.corners = static_cast<int>(p_prev.size());
  if (r.corners < params_.min_inliers) {
    r.failure = "too few corners (" + std::to_string(r.corners) + ")";
    return r;
  }
  std::vector<uchar> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(prev, cur, p_prev, p_cur, status, error,
                           cv::Size(params_.klt_window_px, params_.klt_window_px), params_.klt_levels);
  std::vector<cv::Point2f> a, b;  // current -> previous
  for (size_t i = 0; i < status.size(); ++i)
    if (status[i]) {
      a.push_back(p_cur[i]);
      b.push_back(p_prev[i]);
    }
  r.tracked = static_cast<int>(a.size());
  if (r.tracked < params_.min_inliers) {
    r.failure = "too few corners tracked (" + std::to_string(r.tracked) + ")";
    return r;
  }
  // RANSAC, then OpenCV's Levenberg-Marquardt refinement on the inliers (Eq. 6.2-6.3).
  std::vector<uchar> inlier_mask;
  const cv::Mat H = cv::findHomography(a, b, cv::RANSAC, params_.ransac_threshold_px, inlier_mask, 2000, 0.999);
  if (H.empty()) {
    r.failure = "no homography";
    return r;
  }
  r.inliers = cv::countNonZero(inlier_mask);
  r.tracked_cur = a;
  r.tracked_prev = b;
  r.inlier.assign(inlier_mask.begin(), inlier_mask.end());
  cv::cv2eigen(H, r.H_prev_cur);
  r.H_prev_cur /= r.H_prev_cur(2, 2);
  // Algorithm 1's checks: the outline's area and the centre's displacement.
  const double w = cur.cols - 1, h = cur.rows - 1;
  const Eigen::Vector2d c[4] = {Apply(r.H_prev_cur, 0, 0), Apply(r.H_prev_cur, w, 0), Apply(r.H_prev_cur, w, h),
                                Apply(r.H_prev_cur, 0, h)};
  double area2 = 0;
  for (int i = 0; i < 4; ++i) area2 += c[i].x() * c[(i + 1) % 4].y() - c[(i + 1) % 4].x() * c[i].y();
  r.area_ratio = 0.5 * area2 / (w * h);
  r.translation_px = (Apply(r.H_prev_cur, w / 2, h / 2) - Eigen::Vector2d(w / 2, h / 2)).norm();
  if (r.inliers < params_.min_inliers) {
    r.failure = "too few inliers (" + std::to_string(r.inliers) + ")";
  } else if (!r.H_prev_cur.allFinite() || std::abs(r.area_ratio - 1.0) > params_.max_area_change) {
    r.failure = "area changed by " + std::to_string(static_cast<int>(std::lround((r.area_ratio - 1.0) * 100))) + " %";
  } else if (r.translation_px > params_.max_translation_fraction * std::hypot(w, h)) {
    r.failure = "translation of " + std::to_string(static_cast<int>(r.translation_px)) + " px";
  } else {
    r.ok = true;
  }
  return r;
}

}  // namespace uav::vision
