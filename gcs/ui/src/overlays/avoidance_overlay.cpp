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

ImVec2 DrawAvoidanceLegend(ImDrawList* dl, ImVec2 at) {
  const ImU32 text = IM_COL32(220, 220, 220, 255), box = IM_COL32(20, 24, 30, 220);
  const float line = ImGui::GetTextLineHeight() + 2, ramp_w = 90;
  const ImVec2 size(ramp_w + 150, 4 * line + 6);
  dl->AddRectFilled(at, ImVec2(at.x + size.x, at.y + size.y), box, 3.0f);
  float y = at.y + 3;
  // The height ramp of the occupied cells.
  for (int k = 0; k < 30; ++k) {
    const float x = at.x + 4 + ramp_w * k / 30.0f;
    dl->AddRectFilled(ImVec2(x, y + 2), ImVec2(x + ramp_w / 30.0f + 1, y + line - 2),
                      AvoidanceHeightColour(kGroundUpM + 11.5 * k / 29.0, 255));
  }
  dl->AddText(ImVec2(at.x + 8 + ramp_w, y), text, "occupied, 0.5-12 m up");
  y += line;
  dl->AddLine(ImVec2(at.x + 4, y + line / 2), ImVec2(at.x + 4 + ramp_w, y + line / 2), IM_COL32(120, 220, 255, 220), 1.5f);
  dl->AddText(ImVec2(at.x + 8 + ramp_w, y), text, "planned path");
  y += line;
  dl->AddLine(ImVec2(at.x + 4, y + line / 2), ImVec2(at.x + 4 + ramp_w, y + line / 2), IM_COL32(60, 255, 120, 255), 3.5f);
  dl->AddText(ImVec2(at.x + 8 + ramp_w, y), text, "committed: seen free");
  y += line;
  const ImVec2 g(at.x + 4 + ramp_w / 2, y + line / 2);
  dl->AddCircle(g, 5, IM_COL32(120, 220, 255, 220), 16, 2.0f);
  dl->AddText(ImVec2(at.x + 8 + ramp_w, y), text, "goal (red: no path)");
  return size;
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
  // What the colours mean, in the map's lower left corner.
  const ImVec2 corner(m.dl->GetClipRectMin().x + 6, m.dl->GetClipRectMax().y - 4 * (ImGui::GetTextLineHeight() + 2) - 12);
  DrawAvoidanceLegend(m.dl, corner);
}

}  // namespace uav::gcs
