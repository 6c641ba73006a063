#include "uav/sim/sim_cameras.hpp"

#include <algorithm>
#include <cmath>

namespace uav::sim {

hal::CameraInfo CameraInfoOf(const world::CameraSetup& s) {
  return {s.name, s.intrinsics, s.T_BC, s.rate_hz, s.preview_rate_hz};
}

SimCamera::SimCamera(const world::Scene& scene, const world::CameraSetup& setup, TruthPose truth_T_NB)
    : renderer_(scene, setup), info_(CameraInfoOf(setup)), truth_T_NB_(std::move(truth_T_NB)) {}

hal::CameraFrame SimCamera::Capture(int64_t utime) {
  const Eigen::Isometry3d T_NB = truth_T_NB_();
  return {renderer_.Render(T_NB * info_.T_BC, utime).image, T_NB};
}

SimGimbalCamera::SimGimbalCamera(const world::Scene& scene, const world::CameraSetup& setup, TruthPose truth_T_NB,
                                 double initial_pitch_rad)
    : renderer_(scene, setup), info_(CameraInfoOf(setup)), truth_T_NB_(std::move(truth_T_NB)) {
  SetPitch(initial_pitch_rad);
}

void SimGimbalCamera::SetPitch(double pitch_rad) {
  if (std::isfinite(pitch_rad)) pitch_rad_ = std::clamp(pitch_rad, kMinPitchRad, kMaxPitchRad);
}

hal::CameraFrame SimGimbalCamera::Capture(int64_t utime) {
  const Eigen::Isometry3d T_NB = truth_T_NB_();
  return {renderer_.Render(hal::GimbalCameraPose(T_NB, info_.T_BC, pitch_rad_), utime).image, T_NB};
}

SimStereoCamera::SimStereoCamera(const world::Scene& scene, const world::StereoSetup& setup, TruthPose truth_T_NB)
    : renderer_(scene, setup),
      left_(CameraInfoOf(setup.left)),
      right_(CameraInfoOf(setup.right)),
      truth_T_NB_(std::move(truth_T_NB)) {}

hal::StereoImages SimStereoCamera::Capture(int64_t utime, hal::Emitter emitter) {
  const Eigen::Isometry3d T_NB = truth_T_NB_();
  world::StereoFrame pair = renderer_.Render(T_NB, utime, emitter == hal::Emitter::kOn);
  return {pair.left.image, pair.right.image, utime, utime, T_NB};
}

}  // namespace uav::sim
