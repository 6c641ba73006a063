#pragma once
// Pinhole camera with OpenCV's Brown-Conrady distortion (k1 k2 p1 p2 k3): the lens model every
// camera uses, simulated or real (the simulator renders through it, vision algorithms undistort
// with it). Frame C: x right, y down, z along the optical axis. Pixel centres sit at integer
// coordinates, as in OpenCV.
#include <array>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"

namespace uav {

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

}  // namespace uav
