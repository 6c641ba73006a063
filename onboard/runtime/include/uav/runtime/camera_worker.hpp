#pragma once
// CAM: the downward camera on the vehicle clock. A thin shell around hal::Camera (simulated or
// real): takes a frame at the camera rate, hands a
// JPEG preview to CMM for the GCS video panel at the camera's preview rate, and while the survey camera is on (mission
// capture start .. stop) writes each capture with its pose to the capture directory, which
// is what the stitcher consumes. Runs whether or not the GCS link is up.
#include <cstdio>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "uav/runtime/vision_worker.hpp"
#include "uav/runtime/preview_stream.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/hal/camera.hpp"

namespace uav::runtime {

class CameraWorker : public VisionWorker {
 public:
  struct Options {
    int preview_width = 320;      // [px] preview is scaled to this width
    int preview_quality = 70;     // JPEG quality of the preview
    int capture_quality = 95;     // JPEG quality of survey captures
    std::string capture_dir;      // "" = do not record captures
    GeodeticPoint home;           // origin of the poses' local NED frame, for the session file
  };
  // The recorded pose columns carry the camera's ground truth where it has one (simulation)
  // and the flight stack's estimate.
  CameraWorker(hal::Camera& camera, Blackboard& board, const Options& options);
  ~CameraWorker();
  void Work(Outbox& out) override;
  int captures() const { return captures_; }  // taken (and recorded when there is a capture dir)
  int previews() const { return previews_; }

 private:
  // Writes the capture's JPEG and its captures.csv row.
  void Record(int64_t utime, const hal::CameraFrame& frame, const BlackboardData& d);

  hal::Camera& camera_;
  Options options_;
  PreviewStream preview_;
  std::FILE* csv_ = nullptr;
  int captures_ = 0;
  int previews_ = 0;
  int64_t last_capture_utime_ = -1;
  Eigen::Vector3d last_capture_p_N_ = Eigen::Vector3d::Zero();
};

}  // namespace uav::runtime
