#pragma once
// CAM: the simulated downward camera on the simulated clock (issue 4 item 6). A thin shell
// around world::Renderer: renders at the camera rate from the simulator's true pose, hands a
// JPEG preview to CMM for the GCS video panel at the camera's preview rate, and while the survey camera is on (mission
// capture start .. stop) writes each capture with its pose to the capture directory, which
// is what the stitcher consumes. Runs whether or not the GCS link is up.
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "uav/app/blackboard.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/world/renderer.hpp"

namespace uav::app {

class CameraWorker {
 public:
  struct Options {
    int preview_width = 320;      // [px] preview is scaled to this width
    int preview_quality = 70;     // JPEG quality of the preview
    int capture_quality = 95;     // JPEG quality of survey captures
    std::string capture_dir;      // "" = do not record captures
    GeodeticPoint home;           // origin of the poses' local NED frame, for the session file
  };
  // `truth_T_NB` returns the vehicle's true pose (the simulator's), which is what a real
  // camera sees; the recorded pose columns also carry the flight stack's estimate.
  CameraWorker(const world::Scene& scene, const world::CameraSetup& camera,
               std::function<Eigen::Isometry3d()> truth_T_NB, Blackboard& board, const Options& options);
  ~CameraWorker();
  void Tick(int64_t utime);
  int captures() const { return captures_; }  // taken (and recorded when there is a capture dir)
  int previews() const { return previews_; }

 private:
  void SendPreview(int64_t utime, const world::Frame& frame);
  // Writes the capture's JPEG and its captures.csv row.
  void Record(int64_t utime, const world::Frame& frame, const Eigen::Isometry3d& T_NB, const BlackboardData& d);

  world::Renderer renderer_;
  std::function<Eigen::Isometry3d()> truth_T_NB_;
  Blackboard& board_;
  Options options_;
  std::FILE* csv_ = nullptr;
  int captures_ = 0;
  int previews_ = 0;
  int64_t next_preview_utime_ = -1;
  int64_t last_capture_utime_ = -1;
  Eigen::Vector3d last_capture_p_N_ = Eigen::Vector3d::Zero();
};

}  // namespace uav::app
