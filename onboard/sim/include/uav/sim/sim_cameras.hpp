#pragma once
// The simulated cameras behind hal::Camera and hal::StereoCamera: world::Renderer draws the
// scene from the vehicle's true pose (what a real camera sees), at the time asked for.
#include <functional>

#include "uav/hal/camera.hpp"
#include "uav/world/renderer.hpp"

namespace uav::sim {

// The true body pose T_NB now (SimVehicle::TruthState).
using TruthPose = std::function<Eigen::Isometry3d()>;

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
};

class SimStereoCamera : public hal::StereoCamera {
 public:
  SimStereoCamera(const world::Scene& scene, const world::StereoSetup& setup, TruthPose truth_T_NB);
  const hal::CameraInfo& left() const override { return left_; }
  const hal::CameraInfo& right() const override { return right_; }
  hal::StereoImages Capture(int64_t utime, hal::Emitter emitter) override;

 private:
  world::StereoRenderer renderer_;
  hal::CameraInfo left_, right_;
  TruthPose truth_T_NB_;
};

}  // namespace uav::sim
