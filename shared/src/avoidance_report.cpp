#include "uav/shared/avoidance_report.hpp"

#include <algorithm>

namespace uav {

double AvoidanceReport::PathLength() const {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < path_N.size(); ++i) s += (path_N[i + 1] - path_N[i]).norm();
  return s;
}

std::vector<Eigen::Vector3d> AvoidanceReport::Committed() const {
  std::vector<Eigen::Vector3d> out;
  if (path_N.empty()) return out;
  out.push_back(path_N.front());
  double left = std::max(0.0, seen_free_m);
  for (std::size_t i = 0; i + 1 < path_N.size() && left > 0; ++i) {
    const double len = (path_N[i + 1] - path_N[i]).norm();
    if (len >= left) {
      out.push_back(path_N[i] + (path_N[i + 1] - path_N[i]) * (left / len));
      break;
    }
    out.push_back(path_N[i + 1]);
    left -= len;
  }
  return out;
}

// The plan's lengths, the map's size and the planning time.
const std::vector<Signal<AvoidanceReport>>& ReportSignals<AvoidanceReport>::Table() {
  using F = SignalFormat;
  using R = AvoidanceReport;
  static const std::vector<Signal<R>> k = {
      {{"path", "path_m", "m", "planned path from the vehicle", F::kMetres}, [](const R& r) { return r.PathLength(); }},
      {{"seen_free", "seen_free_m", "m", "of the path, seen free (committed)", F::kMetres}, [](const R& r) { return r.seen_free_m; }},
      {{"map_cells", "map_cells", "1", "onboard map nodes", F::kInteger}, [](const R& r) { return double(r.map_cells); }},
      {{"occupied", "num_cells", "1", "occupied cells around the vehicle", F::kInteger},
       [](const R& r) { return double(r.occupied_N.size()); }},
      {{"planning", "planning_ms", "ms", "", F::kMilliseconds}, [](const R& r) { return r.planning_ms; }},
  };
  return k;
}

}  // namespace uav
