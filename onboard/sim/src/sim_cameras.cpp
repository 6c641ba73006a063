#include "uav/sim/sim_cameras.hpp"

#include <algorithm>
#include <cmath>

namespace uav::sim {

void TruthPoseHistory::Record(int64_t utime, const Eigen::Isometry3d& T_NB) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!poses_.empty() && poses_.back().first >= utime) poses_.clear();  // the clock went back: a new run
  poses_.emplace_back(utime, T_NB);
  while (poses_.front().first < utime - keep_us_) poses_.pop_front();
}

Eigen::Isometry3d TruthPoseHistory::At(int64_t utime) const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (poses_.empty()) return Eigen::Isometry3d::Identity();
  auto it = std::lower_bound(poses_.begin(), poses_.end(), utime,
                             [](const std::pair<int64_t, Eigen::Isometry3d>& p, int64_t t) { return p.first < t; });
  if (it == poses_.end()) return poses_.back().second;
  if (it != poses_.begin() && utime - std::prev(it)->first < it->first - utime) --it;
  return it->second;
}

hal::CameraInfo CameraInfoOf(const world::CameraSetup& s) {
  return {s.name, s.intrinsics, s.T_BC, s.rate_hz, s.preview_rate_hz};
}

SimCamera::SimCamera(const world::Scene& scene, const world::CameraSetup& setup, TruthPose truth_T_NB)
    : renderer_(scene, setup), info_(CameraInfoOf(setup)), truth_T_NB_(std::move(truth_T_NB)) {}

hal::CameraFrame SimCamera::Capture(int64_t utime) {
  std::lock_guard<std::mutex> lock(capture_mutex_);
  const Eigen::Isometry3d T_NB = truth_T_NB_(utime);
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
  std::lock_guard<std::mutex> lock(capture_mutex_);
  const Eigen::Isometry3d T_NB = truth_T_NB_(utime);
  return {renderer_.Render(hal::GimbalCameraPose(T_NB, info_.T_BC, pitch_rad_), utime).image, T_NB};
}

SimStereoCamera::SimStereoCamera(const world::Scene& scene, const world::StereoSetup& setup, TruthPose truth_T_NB)
    : renderer_(scene, setup),
      left_(CameraInfoOf(setup.left)),
      right_(CameraInfoOf(setup.right)),
      truth_T_NB_(std::move(truth_T_NB)),
      has_projector_(setup.laser.enabled) {}

hal::StereoImages SimStereoCamera::Capture(int64_t utime, hal::Emitter emitter) {
  std::lock_guard<std::mutex> lock(capture_mutex_);
  const Eigen::Isometry3d T_NB = truth_T_NB_(utime);
  const bool projector_on = has_projector_ && emitter == hal::Emitter::kOn;
  if (utime != last_utime_ || projector_on != last_projector_on_) {
    last_ = renderer_.Render(T_NB, utime, projector_on);
    ++renders_;
    last_utime_ = utime;
    last_projector_on_ = projector_on;
  }
  // Each worker its own copy: none of them can change another's.
  hal::StereoImages pair{last_.left.image.clone(), last_.right.image.clone(), utime, utime, T_NB};
  if (failed_) {
    pair.left.setTo(0);
    pair.right.setTo(0);
  }
  return pair;
}

}  // namespace uav::sim
