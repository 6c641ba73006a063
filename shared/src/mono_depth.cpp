#include "uav/shared/mono_depth.hpp"

namespace uav {

const char* Name(CellState s) {
  switch (s) {
    case CellState::kUnknown: return "unknown";
    case CellState::kFree: return "free";
    case CellState::kObstacle: return "obstacle";
  }
  return "unknown";
}

// Depth from motion: every cell of the thesis's 4x3 grid (Fig. 3.11) by row and column from the
// top-left, 0 while unknown, and the feature counts.
namespace {

template <int kCell>
double CellDepth(const DepthGrid& g) {
  const int r = kCell / 4, c = kCell % 4;
  return r < g.rows && c < g.cols ? g.at(r, c).depth_m : 0.0;
}

}  // namespace

const std::vector<Signal<DepthGrid>>& ReportSignals<DepthGrid>::Table() {
  using F = SignalFormat;
  static const std::vector<Signal<DepthGrid>> k = {
      {{"r0c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<0>},
      {{"r0c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<1>},
      {{"r0c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<2>},
      {{"r0c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<3>},
      {{"r1c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<4>},
      {{"r1c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<5>},
      {{"r1c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<6>},
      {{"r1c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<7>},
      {{"r2c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<8>},
      {{"r2c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<9>},
      {{"r2c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<10>},
      {{"r2c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<11>},
      {{"tracked", "tracked", "1", "", F::kInteger}, [](const DepthGrid& g) { return double(g.tracked); }},
      {{"measured", "measured", "1", "", F::kInteger}, [](const DepthGrid& g) { return double(g.measured); }},
  };
  return k;
}

}  // namespace uav
