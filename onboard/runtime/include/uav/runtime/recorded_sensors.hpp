#pragma once
// Recorded sensors behind the hal camera interfaces: a stereo sequence in the KITTI odometry or
// the EuRoC/ASL layout, and a video file or a folder of photos for a mono camera, each with its
// recorded timestamps and, where the recording has it, the ground truth. Played on the vehicle
// clock: frame i is exposed at start + (t_i - t_0), so the workers see the recording's own
// timing at any playback speed. Everything is read and checked when the sensor is made (a
// missing right image, a calibration of another size, times that repeat or go backwards are
// refused there, named); an image that cannot be read during the run is the camera's problem
// (problem()), shown in the sensing health, and the run goes on.
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "uav/hal/camera.hpp"
#include "uav/shared/camera_intrinsics.hpp"

namespace cv {
class VideoCapture;
}

namespace uav::runtime {

// The camera's pose in the body frame (FRD) from how it is mounted: at `p_B` [m], looking
// forward and pitched by `pitch_rad` (0: forward, -pi/2: straight down; thesis Eq. 5.48).
Eigen::Isometry3d CameraMount(const Eigen::Vector3d& p_B, double pitch_rad);

// The body's recorded true pose in N at a time of the recording [us].
struct RecordedPose {
  int64_t t_us = 0;
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
};

// Ground truth by time: interpolated between samples (position linearly, attitude by slerp),
// held at the ends.
class RecordedTruth {
 public:
  RecordedTruth() = default;
  explicit RecordedTruth(std::vector<RecordedPose> poses);
  bool empty() const { return poses_.empty(); }
  std::size_t size() const { return poses_.size(); }
  Eigen::Isometry3d At(int64_t t_us) const;

 private:
  std::vector<RecordedPose> poses_;
};

// One recorded IMU sample, in the body frame.
struct ImuSample {
  int64_t t_us = 0;
  Eigen::Vector3d gyro_B = Eigen::Vector3d::Zero();   // [rad/s]
  Eigen::Vector3d accel_B = Eigen::Vector3d::Zero();  // [m/s^2] specific force (at rest: g, up)
};

// One recorded exposure: its time on the recording's clock and its files (right: stereo only).
struct RecordedFrame {
  int64_t t_us = 0;
  std::string left, right;
};

// Which recorded frame the vehicle clock is at: the newest exposed by `utime` (a quarter of a
// frame early counts: the clock's grid rounds the frame period), played from `start_utime`.
// -1 before the first.
int RecordedFrameAt(const std::vector<RecordedFrame>& frames, int64_t start_utime, int64_t utime);

// A recorded stereo sequence, read and checked.
struct StereoRecording {
  std::string dir;
  std::string layout;  // "KITTI" or "EuRoC"
  CameraIntrinsics left, right;
  Eigen::Isometry3d T_BL = Eigen::Isometry3d::Identity();  // left camera in the body frame
  Eigen::Isometry3d T_BR = Eigen::Isometry3d::Identity();  // right camera in the body frame
  std::vector<RecordedFrame> frames;
  RecordedTruth truth;  // the body in N; empty without ground truth
  std::vector<ImuSample> imu;  // the body's IMU (EuRoC's imu0); empty without one
  double rate_hz = 0.0;  // frames per second (median interval)
};

// KITTI odometry: image_0/ image_1/ calib.txt (P0, P1), optional times.txt (10 Hz without) and
// poses.txt (left camera i in camera 0's frame) or ../poses/NN.txt. The pair is rectified; its
// left camera sits at `T_BL` (a car's forward camera by default). The truth puts the body at
// the origin of N, level and heading north, at the first frame. Throws std::runtime_error
// naming the folder and what is wrong.
StereoRecording ReadKittiRecording(const std::string& dir, const Eigen::Isometry3d& T_BL);
// EuRoC/ASL (the folder or its mav0/): cam0/ cam1/ with data.csv and sensor.yaml (T_BS,
// resolution, pinhole intrinsics, radial-tangential distortion), optional imu0/data.csv
// (timestamp ns, w_RS_S [rad/s], a_RS_S [m/s^2]; its sensor.yaml's T_BS, when there, turns the
// samples into the body) and state_groundtruth_estimate0/data.csv. The body is the recording's IMU frame S; its z-up world
// becomes N by a half turn about x. Throws std::runtime_error naming the file and what is wrong.
StereoRecording ReadEurocRecording(const std::string& dir);
// Which of the two a folder is ("" : neither).
std::string StereoLayoutOf(const std::string& dir);

// A recorded stereo pair on the vehicle clock.
class RecordedStereoCamera : public hal::StereoCamera {
 public:
  // `name`: the rig's name for it. Throws std::runtime_error when the first pair's size differs
  // from the calibration's.
  RecordedStereoCamera(const std::string& name, StereoRecording recording, int64_t start_utime);
  const hal::CameraInfo& left() const override { return left_; }
  const hal::CameraInfo& right() const override { return right_; }
  hal::StereoImages Capture(int64_t utime, hal::Emitter emitter) override;
  std::string problem() const override;
  const StereoRecording& recording() const { return rec_; }
  int64_t end_utime() const;  // when the last frame has been exposed

 private:
  StereoRecording rec_;
  int64_t start_utime_;
  hal::CameraInfo left_, right_;
  mutable std::mutex mutex_;
  std::string problem_;
  // The pair last read: the workers sharing this pair take the same frame, decoded once.
  std::mutex read_mutex_;
  int read_index_ = -1;
  cv::Mat read_left_, read_right_;
};

// A recorded mono camera: a video file (times from the container, or `times_path`) or a folder
// of photos (times from `times_path`: one time in seconds a line, or EuRoC's data.csv; else from
// names that are nanosecond timestamps; else `rate_hz`). As a gimbal camera its pitch is the
// mount's and cannot be set (the recording was made as it was).
class RecordedCamera : public hal::GimbalCamera {
 public:
  struct Options {
    std::string name;
    std::string path;        // video file or photo folder
    CameraIntrinsics intrinsics;
    Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
    double rate_hz = 0.0;    // photos without times: this rate; 0: from the times
    std::string times_path;  // "" : none
    int64_t start_utime = 0;
  };
  // Throws std::runtime_error naming the file and what is wrong.
  explicit RecordedCamera(const Options& options);
  ~RecordedCamera() override;
  const hal::CameraInfo& info() const override { return info_; }
  hal::CameraFrame Capture(int64_t utime) override;
  std::string problem() const override;
  void SetPitch(double) override {}
  double pitch_rad() const override { return pitch_rad_; }
  int64_t end_utime() const;
  std::size_t frames() const { return frames_.size(); }

 private:
  cv::Mat ReadVideoFrame(int index);

  Options options_;
  hal::CameraInfo info_;
  double pitch_rad_ = 0.0;
  std::vector<RecordedFrame> frames_;  // left: the photo ("" for a video)
  std::unique_ptr<cv::VideoCapture> video_;
  int video_next_ = 0;  // the index the video reader gives next
  std::mutex read_mutex_;
  mutable std::mutex mutex_;
  std::string problem_;
};

}  // namespace uav::runtime
