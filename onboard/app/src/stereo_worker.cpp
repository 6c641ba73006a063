#include "uav/app/stereo_worker.hpp"

namespace uav::app {

StereoWorker::StereoWorker(const world::Scene& scene, const world::StereoSetup& setup,
                           std::function<Eigen::Isometry3d()> truth_T_NB, Blackboard& board)
    : renderer_(scene, setup),
      range_({setup.left.intrinsics, setup.right.intrinsics, setup.T_LR()}, vision::StereoRangeParams()),
      truth_T_NB_(std::move(truth_T_NB)),
      board_(board) {}

void StereoWorker::Tick(int64_t utime) {
  const world::StereoFrame pair = renderer_.Render(truth_T_NB_(), utime);
  const vision::StereoRangeResult r = range_.Process(pair.left.image, pair.right.image);
  board_.Update([&](BlackboardData& d) { d.obstacle_range_m = r.obstacle ? r.range_m : -1.0; });
  ++frames_;
}

}  // namespace uav::app
