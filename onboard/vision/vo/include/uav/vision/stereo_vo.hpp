#pragma once
// Stereo visual odometry (thesis ch. 5): KLT features on a rectified pair, triangulated from
// left to right, tracked from a keyframe to each new frame, and the camera's motion from them by
// the rigid 3D-3D method (5.3.1, Eq. 5.1-5.8) or by PnP / EPnP (5.3.2, Eq. 5.9-5.19), inside
// RANSAC (5.4, Eq. 5.20) and refined by Levenberg-Marquardt (5.5, Eq. 5.21); the poses are
// chained (5.6, Eq. 5.22-5.31) through keyframes, so that a hovering camera, which keeps seeing
// its keyframe, does not drift. Plain class, fed rectified images; OpenCV stays in the .cpp.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

enum class VoMethod { kPnp, kEpnp, kRigid };
const char* Name(VoMethod m);                        // "pnp", "epnp", "rigid"
std::optional<VoMethod> ParseVoMethod(std::string_view name);

struct VoParams {
  VoMethod method = VoMethod::kPnp;
  // Features (thesis 5.2): Shi-Tomasi corners, the border masked, at least 15 px apart.
  int max_features = 400;
  double min_distance_px = 15.0;
  int border_px = 16;
  double corner_quality = 0.005;     // of the strongest corner in each cell ...
  int feature_grid = 4;              // ... of a feature_grid x feature_grid grid
  int lk_window_px = 21, lk_levels = 3;
  double lk_fb_tol_px = 1.0;         // forward-backward disagreement that drops a track
  double epipolar_tol_px = 1.0;      // rectified row difference allowed between left and right
  // The working range (thesis 5.10, item 3: far points carry errors that grow with the square of
  // the range): a point is used while its depth's 1 sigma (thesis 3.2, sigma_Z = Z^2 sigma_d / f b)
  // is at most max_depth_error of its depth.
  double disparity_sigma_px = 0.2;
  double max_depth_error = 0.05;
  double min_depth_m = 0.3;
  // The rig's disparity offset (true disparity = matched + offset; a residual of the calibration,
  // such as principal points a tenth of a pixel apart) is estimated from the motion, starting
  // from 0 with this sigma (0: taken as exactly 0, not estimated), the estimate's sigma kept at
  // or above the minimum so that it follows a calibration that shifts in flight (PnP and EPnP).
  // A keyframe's measurement of it counts only when its sigma is at most
  // disparity_offset_measurement_sigma_px (the points span enough depths and the camera moved).
  double disparity_offset_prior_sigma_px = 0.2;
  double disparity_offset_min_sigma_px = 0.01;
  double disparity_offset_measurement_sigma_px = 0.1;
  // RANSAC (thesis 5.4): N from Eq. 5.20 with p, updated as the outlier share is learnt, capped;
  // it stops early once the consensus holds `consensus` of the points (step 4).
  double ransac_p = 0.99;
  double ransac_initial_outliers = 0.5;
  int ransac_max_iterations = 300;
  double consensus = 0.9;
  double reprojection_tol_px = 1.5;  // PnP inlier test
  double rigid_tol_sigma = 3.0;      // rigid inlier test, in the pair's combined depth sigma
  // Health and keyframes.
  int min_inliers = 15;              // fewer: the motion is not trusted, the frame is unhealthy
  int keyframe_min_inliers = 200;    // a new keyframe once fewer inliers than this remain (if it had more) ...
  double keyframe_min_fraction = 0.5;  // ... or fewer than this share of the keyframe's points
  // Gyro-aided motion (a pair carrying R_XC): the IMU's attitude enters the refinement as a prior
  // on the rotation, with the pair's covariance plus this sigma on each axis (the reprojections
  // count with track_sigma_px), and RANSAC samples further than the gate from it are not tried.
  // Over plain ground (all points near one depth) a sideways motion and a tilt move the image
  // alike, and vision alone trades one for the other: a climb to 20 m with the camera 3 degrees
  // off the vertical read as a metre of sideways motion without the prior.
  double imu_rotation_sigma_rad = 0.001;
  double imu_rotation_gate_rad = 0.05;
  double track_sigma_px = 0.3;
  double max_sync_skew_s = 0.002;    // left and right exposed further apart: not a pair
  double max_gap_s = 1.0;            // frames further apart: the track restarts
  double min_contrast_dn = 3.0;      // grey standard deviation below this: blank or dark
  void Validate() const;             // throws std::invalid_argument naming the field
};

struct VoResult {
  bool healthy = false;
  std::string reason;  // why not healthy ("" when healthy)
  // The rectified left camera's pose in the odometry frame W (the first frame, camera axes: x
  // right, y down, z forward) and in the current keyframe.
  Eigen::Isometry3d T_WC = Eigen::Isometry3d::Identity();
  Eigen::Isometry3d T_KC = Eigen::Isometry3d::Identity();
  // A segment is one unbroken chain of poses. After a frame gap or a lost track a new one starts
  // from the last pose known: the motion in between is missing, so a consumer that fuses the
  // poses re-anchors when the number changes.
  int segment = 0;
  bool new_keyframe = false;
  int keyframe_points = 0;   // points with depth in the keyframe
  int tracked = 0;           // of them, tracked into this frame
  int inliers = 0;           // RANSAC consensus after refinement
  int ransac_iterations = 0;
  double rms_px = 0.0;       // reprojection RMS of the inliers after refinement
  double disparity_offset_px = 0.0;        // the rig's disparity offset as estimated so far ...
  double disparity_offset_sigma_px = 0.0;  // ... and its sigma (0 when it is not estimated)
};

// One pair: rectified images (8-bit grey or BGR) with each camera's exposure time.
struct RectifiedPair {
  cv::Mat left, right;
  int64_t left_utime = 0, right_utime = 0;  // [us]
  // The rectified left camera's attitude in any frame X fixed to the world, from the IMU (the
  // INS's R_NB times the camera's mounting), where one is fed, and its covariance [rad^2] as a
  // small rotation in the camera's frame (R_XC(true) = R_XC Exp(dth_C)); VoParams's
  // imu_rotation_sigma_rad is added on each axis. Without R_XC the rotation comes from the
  // images alone.
  std::optional<Eigen::Matrix3d> R_XC;
  Eigen::Matrix3d R_XC_covariance = Eigen::Matrix3d::Zero();
};

class StereoVo {
 public:
  // Throws std::invalid_argument for bad parameters or geometry.
  StereoVo(const RectifiedGeometry& geometry, const VoParams& params);
  ~StereoVo();
  StereoVo(StereoVo&&) noexcept;

  // Never throws for a bad pair: it comes back unhealthy with the reason (sizes that do not fit
  // the calibration, an unsynchronised pair, a blank or dark image, too few features or matches,
  // RANSAC without consensus) and the pose stays where it was.
  VoResult Process(const RectifiedPair& pair);
  const RectifiedGeometry& geometry() const;
  const VoParams& params() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Eq. 5.20: RANSAC trials for probability p that one sample of s points is free of outliers,
// when a share `outliers` of the points are outliers.
int RansacIterations(double p, double outliers, int s);

// Rigid motion between matched 3-D point sets (thesis 5.3.1, Eq. 5.1-5.8): the R, t that minimise
// sum w_i |R p_i + t - q_i|^2, by the SVD of the weighted cross-covariance. Needs 3 points not on
// one line; returns false otherwise.
bool RigidMotion(const Eigen::Matrix3Xd& P, const Eigen::Matrix3Xd& Q, const Eigen::VectorXd& w,
                 Eigen::Isometry3d* T_QP);

}  // namespace uav::vision
