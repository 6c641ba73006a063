#pragma once
// STEREO: the forward stereo pair on the vehicle clock. A thin shell around hal::StereoCamera
// (simulated or real): takes both images at the pair's rate, feeds vision::StereoRange (the
// nearest obstacle ahead, vehicle_state_t.obstacle_range_m) and vision::PowerLineStereo (power
// lines in the image and in 3-D, thesis 3.6: power_lines_t, and the nearest wire in
// vehicle_state_t.nearest_wire_m, the median of the last three pairs), and streams the left image to the GCS video panel at its
// preview rate. The wires are placed in NED with the flight stack's estimate, never the truth.
#include <array>
#include <memory>
#include <optional>

#include "uav/app/blackboard.hpp"
#include "uav/app/preview_stream.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/power_line_stereo.hpp"
#include "uav/vision/stereo_range.hpp"

namespace uav::app {

struct StereoWorkerParams {
  bool power_lines = true;             // pwl_enable
  vision::WireRangingParams ranging;   // pwl_min_range, pwl_max_range
  // From a vehicle parameter file; throws naming a missing or out-of-range parameter.
  static StereoWorkerParams FromParameters(const ParameterSet& p);
};

class StereoWorker {
 public:
  StereoWorker(hal::StereoCamera& camera, Blackboard& board, const StereoWorkerParams& params);
  void Tick(int64_t utime);
  int frames() const { return frames_; }

 private:
  void ReportPowerLines(int64_t utime, const std::vector<vision::Wire3D>& wires, const cv::Size& image);

  hal::StereoCamera& camera_;
  vision::StereoRange range_;
  std::optional<vision::PowerLineStereo> power_lines_;
  Blackboard& board_;
  PreviewStream preview_;
  static constexpr double kNoWire = 1e9;
  std::array<double, 3> recent_nearest_m_{kNoWire, kNoWire, kNoWire};  // per pair, kNoWire: none ranged
  int frames_ = 0;
};

}  // namespace uav::app
