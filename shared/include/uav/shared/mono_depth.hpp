#pragma once
// The depth grid of monocular depth from motion (thesis 3.4, Fig. 3.11) as plain data: what the
// estimator produces, the vehicle publishes (mono_depth_t) and the GCS draws. Decoded once, here.
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/signals.hpp"

namespace uav {

enum class CellState { kUnknown = 0, kFree = 1, kObstacle = 2 };
const char* Name(CellState s);  // "unknown", "free", "obstacle"

struct DepthCell {
  CellState state = CellState::kUnknown;
  double depth_m = 0.0;     // mean depth along the optical axis of its converged features; 0 unknown
  double sigma_m = 0.0;     // standard error of that mean from the features' filters
  int features = 0;         // converged features in the cell
  double confidence = 0.0;  // 0..1: features against twice the minimum, less the relative error
  std::string reason;       // why it is unknown
};

struct DepthGrid {
  int64_t utime = 0;        // [us] frame time
  std::string camera;
  int cols = 0, rows = 0;
  std::vector<DepthCell> cells;  // row-major from the top-left
  bool healthy = false;          // this frame was used; false: reason says why
  std::string reason;
  double obstacle_depth_m = 0.0; // nearer: obstacle, beyond: free
  int tracked = 0;               // features tracked into this frame
  int measured = 0;              // of them, with a depth measurement this frame
  const DepthCell& at(int row, int col) const { return cells[row * cols + col]; }
};

// Its signals (every cell of the 4x3 grid and the feature counts): group "DEPTH".
template <>
struct ReportSignals<DepthGrid> {
  static constexpr std::string_view kGroup = "DEPTH";
  static const std::vector<Signal<DepthGrid>>& Table();
};

}  // namespace uav
