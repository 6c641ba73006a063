#pragma once
// ASTEREO: the stereo pair facing down with its laser dot projector (thesis ch. 4), on the
// vehicle clock. A thin shell around vision::ActiveStereo: takes both images at the pair's rate,
// measures the height over the ground cluster with the attitude the INS estimated, publishes
// active_stereo_t (height, dots, clusters; or unhealthy with the reason), hands the height to
// the INS as a height sensor when asv_to_ins is set (indoors, where the barometer drifts and
// the sonar reads table tops), and streams the left image to the GCS video panel.
#include "uav/runtime/vision_worker.hpp"
#include "uav/runtime/preview_stream.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/active_stereo.hpp"

namespace uav::runtime {

struct ActiveStereoWorkerParams {
  bool enabled = false;             // asv_enable: the stereo pair is the downward active rig
  bool to_ins = true;               // asv_to_ins: its height feeds the INS
  double height_noise_m = 0.02;     // asv_height_noise: 1 sigma the INS gives a height, at least
  vision::ActiveStereoParams stereo;  // asv_threshold, asv_min_points
  // From a vehicle parameter file; throws naming a missing or out-of-range parameter.
  static ActiveStereoWorkerParams FromParameters(const ParameterSet& p);
};

class ActiveStereoWorker : public VisionWorker {
 public:
  ActiveStereoWorker(hal::StereoCamera& camera, Blackboard& board, const ActiveStereoWorkerParams& params);
  void Work(Outbox& out) override;
  int frames() const { return frames_; }        // pairs processed
  int unhealthy() const { return unhealthy_; }  // pairs without a height

 private:
  hal::StereoCamera& camera_;
  ActiveStereoWorkerParams params_;
  vision::ActiveStereo stereo_;
  vision::GroundTracker ground_;  // the floor's level in N, from pair to pair
  PreviewStream preview_;
  int frames_ = 0;
  int unhealthy_ = 0;
};

}  // namespace uav::runtime
