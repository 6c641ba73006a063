#pragma once
// The simulator's rig: the scene's rendered cameras (sim/sim_cameras.hpp) and which vision
// worker each feeds, as the vehicle file chooses (obs_rig, vo_rig, asv_rig, pwl_rig, the
// *_enable switches and mdp_camera). The cameras render from the true poses the simulator
// records each physics step; a stereo pair can be failed (the simulator's fault).
#include <cstdint>
#include <memory>
#include <vector>

#include <Eigen/Geometry>

#include "uav/runtime/sensor_rig.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/sim_cameras.hpp"

namespace uav::world {
class Scene;
}

namespace uav::simflight {

class SimRig {
 public:
  // Throws std::invalid_argument naming what is wrong: a scene without cameras, a *_rig the
  // scene has not.
  SimRig(const world::Scene& scene, const ParameterSet& params);
  const runtime::SensorRig& rig() const { return rig_; }
  // The simulator's true pose at `utime`, each physics step: the cameras render from it.
  void RecordTruth(int64_t utime, const Eigen::Isometry3d& T_NB) { truth_.Record(utime, T_NB); }
  // The simulator's fault: stereo pair `pair` (the scene's order) delivers black images from now
  // on (failed) or real ones again. Throws std::out_of_range for a pair the scene has not.
  void SetStereoFailed(int pair, bool failed);

 private:
  sim::TruthPoseHistory truth_;
  std::unique_ptr<sim::SimCamera> downward_;
  std::unique_ptr<sim::SimGimbalCamera> gimbal_;
  std::vector<std::unique_ptr<sim::SimStereoCamera>> stereo_;  // the scene's, in order
  runtime::SensorRig rig_;
};

}  // namespace uav::simflight
