#pragma once
// What the vision threads see of the cameras: a mono camera and a stereo pair, each with its
// calibration and mount, giving an image on request at the vehicle clock's time. Three back-ends
// sit behind it: the simulator's renderer (sim/sim_cameras.hpp), recordings
// (runtime/recorded_sensors.hpp) and live devices (runtime/live_camera.hpp). A camera with no
// usable image gives an empty one and says why in problem(). Included only by the camera
// workers, so OpenCV stays out of the widely included headers.
#include <cmath>
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
  // The image exposed at `utime` (empty when the camera has none: see problem()).
  virtual CameraFrame Capture(int64_t utime) = 0;
  // Why the camera gives no usable image now ("" while it does): a device that stopped or
  // stalled, a recording that ended, a frame that could not be read. Thread-safe.
  virtual std::string problem() const { return ""; }
};

// A camera on a two-axis stabilised gimbal: the gimbal holds it level in roll and sets its pitch;
// it turns with the body's heading. At pitch 0 it looks along the heading, at -pi/2 straight
// down. info().T_BC is the mount at pitch 0 with the body level.
class GimbalCamera : public Camera {
 public:
  static constexpr double kMinPitchRad = -1.5707963267948966;  // straight down
  static constexpr double kMaxPitchRad = 0.3490658503988659;   // 20 degrees up
  // Sets the pitch, clamped to [kMinPitchRad, kMaxPitchRad]; a non-finite value is ignored.
  virtual void SetPitch(double pitch_rad) = 0;
  virtual double pitch_rad() const = 0;
};

// The gimballed camera's pose in N for a body pose T_NB, its level mount T_BC_level (pitch 0)
// and pitch: R_NC = R_z(heading) R_y(pitch) R_BC_level, at the mount point carried by the body.
inline Eigen::Isometry3d GimbalCameraPose(const Eigen::Isometry3d& T_NB, const Eigen::Isometry3d& T_BC_level, double pitch_rad) {
  const Eigen::Matrix3d R_NB = T_NB.linear();
  const double heading = std::atan2(R_NB(1, 0), R_NB(0, 0));
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()).toRotationMatrix() *
                  Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()).toRotationMatrix() * T_BC_level.linear();
  T_NC.translation() = T_NB * T_BC_level.translation();
  return T_NC;
}

struct StereoImages {
  cv::Mat left, right;  // CV_8UC3, BGR, same size
  int64_t left_utime = 0, right_utime = 0;  // [us] each camera's exposure (a pair is synchronised)
  // Where the body really was (simulation only, to measure against; hardware has none).
  std::optional<Eigen::Isometry3d> truth_T_NB;
};

// A rig with a laser dot projector (thesis 4.2) exposes with the projector on or off, as the
// emitter on/off mode of real active rigs does: the dots give features to the active stereo and
// to block matching on plain walls, but they move with the camera, so visual odometry, which
// must see only the world, takes its pairs dark. A rig without a projector ignores it.
enum class Emitter { kOn, kOff };

class StereoCamera {
 public:
  virtual ~StereoCamera() = default;
  virtual const CameraInfo& left() const = 0;
  virtual const CameraInfo& right() const = 0;
  // Pose of the right camera in the left camera's frame (what a stereo matcher needs).
  Eigen::Isometry3d T_LR() const { return left().T_BC.inverse() * right().T_BC; }
  // Empty images when the pair has none (see problem()).
  virtual StereoImages Capture(int64_t utime, Emitter emitter) = 0;
  // As Camera::problem().
  virtual std::string problem() const { return ""; }
};

}  // namespace uav::hal
