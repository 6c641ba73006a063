#pragma once
// A live camera behind hal::GimbalCamera: any source OpenCV's VideoCapture opens (a V4L2 device
// "/dev/video0" or "0", a GStreamer pipeline ending in appsink, an RTSP/RTP URL, a file), with
// its calibration. A thread of its own reads the device as fast as it delivers, as a driver
// does; the vision workers take the newest frame at their exposure time. Each frame is stamped
// with the driver's timestamp (CAP_PROP_POS_MSEC) where it gives an increasing one, else with
// the time it arrived.
//
// What goes wrong shows in problem(), and the sensing health with it: a device that cannot be
// opened or stops delivering (it is reopened every second), a stall (no new frame for
// `stall_s`), garbage (an empty frame, a size other than the calibration's, an image of one
// grey level), driver timestamps that repeat or go backwards (those frames are dropped). The
// vehicle's workers then see no image and say so; nothing waits on the device.
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/hal/camera.hpp"
#include "uav/shared/camera_intrinsics.hpp"

namespace uav::runtime {

class LiveCamera : public hal::GimbalCamera {
 public:
  struct Options {
    std::string name;
    std::string source;  // device path or index, pipeline or URL
    CameraIntrinsics intrinsics;
    Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
    double rate_hz = 30.0;  // what the workers are offered (the device may deliver more)
    double stall_s = 1.0;   // no new frame this long: stalled
  };
  // Opens the source. Throws std::runtime_error naming it when it cannot be opened or gives no
  // frame within `first_frame_s`: a rig that names a missing device refuses before the run.
  explicit LiveCamera(const Options& options, double first_frame_s = 5.0);
  ~LiveCamera() override;
  const hal::CameraInfo& info() const override { return info_; }
  hal::CameraFrame Capture(int64_t utime) override;
  std::string problem() const override;
  void SetPitch(double) override {}
  double pitch_rad() const override { return pitch_rad_; }
  // Frames delivered, and dropped as garbage or out of order, since start.
  int64_t frames() const { return frames_.load(); }
  int64_t rejected() const { return rejected_.load(); }

 private:
  void ReadLoop();

  Options options_;
  hal::CameraInfo info_;
  double pitch_rad_ = 0.0;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> frames_{0}, rejected_{0};
  mutable std::mutex mutex_;
  cv::Mat newest_;               // the newest good frame
  int64_t newest_wall_us_ = -1;  // when it arrived (steady clock)
  double last_driver_ms_ = -1.0;
  std::string device_problem_;   // the device's own trouble ("" : none)
  std::thread reader_;
};

}  // namespace uav::runtime
