#pragma once
// STITCH: the onboard map stitcher (issue 7 item 1). A thin shell around vision::MapStitcher:
// takes every survey capture CAM hands over (image + estimated camera pose), stitches it while
// the vehicle flies, and once the survey is over and the vehicle has landed adjusts all frames
// jointly, renders the map again without seams and writes it (GeoTIFF, PNG + world file, KML)
// into the map directory and reports it. It needs nothing from
// the GCS link, so a link loss does not stop it.
#include <memory>
#include <string>

#include "uav/runtime/vision_worker.hpp"
#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::vision {
class MapStitcher;
}

namespace uav::runtime {

class StitchWorker : public VisionWorker {
 public:
  struct Options {
    std::string map_dir;  // maps are written here as map_<n>.*
    GeodeticPoint home;   // origin of the local NED frame the poses are in
  };
  StitchWorker(const CameraIntrinsics& camera, Blackboard& board, const Options& options);
  ~StitchWorker();
  void Begin(int64_t utime) override;
  void Work(Outbox& out) override;

  int frames() const;  // placed in the current map
  int maps_written() const { return maps_written_; }
  const std::string& last_map() const { return last_map_; }  // path prefix of the newest map

 private:
  void Finish(Outbox& out);

  CameraIntrinsics camera_;
  std::vector<SurveyCapture> captures_;  // taken at Begin
  bool survey_over_ = false;             // camera off and on the ground at Begin
  Options options_;
  std::unique_ptr<vision::MapStitcher> stitcher_;
  int registered_ = 0;
  int maps_written_ = 0;
  std::string last_map_;
};

}  // namespace uav::runtime
