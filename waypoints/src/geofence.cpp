#include "uav/waypoints/geofence.hpp"

#include <cmath>
#include <stdexcept>

namespace uav::waypoints {

std::string ZoneName(bool inclusion, bool circle, int number) {
  return std::string(inclusion ? "keep-in " : "keep-out ") + (circle ? "circle " : "polygon ") + std::to_string(number);
}

std::string FenceItemOwner(const Mission& m, std::size_t i) {
  if (i >= m.items.size()) return "";
  int counts[2][2] = {{0, 0}, {0, 0}}, rally = 0;  // [inclusion][circle]
  for (std::size_t k = 0; k <= i;) {
    const MissionItem& it = m.items[k];
    if (IsRallyItem(it.command)) {
      ++rally;
      if (k == i) return "rally point " + std::to_string(rally);
      ++k;
      continue;
    }
    if (!IsFenceItem(it.command)) {
      if (k == i) return "";
      ++k;
      continue;
    }
    const bool inclusion = it.command == mav_cmd::kNavFencePolygonVertexInclusion ||
                           it.command == mav_cmd::kNavFenceCircleInclusion;
    const bool circle = it.command == mav_cmd::kNavFenceCircleInclusion || it.command == mav_cmd::kNavFenceCircleExclusion;
    // A polygon is a run of param1 vertices (1 when the count is unusable: the error names it).
    std::size_t run = 1;
    if (!circle && std::isfinite(it.param[0]) && it.param[0] >= 1 && it.param[0] <= kMaxPolygonVertices)
      run = static_cast<std::size_t>(it.param[0]);
    const int number = ++counts[inclusion][circle];
    if (i < k + run) return ZoneName(inclusion, circle, number);
    k += run;
  }
  return "";
}

bool FenceZone::Contains(const Eigen::Vector2d& p_N) const {
  if (polygon_N.empty()) return (p_N - centre_N).norm() <= radius_m;
  return waypoints::Contains(polygon_N, p_N);
}

std::string Geofence::Breach(const Eigen::Vector2d& p_N) const {
  bool any_inclusion = false, inside_inclusion = false;
  for (std::size_t i = 0; i < zones.size(); ++i) {
    const FenceZone& z = zones[i];
    if (z.inclusion) {
      any_inclusion = true;
      inside_inclusion |= z.Contains(p_N);
    } else if (z.Contains(p_N)) {
      return "inside " + z.name;
    }
  }
  if (any_inclusion && !inside_inclusion) return "outside every keep-in zone";
  return "";
}

const Eigen::Vector3d* Geofence::NearestRally(const Eigen::Vector2d& p_N) const {
  const Eigen::Vector3d* best = nullptr;
  for (const Eigen::Vector3d& r : rally_N)
    if (!best || (r.head<2>() - p_N).norm() < (best->head<2>() - p_N).norm()) best = &r;
  return best;
}

Geofence CompileGeofence(const Mission& m, const LocalNedFrame& home) {
  Geofence f;
  auto name = [&](std::size_t i) { return ItemLabel(m, i); };
  auto at = [&](const MissionItem& it) {
    return Eigen::Vector2d(home.ToNed({it.latitude_deg, it.longitude_deg, home.home().altitude_m}).head<2>());
  };
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    if (IsRallyItem(it.command)) {
      const double above_home = it.frame == mav_frame::kGlobal ? it.altitude_m - m.home.altitude_m : it.altitude_m;
      const Eigen::Vector2d p = at(it);
      f.rally_N.emplace_back(p.x(), p.y(), -above_home);
      continue;
    }
    if (!IsFenceItem(it.command)) continue;
    FenceZone z;
    z.inclusion = it.command == mav_cmd::kNavFencePolygonVertexInclusion || it.command == mav_cmd::kNavFenceCircleInclusion;
    if (it.command == mav_cmd::kNavFenceCircleInclusion || it.command == mav_cmd::kNavFenceCircleExclusion) {
      if (!(std::isfinite(it.param[0]) && it.param[0] > 0))
        throw std::invalid_argument(name(i) + ": param1 (radius) must be a positive number of metres");
      z.name = FenceItemOwner(m, i);
      z.centre_N = at(it);
      z.radius_m = it.param[0];
      f.zones.push_back(z);
      continue;
    }
    // A polygon: param1 vertices in a row, each repeating the count.
    const double count = it.param[0];
    if (!(std::isfinite(count) && count >= 3 && count == std::floor(count) && count <= kMaxPolygonVertices))
      throw std::invalid_argument(name(i) + ": param1 (vertex count) must be a whole number of at least 3");
    const auto n = static_cast<std::size_t>(count);
    if (i + n > m.items.size())
      throw std::invalid_argument(name(i) + ": the polygon has " + std::to_string(n) + " vertices, the mission ends first");
    for (std::size_t k = 0; k < n; ++k) {
      const MissionItem& v = m.items[i + k];
      if (v.command != it.command || v.param[0] != count)
        throw std::invalid_argument(name(i + k) + ": vertex " + std::to_string(k + 1) + " of the polygon at item " +
                                    std::to_string(i) + " (" + std::to_string(n) + " vertices) is missing");
      z.polygon_N.push_back(at(v));
    }
    try {
      ValidatePolygon(z.polygon_N);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(name(i) + ": fence polygon: " + e.what());
    }
    z.name = FenceItemOwner(m, i);
    f.zones.push_back(z);
    i += n - 1;
  }
  return f;
}

}  // namespace uav::waypoints
