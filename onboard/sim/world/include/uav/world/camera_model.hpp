#pragma once
// Camera mounts on the vehicle, the laser emitter and the stereo rig; the lens model is
// uav::CameraIntrinsics (shared, as real cameras use it too). Frames (DESIGN.md 4): C = camera x-right y-down z-optical, B = body forward-right-down.
// Pixel centres sit at integer coordinates, as in OpenCV.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/frames.hpp"

namespace uav::world {

// A downward camera in the body frame: it looks along body z with the top of the image towards
// the nose (image width across the flight direction, as the survey planner assumes). A forward
// camera is uav::RotationBCForward (shared/frames.hpp).
Eigen::Matrix3d RotationBCDownward();

// Green laser with a diffraction grating in the middle of the stereo rig (thesis 4.2): a
// rows x cols grid of beams about the emitter's z axis (parallel to the optical axes).
struct LaserEmitter {
  bool enabled = false;
  int rows = 15;
  int cols = 15;
  double pitch_rad = 0.026;        // angle between neighbouring beams
  double spot_radius_m = 0.002;    // beam radius at the emitter
  double divergence_rad = 0.0008;  // growth of the spot radius per metre of range
  double intensity = 255.0;        // peak added brightness [DN]
  // The grating turned about the beam axis: a grid square to the image rows puts whole rows of
  // dots on one epipolar line, where a stereo search cannot tell them apart (thesis 4.3.2).
  double roll_rad = 0.0;
  int beam_count() const { return enabled ? rows * cols : 0; }
  // Unit direction of beam i (row-major) in the emitter frame (z forward like a camera).
  Eigen::Vector3d BeamDirection(int i) const;
};

// A camera as mounted and operated on the vehicle.
struct CameraSetup {
  std::string name;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();  // camera pose in the body frame
  double rate_hz = 5.0;        // frame rate on the simulated clock
  double preview_rate_hz = 5.0;  // JPEG previews to the GCS (<= rate_hz; 0: none)
  double noise_sigma = 2.0;    // [DN] Gaussian read noise per channel
  double exposure_s = 0.004;   // shutter time; used for motion blur
  int blur_samples = 1;        // > 1: average this many poses across the shutter time
  int supersample = 1;         // n x n samples per pixel (anti-aliasing)
  bool auto_exposure = true;   // gain brings the frame mean to target_mean
  double target_mean = 0.45;   // auto-exposure target, fraction of full scale
};

// Forward stereo pair (thesis 3.2: baseline 0.12 m) with the laser emitter between the cameras.
// The right camera sits baseline_m along the left camera's x axis; both share intrinsics and
// orientation, so the pair is rectified and disparity = fx * baseline / depth.
struct StereoSetup {
  CameraSetup left;
  CameraSetup right;
  double baseline_m = 0.12;
  LaserEmitter laser;
  Eigen::Isometry3d T_BE = Eigen::Isometry3d::Identity();  // emitter pose in the body frame
  // Pose of the right camera in the left camera frame (what a stereo matcher needs).
  Eigen::Isometry3d T_LR() const { return left.T_BC.inverse() * right.T_BC; }
};

// Builds a stereo setup: left/right poses from the rig centre pose T_B_rig (camera axes) and the
// baseline; the emitter sits at the rig centre with the same orientation.
StereoSetup MakeStereoSetup(const CameraSetup& camera, const Eigen::Isometry3d& T_B_rig,
                            double baseline_m, const LaserEmitter& laser);

}  // namespace uav::world
