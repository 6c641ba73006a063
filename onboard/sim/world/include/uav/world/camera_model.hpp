#pragma once
// Pinhole camera with OpenCV's Brown-Conrady distortion (k1 k2 p1 p2 k3) and camera mounts on the
// vehicle. Frames (DESIGN.md 4): C = camera x-right y-down z-optical, B = body forward-right-down.
// Pixel centres sit at integer coordinates, as in OpenCV.
#include <array>
#include <string>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/shared/parameters.hpp"

namespace uav::world {

struct CameraIntrinsics {
  int width = 640;
  int height = 480;
  double fx = 500.0;  // [px]
  double fy = 500.0;  // [px]
  double cx = 319.5;  // [px]
  double cy = 239.5;  // [px]
  std::array<double, 5> distortion{};  // k1 k2 p1 p2 k3 (OpenCV order)
};

// Throws std::invalid_argument naming the field: sizes 16..20000, focal lengths positive,
// principal point inside the image, distortion finite with |k| < 10.
void ValidateIntrinsics(const CameraIntrinsics& k);

// From a camera file (resources/cameras/*.camera): image_width_px, image_height_px and
// focal_length_mm / sensor_width_mm / sensor_height_mm, optionally cx_px, cy_px and k1 k2 p1 p2 k3.
CameraIntrinsics IntrinsicsFromParameters(const ParameterSet& p);

// Pixel of the camera-frame point p_C (z > 0), distortion applied.
Eigen::Vector2d Project(const CameraIntrinsics& k, const Eigen::Vector3d& p_C);
// Normalised undistorted image coordinates (x/z, y/z) of pixel (u, v); the inverse of Project,
// iterated to 1e-12.
Eigen::Vector2d Unproject(const CameraIntrinsics& k, const Eigen::Vector2d& uv);

// Camera orientations in the body frame. A downward camera looks along body z with the top of
// the image towards the nose (image width across the flight direction, as the survey planner
// assumes); a forward camera looks along body x (thesis Eq. 5.48).
Eigen::Matrix3d RotationBCDownward();
Eigen::Matrix3d RotationBCForward();

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
  int beam_count() const { return enabled ? rows * cols : 0; }
  // Unit direction of beam i (row-major) in the emitter frame (z forward like a camera).
  Eigen::Vector3d BeamDirection(int i) const;
};

// A camera as mounted and operated on the vehicle.
struct CameraSetup {
  std::string name;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();  // camera pose in the body frame
  double rate_hz = 5.0;        // capture rate on the simulated clock
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
};

// Builds a stereo setup: left/right poses from the rig centre pose T_B_rig (camera axes) and the
// baseline; the emitter sits at the rig centre with the same orientation.
StereoSetup MakeStereoSetup(const CameraSetup& camera, const Eigen::Isometry3d& T_B_rig,
                            double baseline_m, const LaserEmitter& laser);

}  // namespace uav::world
