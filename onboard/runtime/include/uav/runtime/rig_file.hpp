#pragma once
// A rig file (JSON; resources/rigs/ has examples, docs/vehicle/rigs.md the reference): the
// vehicle's real cameras, recorded or live, and which vision worker each feeds.
//
//   {
//     "cameras": {
//       "front":  {"type": "kitti", "path": "kitti/00", "mount": {"xyz_m": [0, 0, -1.65]}},
//       "down":   {"type": "video", "path": "flight.mp4", "calibration": "down.yaml", "mount": {"pitch_deg": -90}},
//       "gimbal": {"type": "live", "source": "/dev/video0", "calibration": "gimbal.camera", "rate_hz": 30}
//     },
//     "workers": {"odometry": "front", "obstacles": "front", "wires": "front",
//                 "survey": "down", "tracking": "gimbal", "depth": "survey"},
//     "pose": "truth"
//   }
//
// Types: "kitti" and "euroc" (stereo sequences), "video" and "photos" (a recorded mono camera,
// with "times" or "rate_hz"), "live" (any OpenCV VideoCapture source). A mono camera needs its
// calibration: our .camera file or OpenCV's YAML/XML (camera_matrix, distortion_coefficients,
// image_width, image_height). Relative paths are from the rig file's folder. "pose": where the
// bench takes the vehicle's pose from: "truth" (the recording's ground truth), "imu" (the
// attitude from the recording's IMU, the position from the VO worker, which the IMU aids),
// "odometry" (the VO worker's alone) or "fixed" (standing at home, level, heading north); by
// default the truth where a recording has one, else the IMU and odometry where both are, else
// the odometry where a pair feeds it, else fixed.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "uav/runtime/recorded_sensors.hpp"
#include "uav/runtime/sensor_rig.hpp"

namespace uav::runtime {

class RigFile {
 public:
  enum class PoseSource { kTruth, kImuOdometry, kOdometry, kFixed };
  // Reads the file and opens every camera: recordings are read and checked, live devices opened
  // and a first frame taken. Recordings play from `start_utime`. Throws std::runtime_error naming
  // the file, the field and what is wrong (an unknown field or type, a camera no worker can
  // use, a missing file or device, a calibration of another size than the images).
  static std::unique_ptr<RigFile> Load(const std::string& path, int64_t start_utime);
  // The same from JSON text; relative paths from `dir`.
  static std::unique_ptr<RigFile> Parse(const std::string& json_text, const std::string& dir, const std::string& name,
                                        int64_t start_utime);
  ~RigFile();

  const SensorRig& rig() const { return rig_; }
  PoseSource pose_source() const { return pose_source_; }
  // The recorded ground truth the pose comes from (null: none, or the pose is the odometry's).
  const RecordedTruth* truth() const { return pose_source_ == PoseSource::kTruth ? truth_ : nullptr; }
  // The ground truth's body pose at vehicle time `utime` (the recording plays from the start).
  Eigen::Isometry3d TruthAt(int64_t utime) const;
  // The recorded IMU's samples (null: none, or the pose does not use it) and the vehicle time of
  // a sample: t_us - imu_offset_us().
  const std::vector<ImuSample>* imu() const { return pose_source_ == PoseSource::kImuOdometry ? imu_ : nullptr; }
  int64_t imu_offset_us() const { return imu_offset_us_; }
  // When the last recorded frame has been taken: its exposure and half a frame more (-1: a
  // camera is live; no end).
  int64_t end_utime() const { return end_utime_; }
  // One line per camera: "front: KITTI sequence DIR, 51 pairs at 10.0 Hz, ground truth; odometry, obstacles".
  std::string Describe() const;

 private:
  RigFile() = default;
  std::vector<std::unique_ptr<hal::Camera>> mono_;
  std::vector<std::unique_ptr<hal::StereoCamera>> stereo_;
  std::vector<std::string> lines_;
  SensorRig rig_;
  const RecordedTruth* truth_ = nullptr;
  int64_t truth_offset_us_ = 0;  // recording time minus vehicle time
  const std::vector<ImuSample>* imu_ = nullptr;
  int64_t imu_offset_us_ = 0;
  PoseSource pose_source_ = PoseSource::kOdometry;
  int64_t end_utime_ = -1;
};

// A camera's calibration from our .camera file or OpenCV's YAML/XML. Throws std::runtime_error
// naming the file and what is missing.
CameraIntrinsics ReadCalibration(const std::string& path);

}  // namespace uav::runtime
