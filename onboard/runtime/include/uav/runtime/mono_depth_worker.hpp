#pragma once
// MDEPTH: monocular depth from motion (thesis 3.4) on one of the vehicle's cameras. A thin shell
// around vision::MonoDepthEstimator: the camera's thread (CAM or TRK) shares each frame with the
// pose the navigation solution gave it; this thread runs the estimator on it and hands the grid
// to CMM for the GCS, at the camera's rate.
#include <string>

#include "uav/runtime/vision_worker.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/mono_depth.hpp"

namespace uav::runtime {

// The estimate is from within a control period of the frame (else there is no navigation sample
// matching it).
bool EstimateMatchesFrame(const hal::VehicleEstimate& estimate, int64_t frame_utime);
// Shares `image` with MDEPTH when it wants this camera's frames, with the camera pose (given in
// N, shared in the odometry frame) and the vehicle's velocity from the estimate (when it
// matches the frame's time).
void ShareFrame(Outbox& out, const BlackboardData& d, const std::string& camera, int64_t utime, const cv::Mat& image,
                const std::optional<Eigen::Isometry3d>& T_NC_estimate);

struct MonoDepthWorkerParams {
  int camera = 0;  // mdp_camera: 0 off, 1 the downward camera, 2 the gimbal camera
  vision::MonoDepthParams estimator;  // mdp_obstacle_depth, mdp_max_features
  bool to_map = false;                // avd_enable: each grid goes into obstacle avoidance's map too
  static MonoDepthWorkerParams FromParameters(const ParameterSet& p);
};

class MonoDepthWorker : public VisionWorker {
 public:
  // `to_map`: each grid's trusted cells go into obstacle avoidance's map (avoid::DepthGridScan).
  MonoDepthWorker(const hal::CameraInfo& camera, Blackboard& board, const vision::MonoDepthParams& params, bool to_map = false);
  void Begin(int64_t utime) override;
  void Work(Outbox& out) override;
  int frames() const { return frames_; }
  double rate_hz() const { return rate_hz_; }  // the camera's
  const std::string& camera() const { return camera_; }
  const vision::MonoDepthEstimator& estimator() const { return estimator_; }

 private:
  std::string camera_;  // whose frames it takes
  CameraIntrinsics intrinsics_;
  bool to_map_;
  double rate_hz_;
  std::optional<SharedFrame> frame_;  // taken at Begin
  vision::MonoDepthEstimator estimator_;
  int frames_ = 0;
};

}  // namespace uav::runtime
