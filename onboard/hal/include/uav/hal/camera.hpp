#pragma once
// What the vision threads see of the cameras: a mono camera and a stereo pair, each with its
// calibration and mount, giving an image on request at the vehicle clock's time. The simulator
// renders behind this interface (sim/sim_cameras.hpp), as the vehicle model sits behind
// VehicleBackend; hardware drivers come later behind the same one. Included only by the camera
// workers, so OpenCV stays out of the widely included headers.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/shared/camera_intrinsics.hpp"

namespace uav::hal {

struct CameraInfo {
  std::string name;
  CameraIntrinsics intrinsics;
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();  // camera pose in the body frame
  double rate_hz = 5.0;          // frames per second on the vehicle clock
  double preview_rate_hz = 5.0;  // JPEG previews for the GCS (<= rate_hz; 0: none)
};

struct CameraFrame {
  cv::Mat image;  // CV_8UC3, BGR, the calibration's size
  // Where the body really was (simulation only, to measure against; hardware has none).
  std::optional<Eigen::Isometry3d> truth_T_NB;
};

class Camera {
 public:
  virtual ~Camera() = default;
  virtual const CameraInfo& info() const = 0;
  // The image exposed at `utime`.
  virtual CameraFrame Capture(int64_t utime) = 0;
};

struct StereoImages {
  cv::Mat left, right;  // CV_8UC3, BGR, same size
};

class StereoCamera {
 public:
  virtual ~StereoCamera() = default;
  virtual const CameraInfo& left() const = 0;
  virtual const CameraInfo& right() const = 0;
  // Pose of the right camera in the left camera's frame (what a stereo matcher needs).
  Eigen::Isometry3d T_LR() const { return left().T_BC.inverse() * right().T_BC; }
  virtual StereoImages Capture(int64_t utime) = 0;
};

}  // namespace uav::hal
