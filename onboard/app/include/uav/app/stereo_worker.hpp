#pragma once
// STEREO: the simulated forward stereo pair on the simulated clock (issue 4 item 6). A thin
// shell: renders both cameras (and the laser grid) from the simulator's true pose at the pair's
// rate, feeds vision::StereoRange, and posts the nearest obstacle ahead to the blackboard, from
// where CMM sends it to the GCS (vehicle_state_t.obstacle_range_m) and DLG logs it.
#include <functional>

#include <Eigen/Geometry>

#include "uav/app/blackboard.hpp"
#include "uav/vision/stereo_range.hpp"
#include "uav/world/renderer.hpp"

namespace uav::app {

class StereoWorker {
 public:
  StereoWorker(const world::Scene& scene, const world::StereoSetup& setup,
               std::function<Eigen::Isometry3d()> truth_T_NB, Blackboard& board);
  void Tick(int64_t utime);
  int frames() const { return frames_; }

 private:
  world::StereoRenderer renderer_;
  vision::StereoRange range_;
  std::function<Eigen::Isometry3d()> truth_T_NB_;
  Blackboard& board_;
  int frames_ = 0;
};

}  // namespace uav::app
