#pragma once
// VO: the stereo pair as visual odometry (thesis ch. 5), on the vehicle clock. A thin shell
// around vision::StereoVo: rectifies each pair, runs the odometry, ties its frame to N with the
// INS's estimate when a segment starts (camera to body from the mount, Eq. 5.48), hands the body
// position to the IMU thread (the INS uses it while GPS is lost; the 9-state VO+IMU filter always)
// and reports health, counts and the truth (simulation) for the GCS.
#include <cstdio>
#include <map>
#include <optional>
#include <string>

#include "uav/runtime/vision_worker.hpp"
#include "uav/runtime/preview_stream.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/stereo_rectifier.hpp"
#include "uav/vision/stereo_vo.hpp"

namespace uav::runtime {

struct VoWorkerParams {
  bool enabled = false;            // vo_enable: the stereo pair runs visual odometry
  double position_noise_m = 0.05;  // vo_position_noise: 1 sigma of a VO position for the filters
  vision::VoParams vo;             // vo_method, vo_max_features
  bool stream_video = true;        // the left images to the video panel (not when the pair is shared)
  bool gyro_aided = true;          // the INS's attitude weighs the odometry's rotation (false: no IMU)
  std::string poses_path;          // "" or a file for one KITTI pose line per pair (as uav-vo writes)
  static VoWorkerParams FromParameters(const ParameterSet& p);
};

class VoWorker : public VisionWorker {
 public:
  // Throws std::runtime_error when the poses file cannot be written.
  VoWorker(hal::StereoCamera& camera, Blackboard& board, const VoWorkerParams& params);
  ~VoWorker() override;
  void Work(Outbox& out) override;
  int frames() const { return frames_; }
  int unhealthy() const { return unhealthy_; }
  // The commonest reasons for unhealthy pairs, numbers blanked ("left image is blank ... (#)"),
  // most frequent first, each with its count: "N x reason; ...".
  std::string UnhealthySummary(int top) const;

 private:
  hal::StereoCamera& camera_;
  VoWorkerParams params_;
  vision::StereoRectifier rectifier_;
  vision::StereoVo vo_;
  Eigen::Isometry3d T_BC_;  // the rectified left camera in the body frame
  std::optional<std::pair<int, Eigen::Isometry3d>> T_NW_;  // odometry frame in N, per segment
  PreviewStream preview_;
  int frames_ = 0, unhealthy_ = 0;
  std::map<std::string, int> reasons_;
  std::FILE* poses_ = nullptr;
  Eigen::Isometry3d last_T_WC_ = Eigen::Isometry3d::Identity();
};

}  // namespace uav::runtime
