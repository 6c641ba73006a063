// The survey being planned, on the map.
#include <cmath>
#include <cstdio>

#include "overlays.hpp"

namespace uav::gcs {

constexpr ImU32 kPolygon = IM_COL32(80, 220, 100, 255);
constexpr ImU32 kCoverage = IM_COL32(90, 150, 230, 60);
constexpr ImU32 kPath = IM_COL32(120, 180, 255, 255);

void DrawSurveyOnMap(GcsModel& model, const MapCanvas& m) {
  const SurveyPlanner& planner = model.missions().planner();
  const bool have_live_map = model.selected() && !model.selected()->live_map.tiles.empty();
  if (const auto& plan = planner.plan()) {
    const double half = 0.5 * plan->footprint.across_m;
    // The predicted coverage of each capture leg, until the vehicle's real map takes its place.
    for (std::size_t i = 0; i + 1 < plan->waypoints.size() && !have_live_map; ++i) {
      const auto& a = plan->waypoints[i];
      const auto& b = plan->waypoints[i + 1];
      if (a.kind != waypoints::SurveyWaypoint::Kind::kCaptureStart || b.line != a.line) continue;
      Eigen::Vector2d d = (b.p_N - a.p_N).head<2>();
      const double along = 0.5 * plan->footprint.along_m;
      const Eigen::Vector2d u = d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized())
                                                : Eigen::Vector2d(std::cos(a.yaw_rad), std::sin(a.yaw_rad));
      const Eigen::Vector2d n(-u.y(), u.x());
      const Eigen::Vector2d A = a.p_N.head<2>() - along * u, B = b.p_N.head<2>() + along * u;
      const Eigen::Vector2d corners[4] = {A + half * n, B + half * n, B - half * n, A - half * n};
      ImVec2 q[4];
      for (int k = 0; k < 4; ++k) q[k] = m.ToScreen(corners[k].x(), corners[k].y());
      m.dl->AddConvexPolyFilled(q, 4, kCoverage);
    }
    for (std::size_t i = 0; i + 1 < plan->waypoints.size(); ++i)
      m.dl->AddLine(m.ToScreen(plan->waypoints[i].p_N.x(), plan->waypoints[i].p_N.y()),
                    m.ToScreen(plan->waypoints[i + 1].p_N.x(), plan->waypoints[i + 1].p_N.y()), kPath, 1.5f);
    if (!plan->waypoints.empty())
      m.dl->AddCircle(m.ToScreen(plan->waypoints[0].p_N.x(), plan->waypoints[0].p_N.y()), 6.0f, kPath, 0, 2.0f);
  }
  const auto poly = planner.polygon_map();
  for (std::size_t i = 0; i < poly.size() && poly.size() > 1; ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    m.dl->AddLine(m.ToScreen(a.x(), a.y()), m.ToScreen(b.x(), b.y()), kPolygon, 2.0f);
  }
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const ImVec2 s = m.ToScreen(poly[i].x(), poly[i].y());
    m.dl->AddCircleFilled(s, 5.0f, kPolygon);
    char label[24];
    std::snprintf(label, sizeof label, "%zu", i);
    m.dl->AddText(ImVec2(s.x + 6, s.y - 14), kPolygon, label);
  }
}

}  // namespace uav::gcs
