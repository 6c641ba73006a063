#pragma once
// Frame-to-frame registration of the downward camera (thesis 6.2-6.3, Algorithm 1): good
// features to track in the previous frame, pyramidal Lucas-Kanade tracking into the current
// one, a homography by RANSAC refined by Levenberg-Marquardt on the inliers (Eq. 6.1-6.3), and
// the failure checks of Algorithm 1 (area change beyond +-20 %, translation beyond half the
// image diagonal). The stitcher chains the result (Eq. 6.4) and falls back to the navigation
// solution when a check fails. A plain class: grey images in, homography out.
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>
#include <opencv2/core/types.hpp>

namespace uav::vision {

// How corners are found and paired (the study of thesis Table 6.1).
enum class Detector {
  kGfttKlt,   // good features to track, followed by pyramidal Lucas-Kanade (the thesis's choice)
  kFastOrb,   // FAST corners with ORB descriptors, brute-force Hamming matching
  kSiftFlann,  // SIFT keypoints and descriptors, FLANN kd-tree matching
  kAsift       // SIFT on affine-simulated views of both frames (Morel and Yu's ASIFT, as OpenCV's
               // asift sample): for oblique pairs with large viewpoint change; seconds per pair
};
// "gftt", "orb", "sift", "asift"; throws std::invalid_argument naming the choices.
Detector ParseDetector(const std::string& name);
const char* DetectorName(Detector d);

struct RegistrationParams {
  Detector detector = Detector::kGfttKlt;
  int max_corners = 400;           // corners (keypoints) in the previous frame
  double corner_quality = 0.01;    // relative to the strongest corner
  double corner_spacing_px = 10;   // minimum distance between corners
  int klt_window_px = 21;          // Lucas-Kanade window
  int klt_levels = 3;              // pyramid levels above the image
  double ransac_threshold_px = 2.0;
  int min_inliers = 30;
  double max_area_change = 0.20;           // Algorithm 1: |area ratio - 1|
  double max_translation_fraction = 0.5;   // Algorithm 1: of the image diagonal
};

struct Registration {
  bool ok = false;
  std::string failure;  // why not, for the report and the operator
  // Maps a pixel of the current frame to the previous frame (homogeneous, H(2,2) = 1).
  Eigen::Matrix3d H_prev_cur = Eigen::Matrix3d::Identity();
  int corners = 0;      // found in the previous frame
  int tracked = 0;      // followed (or matched) into the current frame
  int inliers = 0;      // agreeing with the homography
  double area_ratio = 1.0;      // area of the current frame's outline mapped into the previous
  double translation_px = 0.0;  // displacement of the image centre
  // Every tracked corner in each frame, and whether it agrees with the homography. Over 3-D
  // structure the homography follows the dominant plane, which need not be the ground.
  std::vector<cv::Point2f> tracked_prev, tracked_cur;
  std::vector<uint8_t> inlier;
};

// What registration finds in a frame before pairing it: corners (gftt, strongest first) or
// keypoints with descriptors. Found once per frame and used against each partner.
struct FrameFeatures {
  std::vector<cv::Point2f> points;       // the corners, or the keypoints' positions
  std::vector<cv::KeyPoint> keypoints;   // descriptor detectors only
  cv::Mat descriptors;                   // one row per keypoint; descriptor detectors only
  // The features whose points pass `keep`, in order, at most `most` of them.
  template <class Keep>
  FrameFeatures Select(Keep keep, size_t most) const {
    FrameFeatures out;
    for (size_t i = 0; i < points.size() && out.points.size() < most; ++i) {
      if (!keep(points[i])) continue;
      out.points.push_back(points[i]);
      if (!keypoints.empty()) {
        out.keypoints.push_back(keypoints[i]);
        out.descriptors.push_back(descriptors.row(static_cast<int>(i)));
      }
    }
    return out;
  }
};

// Features of one frame followed (KLT) or matched (descriptors) into another, before any model.
struct FeatureMatches {
  int corners = 0;                           // features given in the first frame
  std::vector<cv::Point2f> prev, cur;        // the pairs, index by index
  std::string failure;                       // non-empty: too few features or pairs to register
};

class FrameRegistration {
 public:
  // Throws std::invalid_argument naming a bad parameter.
  explicit FrameRegistration(const RegistrationParams& params = RegistrationParams());
  ~FrameRegistration();
  FrameRegistration(FrameRegistration&&) noexcept;
  // The features of an 8-bit grey image. Throws std::invalid_argument for an empty or non-grey
  // image.
  FrameFeatures Features(const cv::Mat& grey) const;
  // 8-bit grey images of the same size; prev's features are found first. Throws
  // std::invalid_argument for empty, mismatched or non-grey images; a registration that fails
  // its checks returns ok = false with the reason.
  Registration Register(const cv::Mat& prev_grey, const cv::Mat& cur_grey) const;
  // The same with prev's features already found (by Features on prev_grey, or a Select of them).
  Registration Register(const cv::Mat& prev_grey, const FrameFeatures& prev_features, const cv::Mat& cur_grey) const;
  // The pairs only, without the homography and its checks (for a caller that sorts the pairs
  // itself, as the alignment's ground gate does).
  FeatureMatches Match(const cv::Mat& prev_grey, const FrameFeatures& prev_features, const cv::Mat& cur_grey) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  RegistrationParams params_;
};

}  // namespace uav::vision
