#pragma once
// The simulated cameras behind hal::Camera and hal::StereoCamera: world::Renderer draws the
// scene from the vehicle's true pose (what a real camera sees), at the time asked for.
#include <atomic>
#include <cstdint>
#include <deque>
#include <functional>
#include <mutex>
#include <utility>

#include "uav/hal/camera.hpp"
#include "uav/world/renderer.hpp"

namespace uav::sim {

// The true body pose T_NB at `utime` (SimVehicle::TruthState then). Vision workers render on
// their own threads while the simulation runs on: the pose is looked up by the exposure's time.
using TruthPose = std::function<Eigen::Isometry3d(int64_t utime)>;

// The simulator's true poses of the last seconds, by time: recorded by the clock's thread each
// physics step, read by the camera threads (thread-safe). A time not recorded gets the nearest.
class TruthPoseHistory {
 public:
  explicit TruthPoseHistory(int64_t keep_us = 3'000'000) : keep_us_(keep_us) {}
  void Record(int64_t utime, const Eigen::Isometry3d& T_NB);
  Eigen::Isometry3d At(int64_t utime) const;
  TruthPose Lookup() const {
    return [this](int64_t utime) { return At(utime); };
  }

 private:
  int64_t keep_us_;
  mutable std::mutex mutex_;
  std::deque<std::pair<int64_t, Eigen::Isometry3d>> poses_;
};

hal::CameraInfo CameraInfoOf(const world::CameraSetup& setup);

class SimCamera : public hal::Camera {
 public:
  SimCamera(const world::Scene& scene, const world::CameraSetup& setup, TruthPose truth_T_NB);
  const hal::CameraInfo& info() const override { return info_; }
  hal::CameraFrame Capture(int64_t utime) override;

 private:
  world::Renderer renderer_;
  hal::CameraInfo info_;
  TruthPose truth_T_NB_;
  std::mutex capture_mutex_;  // one exposure at a time, as a camera driver delivers them
};

// The gimballed camera: rendered from the true position and heading with the gimbal's pitch.
class SimGimbalCamera : public hal::GimbalCamera {
 public:
  SimGimbalCamera(const world::Scene& scene, const world::CameraSetup& setup, TruthPose truth_T_NB,
                  double initial_pitch_rad);
  const hal::CameraInfo& info() const override { return info_; }
  hal::CameraFrame Capture(int64_t utime) override;
  void SetPitch(double pitch_rad) override;
  double pitch_rad() const override { return pitch_rad_; }

 private:
  world::Renderer renderer_;
  hal::CameraInfo info_;
  TruthPose truth_T_NB_;
  double pitch_rad_ = 0.0;
  std::mutex capture_mutex_;  // one exposure at a time, as a camera driver delivers them
};

class SimStereoCamera : public hal::StereoCamera {
 public:
  SimStereoCamera(const world::Scene& scene, const world::StereoSetup& setup, TruthPose truth_T_NB);
  const hal::CameraInfo& left() const override { return left_; }
  const hal::CameraInfo& right() const override { return right_; }
  hal::StereoImages Capture(int64_t utime, hal::Emitter emitter) override;
  // The simulator's fault: a failed pair delivers black images (a camera whose sensor or cable
  // died), so the vision workers find nothing in them and say so.
  void SetFailed(bool failed) { failed_ = failed; }
  // Exposures rendered so far: one per exposure time (and projector mode), however many workers ask.
  int64_t renders() const { return renders_; }

 private:
  std::atomic<bool> failed_{false};
  std::atomic<int64_t> renders_{0};
  world::StereoRenderer renderer_;
  hal::CameraInfo left_, right_;
  TruthPose truth_T_NB_;
  bool has_projector_ = false;
  std::mutex capture_mutex_;  // one exposure at a time, as a camera driver delivers them
  // The last exposure (under capture_mutex_): workers sharing the pair at one rate (odometry with
  // obstacles and wires) ask for the same one, which a camera exposes once; without a projector
  // the emitter mode changes nothing in it.
  int64_t last_utime_ = -1;
  bool last_projector_on_ = false;
  world::StereoFrame last_;
};

}  // namespace uav::sim
