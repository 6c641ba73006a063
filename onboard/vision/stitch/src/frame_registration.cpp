#include "uav/vision/frame_registration.hpp"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/features2d.hpp>
#include <opencv2/flann.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

#include "homography.hpp"

namespace uav::vision {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("frame registration: " + what);
}
}  // namespace

Detector ParseDetector(const std::string& name) {
  if (name == "gftt") return Detector::kGfttKlt;
  if (name == "orb") return Detector::kFastOrb;
  if (name == "sift") return Detector::kSiftFlann;
  if (name == "asift") return Detector::kAsift;
  throw std::invalid_argument("detector must be gftt, orb, sift or asift, got '" + name + "'");
}

const char* DetectorName(Detector d) {
  switch (d) {
    case Detector::kGfttKlt: return "gftt";
    case Detector::kFastOrb: return "orb";
    case Detector::kSiftFlann: return "sift";
    case Detector::kAsift: return "asift";
  }
  return "?";
}

struct FrameRegistration::Impl {
  cv::Ptr<cv::FastFeatureDetector> fast;
  cv::Ptr<cv::ORB> orb;
  cv::Ptr<cv::SIFT> sift;
  cv::Ptr<cv::DescriptorMatcher> matcher;
};

FrameRegistration::~FrameRegistration() = default;
FrameRegistration::FrameRegistration(FrameRegistration&&) noexcept = default;

FrameRegistration::FrameRegistration(const RegistrationParams& p) : impl_(std::make_unique<Impl>()), params_(p) {
  Require(p.max_corners >= 8 && p.max_corners <= 10000, "max_corners must be 8..10000");
  Require(p.corner_quality > 0 && p.corner_quality < 1, "corner_quality must be in (0, 1)");
  Require(p.corner_spacing_px >= 1, "corner_spacing_px must be at least 1");
  Require(p.klt_window_px >= 5 && p.klt_window_px <= 101, "klt_window_px must be 5..101");
  Require(p.klt_levels >= 0 && p.klt_levels <= 8, "klt_levels must be 0..8");
  Require(p.ransac_threshold_px > 0 && p.ransac_threshold_px < 50, "ransac_threshold_px must be in (0, 50)");
  Require(p.min_inliers >= 4, "min_inliers must be at least 4");
  Require(p.max_area_change > 0 && p.max_area_change <= 10, "max_area_change must be in (0, 10]");
  Require(p.max_translation_fraction > 0 && p.max_translation_fraction <= 1, "max_translation_fraction must be in (0, 1]");
  switch (p.detector) {
    case Detector::kGfttKlt:
      break;
    // Descriptor matching keeps a fraction of its keypoints where tracking keeps most, so the
    // descriptor detectors take four times the corners (measured on the village: SIFT with 400
    // keypoints kept 43 inliers and a 6.9 px error, with 1600 about 180 inliers and 0.1 px).
    case Detector::kFastOrb:
      impl_->fast = cv::FastFeatureDetector::create(10, true);
      impl_->orb = cv::ORB::create(4 * p.max_corners);
      impl_->matcher = cv::BFMatcher::create(cv::NORM_HAMMING, /*crossCheck=*/true);
      break;
    case Detector::kSiftFlann:
      impl_->sift = cv::SIFT::create(4 * p.max_corners);
      impl_->matcher = cv::FlannBasedMatcher::create();
      break;
    case Detector::kAsift:
      impl_->sift = cv::SIFT::create();
      impl_->matcher = cv::FlannBasedMatcher::create();
      break;
  }
}

