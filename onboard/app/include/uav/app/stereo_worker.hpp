#pragma once
// STEREO: the forward stereo pair on the vehicle clock. A thin shell around hal::StereoCamera
// (simulated or real): takes both images at the pair's rate, feeds vision::StereoRange, and
// posts the nearest obstacle ahead to the blackboard, from where CMM sends it to the GCS
// (vehicle_state_t.obstacle_range_m) and DLG logs it.
#include "uav/app/blackboard.hpp"
#include "uav/hal/camera.hpp"
#include "uav/vision/stereo_range.hpp"

namespace uav::app {

class StereoWorker {
 public:
  StereoWorker(hal::StereoCamera& camera, Blackboard& board);
  void Tick(int64_t utime);
  int frames() const { return frames_; }

 private:
  hal::StereoCamera& camera_;
  vision::StereoRange range_;
  Blackboard& board_;
  int frames_ = 0;
};

}  // namespace uav::app
