// Obstacle avoidance (thesis 7.2) on the map: the vehicle's 3-D map as occupied cells coloured
// by height (the ground left out), the planner's path to the goal and, drawn over it, the part
// the vehicle has seen free and is committed to.
#include <algorithm>
#include <cmath>
#include <vector>

#include "overlays.hpp"

namespace uav::gcs {

namespace {
// A report older than this is not drawn: the vehicle sends one every 0.5 s while it travels.
constexpr double kStaleAfterS = 2.0;
// Cells lower than this above home are the ground the cameras saw, not obstacles.
constexpr double kGroundUpM = 0.5;
}  // namespace

ImU32 AvoidanceHeightColour(double up_m, int alpha) {
  // 0.5 m: blue, through green and yellow, to red at 12 m and above.
  const float t = static_cast<float>(std::clamp((up_m - kGroundUpM) / 11.5, 0.0, 1.0));
  const float r = std::clamp(2.0f * t, 0.0f, 1.0f), g = std::clamp(t < 0.5f ? 2.0f * t : 2.0f - 2.0f * t, 0.0f, 1.0f) * 0.9f + 0.1f,
              b = std::clamp(1.0f - 2.0f * t, 0.0f, 1.0f);
  return IM_COL32(static_cast<int>(40 + 215 * r), static_cast<int>(40 + 215 * g), static_cast<int>(40 + 215 * b), alpha);
}

const AvoidanceReport* FreshAvoidance(const VehicleModel& v, double now) {
  return v.reports.Fresh<AvoidanceReport>(now, kStaleAfterS);
}

void DrawAvoidanceOnMap(const VehicleModel& v, const MapCanvas& m, double now) {
  const AvoidanceReport* r = FreshAvoidance(v, now);
  if (!r) return;
  // Cells from the lowest up, so that what stands highest is on top, as seen from above.
  std::vector<const Eigen::Vector3f*> cells;
  cells.reserve(r->occupied_N.size());
  for (const Eigen::Vector3f& c : r->occupied_N)
    if (-c.z() >= kGroundUpM) cells.push_back(&c);
  std::sort(cells.begin(), cells.end(), [](const Eigen::Vector3f* a, const Eigen::Vector3f* b) { return a->z() > b->z(); });
  const float half = std::max(1.0f, static_cast<float>(0.5 * r->cell_m * m.px_per_m));
  for (const Eigen::Vector3f* c : cells) {
    const ImVec2 s = m.ToScreen(c->x(), c->y());
    m.dl->AddRectFilled(ImVec2(s.x - half, s.y - half), ImVec2(s.x + half, s.y + half), AvoidanceHeightColour(-c->z(), 170));
  }
  // The path (thin) and its committed part (thick), then the goal.
  const ImU32 path_colour = IM_COL32(120, 220, 255, 220), committed_colour = IM_COL32(60, 255, 120, 255);
  auto polyline = [&](const std::vector<Eigen::Vector3d>& p, ImU32 colour, float width) {
    std::vector<ImVec2> pts;
    for (const Eigen::Vector3d& q : p) pts.push_back(m.ToScreen(q.x(), q.y()));
    if (pts.size() >= 2) m.dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, 0, width);
  };
  polyline(r->path_N, path_colour, 1.5f);
  polyline(r->Committed(), committed_colour, 3.5f);
  const ImVec2 g = m.ToScreen(r->goal_N.x(), r->goal_N.y());
  const ImU32 goal_colour = r->state == AvoidState::kNoPath ? IM_COL32(255, 70, 60, 255) : path_colour;
  m.dl->AddCircle(g, 6, goal_colour, 16, 2.0f);
  m.dl->AddLine(ImVec2(g.x - 4, g.y - 4), ImVec2(g.x + 4, g.y + 4), goal_colour, 2.0f);
  m.dl->AddLine(ImVec2(g.x - 4, g.y + 4), ImVec2(g.x + 4, g.y - 4), goal_colour, 2.0f);
}

}  // namespace uav::gcs
