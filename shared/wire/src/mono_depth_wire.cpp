#include "uav/wire/messages.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "uavmsg/mono_depth_t.hpp"

namespace uav {
namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("mono_depth_t: " + what);
}
}  // namespace

DepthGrid FromMessage(const uavmsg::mono_depth_t& m) {
  using M = uavmsg::mono_depth_t;
  Require(m.rows >= 1 && m.cols >= 1 && m.rows * m.cols == m.num_cells && m.num_cells <= M::MAX_CELLS,
          "grid " + std::to_string(m.rows) + "x" + std::to_string(m.cols) + " with num_cells " + std::to_string(m.num_cells) +
              " (at most " + std::to_string(M::MAX_CELLS) + ")");
  const std::size_t n = static_cast<std::size_t>(m.num_cells);
  Require(m.state.size() == n && m.depth_m.size() == n && m.sigma_m.size() == n && m.features.size() == n &&
              m.confidence.size() == n && m.cell_reason.size() == n,
          "cell arrays do not have num_cells entries");
  Require(std::isfinite(m.obstacle_depth_m) && m.obstacle_depth_m > 0, "obstacle_depth_m is not a positive number");
  Require(m.tracked >= 0 && m.measured >= 0, "negative feature counts");
  DepthGrid g;
  g.utime = m.utime;
  g.camera = m.camera;
  g.rows = m.rows;
  g.cols = m.cols;
  g.healthy = m.healthy;
  g.reason = m.reason;
  g.obstacle_depth_m = m.obstacle_depth_m;
  g.tracked = m.tracked;
  g.measured = m.measured;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string cell = "cell " + std::to_string(i) + ": ";
    Require(m.state[i] >= M::STATE_UNKNOWN && m.state[i] <= M::STATE_OBSTACLE, cell + "state " + std::to_string(m.state[i]) + " is not 0..2");
    Require(std::isfinite(m.depth_m[i]) && m.depth_m[i] >= 0 && std::isfinite(m.sigma_m[i]) && m.sigma_m[i] >= 0,
            cell + "depth or sigma is not a finite non-negative number");
    Require(std::isfinite(m.confidence[i]) && m.confidence[i] >= 0 && m.confidence[i] <= 1, cell + "confidence is not in 0..1");
    Require(m.features[i] >= 0, cell + "negative feature count");
    DepthCell c;
    c.state = static_cast<CellState>(m.state[i]);
    Require(c.state == CellState::kUnknown || m.depth_m[i] > 0, cell + "known without a depth");
    Require(m.healthy || c.state == CellState::kUnknown, cell + "known in an unhealthy report");
    c.depth_m = m.depth_m[i];
    c.sigma_m = m.sigma_m[i];
    c.features = m.features[i];
    c.confidence = m.confidence[i];
    c.reason = m.cell_reason[i];
    g.cells.push_back(c);
  }
  return g;
}

uavmsg::mono_depth_t ToMessage(const DepthGrid& g) {
  uavmsg::mono_depth_t m{};
  m.utime = g.utime;
  m.camera = g.camera;
  m.healthy = g.healthy;
  m.reason = g.reason;
  m.obstacle_depth_m = static_cast<float>(g.obstacle_depth_m);
  m.tracked = static_cast<int16_t>(std::min(g.tracked, 32767));
  m.measured = static_cast<int16_t>(std::min(g.measured, 32767));
  m.rows = static_cast<int16_t>(g.rows);
  m.cols = static_cast<int16_t>(g.cols);
  m.num_cells = static_cast<int16_t>(g.cells.size());
  for (const DepthCell& c : g.cells) {
    m.state.push_back(static_cast<int8_t>(c.state));
    m.depth_m.push_back(static_cast<float>(c.depth_m));
    m.sigma_m.push_back(static_cast<float>(c.sigma_m));
    m.features.push_back(static_cast<int16_t>(std::min(c.features, 32767)));
    m.confidence.push_back(static_cast<float>(c.confidence));
    m.cell_reason.push_back(c.reason);
  }
  return m;
}

}  // namespace uav