namespace {
// ASIFT's view simulation: for tilts t = 2^(i/2), i = 0..5, and rotations phi in steps of
// 72 deg / t, rotate the image, blur and squeeze it by t along x (a camera tilt), detect SIFT
// there and map the keypoints back into the image.
void AffineSift(const cv::Ptr<cv::SIFT>& sift, const cv::Mat& image, std::vector<cv::KeyPoint>* keypoints,
                cv::Mat* descriptors) {
  std::vector<cv::Mat> all;
  for (int ti = 0; ti <= 5; ++ti) {
    const double t = std::pow(2.0, 0.5 * ti);
    for (double phi = 0; phi < 180; phi += ti == 0 ? 180 : 72.0 / t) {
      cv::Mat A = cv::Mat::eye(2, 3, CV_64F), view = image;
      if (phi != 0) {
        const double s = std::sin(phi * CV_PI / 180), c = std::cos(phi * CV_PI / 180);
        const cv::Mat R = (cv::Mat_<double>(2, 2) << c, -s, s, c);
        std::vector<cv::Point2f> corners = {{0, 0}, {float(image.cols), 0}, {float(image.cols), float(image.rows)}, {0, float(image.rows)}};
        cv::transform(corners, corners, R);
        const cv::Rect box = cv::boundingRect(corners);
        const cv::Mat offset = (cv::Mat_<double>(2, 1) << -box.x, -box.y);
        cv::hconcat(R, offset, A);
        cv::warpAffine(image, view, A, box.size(), cv::INTER_LINEAR, cv::BORDER_REPLICATE);
      }
      if (t != 1) {
        cv::GaussianBlur(view, view, cv::Size(0, 0), 0.8 * std::sqrt(t * t - 1), 0.01);
        cv::resize(view, view, cv::Size(0, 0), 1.0 / t, 1.0, cv::INTER_NEAREST);
        A.row(0) /= t;
      }
      std::vector<cv::KeyPoint> k;
      cv::Mat d;
      sift->detectAndCompute(view, cv::noArray(), k, d);
      cv::Mat back;
      cv::invertAffineTransform(A, back);
      const double* b = back.ptr<double>();
      for (cv::KeyPoint& kp : k) {
        const cv::Point2f q = kp.pt;
        kp.pt = cv::Point2f(static_cast<float>(b[0] * q.x + b[1] * q.y + b[2]), static_cast<float>(b[3] * q.x + b[4] * q.y + b[5]));
        keypoints->push_back(kp);
      }
      if (!d.empty()) all.push_back(d);
    }
  }
  if (!all.empty()) cv::vconcat(all, *descriptors);
}

// Keeps the strongest `n` keypoints.
void Strongest(std::vector<cv::KeyPoint>* k, int n) {
  if (static_cast<int>(k->size()) <= n) return;
  std::nth_element(k->begin(), k->begin() + n, k->end(),
                   [](const cv::KeyPoint& a, const cv::KeyPoint& b) { return a.response > b.response; });
  k->resize(n);
}
}  // namespace

FrameFeatures FrameRegistration::Features(const cv::Mat& grey) const {
  Require(!grey.empty(), "empty image");
  Require(grey.type() == CV_8UC1, "images must be 8-bit grey");
  FrameFeatures f;
  switch (params_.detector) {
    case Detector::kGfttKlt:
      cv::goodFeaturesToTrack(grey, f.points, params_.max_corners, params_.corner_quality, params_.corner_spacing_px);
      return f;
    case Detector::kFastOrb:
      impl_->fast->detect(grey, f.keypoints);
      Strongest(&f.keypoints, 4 * params_.max_corners);
      impl_->orb->compute(grey, f.keypoints, f.descriptors);
      break;
    case Detector::kSiftFlann:
      impl_->sift->detectAndCompute(grey, cv::noArray(), f.keypoints, f.descriptors);
      break;
    case Detector::kAsift:
      AffineSift(impl_->sift, grey, &f.keypoints, &f.descriptors);
      break;
  }
  for (const cv::KeyPoint& k : f.keypoints) f.points.push_back(k.pt);
  return f;
}

Registration FrameRegistration::Register(const cv::Mat& prev, const cv::Mat& cur) const {
  Require(!prev.empty() && !cur.empty(), "empty image");
  return Register(prev, Features(prev), cur);
}

