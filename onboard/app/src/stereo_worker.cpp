#include "uav/app/stereo_worker.hpp"

namespace uav::app {

StereoWorker::StereoWorker(hal::StereoCamera& camera, Blackboard& board)
    : camera_(camera),
      range_({camera.left().intrinsics, camera.right().intrinsics, camera.T_LR()}, vision::StereoRangeParams()),
      board_(board) {}

void StereoWorker::Tick(int64_t utime) {
  const hal::StereoImages pair = camera_.Capture(utime);
  const vision::StereoRangeResult r = range_.Process(pair.left, pair.right);
  board_.Update([&](BlackboardData& d) { d.obstacle_range_m = r.obstacle ? r.range_m : -1.0; });
  ++frames_;
}

}  // namespace uav::app
