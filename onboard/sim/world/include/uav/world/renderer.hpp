#pragma once
// Renders what a camera sees of a Scene, with exact ground truth for every pixel. Each pixel is
// a ray cast against the scene's analytic surfaces (no triangles, so depth is exact); textures
// are procedural, mip-mapped and deterministic: the same scene, camera, pose and time give a
// bit-identical image on any number of threads.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core.hpp>

#include "uav/world/camera_model.hpp"
#include "uav/world/scene.hpp"

namespace uav::world {

// One laser beam's ground truth.
struct LaserDot {
  int beam = 0;
  bool hit = false;                                   // the beam hit a surface
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();      // where it lands
  double range_m = 0.0;                               // from the emitter
  double spot_radius_m = 0.0;                         // radius of the spot where it lands
  double intensity = 0.0;                             // [DN] peak brightness added
  bool visible = false;                               // seen by this camera (in view, not occluded)
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();    // where it appears (distortion applied)
};

struct Frame {
  int64_t utime = 0;
  std::string camera;
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();  // camera pose at mid-exposure
  cv::Mat image;      // CV_8UC3, BGR
  cv::Mat depth;      // CV_32F, [m] along the optical axis (z in C); 0 where nothing was hit
  cv::Mat object_id;  // CV_16U: kNoObject, kGroundId, or an object id
  double exposure_gain = 1.0;
  std::vector<LaserDot> laser_dots;  // every beam, with this camera's visibility
};

struct StereoFrame {
  Frame left;
  Frame right;
  cv::Mat disparity;  // CV_32F, left image: fx * baseline / depth [px]; 0 where depth is 0
};

// Casts the emitter's beams (thesis 4.2) into the scene from the emitter pose T_NE, with moving
// objects where they are at t_s.
std::vector<LaserDot> CastLaser(const Scene& scene, const LaserEmitter& laser,
                                const Eigen::Isometry3d& T_NE, double t_s);

// The exact image box of an object in a rendered frame: the bounding rectangle of its visible
// pixels (empty when none shows). Tracking's ground truth (thesis 3.7).
cv::Rect ObjectBox(const Frame& frame, int object_id);

class Renderer {
 public:
  // Keeps a reference to `scene`, which must outlive the renderer and not change while it renders.
  Renderer(const Scene& scene, const CameraSetup& camera);
  ~Renderer();
  Renderer(Renderer&&) noexcept;

  const CameraSetup& camera() const;

  // Renders at camera pose T_NC (mid-exposure) at `utime`; clouds drift with time and the sensor
  // noise is drawn from (scene seed, camera name, utime). With blur_samples > 1 the camera moves
  // with velocity v_N and angular velocity w_C during exposure_s. `dots` (from CastLaser) are
  // drawn where visible.
  Frame Render(const Eigen::Isometry3d& T_NC, int64_t utime,
               const std::vector<LaserDot>& dots = {},
               const Eigen::Vector3d& v_N = Eigen::Vector3d::Zero(),
               const Eigen::Vector3d& w_C = Eigen::Vector3d::Zero()) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Renders both cameras of a stereo pair and the laser from the vehicle pose T_NB.
class StereoRenderer {
 public:
  StereoRenderer(const Scene& scene, const StereoSetup& setup);
  // laser_on false: the exposure with the projector off (no dots, whatever the setup says).
  StereoFrame Render(const Eigen::Isometry3d& T_NB, int64_t utime, bool laser_on = true) const;
  const StereoSetup& setup() const { return setup_; }

 private:
  const Scene& scene_;
  StereoSetup setup_;
  Renderer left_;
  Renderer right_;
};

}  // namespace uav::world
