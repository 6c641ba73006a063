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

class SimStereoCamera : public hal::StereoCamera {
 public:
  SimStereoCamera(const world::Scene& scene, const world::StereoSetup& setup, TruthPose truth_T_NB);
  const hal::CameraInfo& left() const override { return left_; }
  const hal::CameraInfo& right() const override { return right_; }
  hal::StereoImages Capture(int64_t utime) override;

 private:
  world::StereoRenderer renderer_;
  hal::CameraInfo left_, right_;
  TruthPose truth_T_NB_;
};

}  // namespace uav::sim
