// The selected vehicle on the map: its accepted mission, home, geofence, trails, the target of
// the goto it flies (this GCS's) and itself.
#include <cmath>
#include <cstdio>
#include <deque>
#include <vector>

#include "overlays.hpp"

namespace uav::gcs {

constexpr ImU32 kMission = IM_COL32(255, 170, 60, 255);
constexpr ImU32 kVehicle = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kFence = IM_COL32(230, 60, 60, 200);
constexpr ImU32 kTrail = IM_COL32(255, 80, 80, 200);         // the flown estimate
constexpr ImU32 kGpsTrail = IM_COL32(255, 230, 80, 180);     // GPS fixes
constexpr ImU32 kVoTrail = IM_COL32(80, 220, 255, 220);      // the VO+IMU filter
constexpr ImU32 kTruthTrail = IM_COL32(255, 255, 255, 160);  // simulation's truth
constexpr ImU32 kGotoTarget = IM_COL32(80, 255, 120, 255);

void DrawVehicleOnMap(GcsModel& model, const VehicleModel* v, const MapCanvas& m) {
  const SurveyPlanner& planner = model.missions().planner();
  if (v && v->mission) {
    std::vector<ImVec2> pts;
    for (const auto& it : v->mission->items)
      if (it.command == waypoints::mav_cmd::kNavWaypoint) {
        const Eigen::Vector2d ne = planner.ToMap({it.latitude_deg, it.longitude_deg, 0});
        pts.push_back(m.ToScreen(ne.x(), ne.y()));
      }
    if (pts.size() > 1) m.dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), kMission, 0, 1.0f);
    for (const auto& p : pts) m.dl->AddCircleFilled(p, 2.5f, kMission);
  }
  const ImVec2 home = m.ToScreen(0, 0);
  // The geofence the vehicle enforces: its radius around home.
  if (v && v->state && v->state->fence_radius_m > 0) {
    const float px = static_cast<float>(v->state->fence_radius_m * m.px_per_m);
    m.dl->AddCircle(home, px, kFence, 128, 2.0f);
    char label[64];
    std::snprintf(label, sizeof label, "geofence %.0f m, %.0f m high", v->state->fence_radius_m, v->state->fence_alt_m);
    m.dl->AddText(ImVec2(home.x + px * 0.7071f + 4, home.y - px * 0.7071f - 14), kFence, label);
  }
  m.dl->AddRect(ImVec2(home.x - 7, home.y - 7), ImVec2(home.x + 7, home.y + 7), kVehicle, 0, 0, 2.0f);
  m.dl->AddText(ImVec2(home.x + 9, home.y - 7), kVehicle, "H");
  if (!v) return;
  // The estimate's trail, and beside it (thesis ch. 5) the GPS fixes, the VO+IMU track and, in
  // simulation, the truth.
  auto polyline = [&](const std::deque<Eigen::Vector2d>& points, ImU32 colour, float width) {
    std::vector<ImVec2> line;
    for (const auto& p_N : points) line.push_back(m.ToScreen(p_N.x(), p_N.y()));
    if (line.size() > 1) m.dl->AddPolyline(line.data(), static_cast<int>(line.size()), colour, 0, width);
  };
  polyline(v->truth_trail, kTruthTrail, 1.0f);
  polyline(v->gps_trail, kGpsTrail, 1.0f);
  polyline(v->vo_trail, kVoTrail, 1.5f);
  polyline(v->trail, kTrail, 1.5f);
  if (const auto target_N = model.commands().ActiveGoto(v->id)) {
    const ImVec2 t = m.ToScreen(target_N->x(), target_N->y());
    m.dl->AddCircle(t, 9.0f, kGotoTarget, 24, 2.0f);
    m.dl->AddLine(ImVec2(t.x - 13, t.y), ImVec2(t.x + 13, t.y), kGotoTarget, 1.5f);
    m.dl->AddLine(ImVec2(t.x, t.y - 13), ImVec2(t.x, t.y + 13), kGotoTarget, 1.5f);
    char label[48];
    std::snprintf(label, sizeof label, "goto %.0f m", -target_N->z());
    m.dl->AddText(ImVec2(t.x + 12, t.y + 2), kGotoTarget, label);
    if (v->state)
      m.dl->AddLine(m.ToScreen(v->state->p_N.x(), v->state->p_N.y()), t, kGotoTarget & IM_COL32(255, 255, 255, 110), 1.0f);
  }
  if (v->state) {
    const double h = v->state->euler.psi;
    const ImVec2 s = m.ToScreen(v->state->p_N.x(), v->state->p_N.y());
    auto rot = [&](float fwd, float right) {  // body offset in pixels to screen
      return ImVec2(s.x + static_cast<float>(fwd * std::sin(h) + right * std::cos(h)),
                    s.y - static_cast<float>(fwd * std::cos(h) - right * std::sin(h)));
    };
    m.dl->AddTriangleFilled(rot(12, 0), rot(-7, -7), rot(-7, 7), kVehicle);
  }
}

}  // namespace uav::gcs
