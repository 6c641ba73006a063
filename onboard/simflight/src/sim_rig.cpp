#include "uav/simflight/sim_rig.hpp"

#include <stdexcept>
#include <string>

#include "uav/runtime/track_worker.hpp"
#include "uav/world/scene.hpp"

namespace uav::simflight {

SimRig::SimRig(const world::Scene& scene, const ParameterSet& params) {
  if (!scene.downward_camera() && !scene.stereo_camera() && !scene.gimbal_camera())
    throw std::invalid_argument("the scene declares no camera");
  // Cameras see the world from the true pose at their exposure, as real ones do.
  const sim::TruthPose truth = truth_.Lookup();
  if (scene.downward_camera()) {
    downward_ = std::make_unique<sim::SimCamera>(scene, *scene.downward_camera(), truth);
    rig_.survey = downward_.get();
  }
  if (scene.gimbal_camera()) {
    const double pitch = runtime::TrackWorkerParams::FromParameters(params).gimbal_pitch_rad;
    gimbal_ = std::make_unique<sim::SimGimbalCamera>(scene, *scene.gimbal_camera(), truth, pitch);
    rig_.tracking = gimbal_.get();
  }
  const int mdp_camera = static_cast<int>(params.Get("mdp_camera"));
  rig_.depth = mdp_camera == 1   ? runtime::SensorRig::DepthCamera::kSurvey
               : mdp_camera == 2 ? runtime::SensorRig::DepthCamera::kTracking
                                 : runtime::SensorRig::DepthCamera::kNone;
  // What runs on which pair (the vehicle file's *_rig): active stereo on a downward pair with the
  // dot projector, odometry, obstacles (obs_rig; by default the first pair none of the others
  // uses) and wires, with the obstacles or alone on their own pair (pwl_rig).
  const int pairs = static_cast<int>(scene.stereo_rigs().size());
  if (pairs == 0) return;
  for (const world::StereoSetup& setup : scene.stereo_rigs()) {
    stereo_.push_back(std::make_unique<sim::SimStereoCamera>(scene, setup, truth));
    rig_.stereo_pairs.push_back(stereo_.back().get());
  }
  auto pair_of = [&](const char* name) {
    const int k = static_cast<int>(params.Get(name));
    if (k >= pairs)
      throw std::invalid_argument(std::string(name) + " " + std::to_string(k) + ": the scene has " +
                                  std::to_string(pairs) + " stereo rig" + (pairs == 1 ? "" : "s") + " (from 0)");
    return k;
  };
  const int active = params.Get("asv_enable") != 0.0 ? pair_of("asv_rig") : -1;
  const int odometry = params.Get("vo_enable") != 0.0 ? pair_of("vo_rig") : -1;
  const bool power_lines = params.Get("pwl_enable") != 0.0;
  const int wires_alone = power_lines ? pair_of("pwl_rig") : -1;
  int obstacles = -1;
  if (params.Get("obs_enable") != 0.0) {
    obstacles = pair_of("obs_rig");
    for (int k = 0; k < pairs && obstacles < 0; ++k)
      if (k != active && k != odometry && k != wires_alone) obstacles = k;
  }
  auto pair = [&](int k) { return k >= 0 ? stereo_[static_cast<std::size_t>(k)].get() : nullptr; };
  rig_.active_stereo = pair(active);
  rig_.odometry = pair(odometry);
  rig_.obstacles = pair(obstacles);
  rig_.wires = !power_lines ? nullptr : wires_alone >= 0 ? pair(wires_alone) : rig_.obstacles;
}

void SimRig::SetStereoFailed(int pair, bool failed) {
  if (pair < 0 || pair >= static_cast<int>(stereo_.size()))
    throw std::out_of_range("stereo rig " + std::to_string(pair) + ": the scene has " + std::to_string(stereo_.size()));
  stereo_[static_cast<std::size_t>(pair)]->SetFailed(failed);
}

}  // namespace uav::simflight