FeatureMatches FrameRegistration::Match(const cv::Mat& prev, const FrameFeatures& features, const cv::Mat& cur) const {
  Require(!prev.empty() && !cur.empty(), "empty image");
  Require(prev.type() == CV_8UC1 && cur.type() == CV_8UC1, "images must be 8-bit grey");
  Require(prev.size() == cur.size(), "images must have the same size");
  Require(features.keypoints.empty() || (features.keypoints.size() == features.points.size() &&
                                         features.descriptors.rows == static_cast<int>(features.points.size())),
          "features must have one keypoint and descriptor per point");
  FeatureMatches r;
  std::vector<cv::Point2f>& a = r.cur;
  std::vector<cv::Point2f>& b = r.prev;
  r.corners = static_cast<int>(features.points.size());
  if (params_.detector == Detector::kGfttKlt) {
    if (r.corners < params_.min_inliers) {
      r.failure = "too few corners (" + std::to_string(r.corners) + ")";
      return r;
    }
    std::vector<cv::Point2f> p_cur;
    std::vector<uchar> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(prev, cur, features.points, p_cur, status, error,
                             cv::Size(params_.klt_window_px, params_.klt_window_px), params_.klt_levels);
    for (size_t i = 0; i < status.size(); ++i)
      if (status[i]) {
        a.push_back(p_cur[i]);
        b.push_back(features.points[i]);
      }
  } else {
    // Keypoints and descriptors in the current frame too, then matching (brute force with
    // cross-check for ORB's binary descriptors; FLANN with Lowe's ratio test for SIFT).
    const FrameFeatures current = Features(cur);
    if (r.corners < params_.min_inliers || static_cast<int>(current.points.size()) < params_.min_inliers) {
      r.failure = "too few corners (" + std::to_string(std::min(features.points.size(), current.points.size())) + ")";
      return r;
    }
    if (params_.detector == Detector::kFastOrb) {
      std::vector<cv::DMatch> matches;
      impl_->matcher->match(current.descriptors, features.descriptors, matches);
      for (const cv::DMatch& m : matches) {
        a.push_back(current.points[m.queryIdx]);
        b.push_back(features.points[m.trainIdx]);
      }
    } else {
      // Lowe's ratio test against the nearest neighbour elsewhere in the image: ASIFT finds
      // a point again in several simulated views, and those copies are not rivals.
      std::vector<std::vector<cv::DMatch>> knn;
      {
        // FLANN's randomised trees draw from the thread's RNG: from a fixed state, the same
        // frames give the same matches whatever ran before on this thread.
        const cv::RNG caller_rng = cv::theRNG();
        cv::theRNG() = cv::RNG();
        impl_->matcher->knnMatch(current.descriptors, features.descriptors, knn, 4);
        cv::theRNG() = caller_rng;
      }
      for (const auto& m : knn) {
        if (m.empty()) continue;
        const cv::Point2f best = features.points[m[0].trainIdx];
        for (size_t j = 1; j < m.size(); ++j) {
          if (cv::norm(features.points[m[j].trainIdx] - best) <= 2.0f) continue;
          if (m[0].distance < 0.75f * m[j].distance) {
            a.push_back(current.points[m[0].queryIdx]);
            b.push_back(best);
          }
          break;
        }
      }
    }
  }
  if (static_cast<int>(a.size()) < params_.min_inliers) r.failure = "too few corners tracked (" + std::to_string(a.size()) + ")";
  return r;
}

Registration FrameRegistration::Register(const cv::Mat& prev, const FrameFeatures& features, const cv::Mat& cur) const {
  Registration r;
  const FeatureMatches m = Match(prev, features, cur);
  r.corners = m.corners;
  r.tracked = static_cast<int>(m.prev.size());
  r.failure = m.failure;
  if (!r.failure.empty()) return r;
  const std::vector<cv::Point2f>& a = m.cur;
  const std::vector<cv::Point2f>& b = m.prev;
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
  const Eigen::Vector2d c[4] = {Apply(r.H_prev_cur, {0, 0}), Apply(r.H_prev_cur, {w, 0}), Apply(r.H_prev_cur, {w, h}),
                                Apply(r.H_prev_cur, {0, h})};
  double area2 = 0;
  for (int i = 0; i < 4; ++i) area2 += c[i].x() * c[(i + 1) % 4].y() - c[(i + 1) % 4].x() * c[i].y();
  r.area_ratio = 0.5 * area2 / (w * h);
  r.translation_px = (Apply(r.H_prev_cur, {w / 2, h / 2}) - Eigen::Vector2d(w / 2, h / 2)).norm();
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
