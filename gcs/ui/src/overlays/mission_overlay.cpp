// The mission being edited, on the map: the items in order from home (the take-off), each
// position item a numbered circle (the selected one filled), the others named beside the point
// where they happen; its geofence zones and rally points.
#include <cstdio>
#include <vector>

#include "overlays.hpp"

namespace uav::gcs {

namespace {

constexpr ImU32 kLeg = IM_COL32(255, 200, 60, 230);
constexpr ImU32 kItem = IM_COL32(255, 200, 60, 255);
constexpr ImU32 kSelected = IM_COL32(255, 120, 40, 255);
constexpr ImU32 kFlown = IM_COL32(90, 240, 120, 255);
constexpr ImU32 kInclusion = IM_COL32(80, 230, 120, 255);
constexpr ImU32 kExclusion = IM_COL32(240, 70, 70, 255);
constexpr ImU32 kRally = IM_COL32(200, 120, 255, 255);

// The geofence zones (green: stay inside, red: keep out; the zone being drawn thicker) and the
// rally points (R).
void DrawFenceOnMap(const MissionEditor& editor, const SurveyPlanner& planner, const MapCanvas& m) {
  for (std::size_t z = 0; z < editor.fences.size(); ++z) {
    const FenceDraft& f = editor.fences[z];
    const ImU32 colour = f.inclusion ? kInclusion : kExclusion;
    const float width = static_cast<int>(z) == editor.fence_selected ? 3.0f : 1.5f;
    std::vector<ImVec2> pts;
    for (const GeodeticPoint& v : f.vertices) {
      const Eigen::Vector2d p = planner.ToMap(v);
      pts.push_back(m.ToScreen(p.x(), p.y()));
    }
    if (f.circle && !pts.empty()) {
      m.dl->AddCircle(pts[0], static_cast<float>(f.radius_m * m.px_per_m), colour, 64, width);
    } else if (!pts.empty()) {
      m.dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, pts.size() >= 3 ? ImDrawFlags_Closed : 0, width);
      for (const ImVec2& q : pts) m.dl->AddCircleFilled(q, 3.5f, colour);
    }
    if (!pts.empty()) m.dl->AddText(ImVec2(pts[0].x + 6, pts[0].y + 4), colour, editor.ZoneLabel(z).c_str());
  }
  for (const GeodeticPoint& r : editor.rally) {
    const Eigen::Vector2d p = planner.ToMap(r);
    const ImVec2 s = m.ToScreen(p.x(), p.y());
    m.dl->AddRectFilled(ImVec2(s.x - 7, s.y - 7), ImVec2(s.x + 7, s.y + 7), kRally);
    m.dl->AddText(ImVec2(s.x - 3, s.y - 7), IM_COL32(0, 0, 0, 255), "R");
  }
}

}  // namespace

void DrawMissionPlanOnMap(GcsModel& model, const MapCanvas& m) {
  const MissionEditor& editor = model.missions().editor();
  const SurveyPlanner& planner = model.missions().planner();
  DrawFenceOnMap(editor, planner, m);
  const int flown = model.FlownMissionRow();  // ringed green: the item being flown
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // the take-off: over home
  float note_dy = 0;                             // items without a point stack their names
  for (std::size_t i = 0; i < editor.items().size(); ++i) {
    const PlanItem& it = editor.items()[i];
    char label[48];
    if (it.HasPosition()) {
      const Eigen::Vector2d p = planner.ToMap({it.latitude_deg, it.longitude_deg, 0});
      m.dl->AddLine(m.ToScreen(at.x(), at.y()), m.ToScreen(p.x(), p.y()), kLeg, 2.0f);
      at = p;
      note_dy = 0;
      const ImVec2 s = m.ToScreen(p.x(), p.y());
      const bool selected = static_cast<int>(i) == editor.selected;
      if (selected) m.dl->AddCircleFilled(s, 9.0f, kSelected);
      m.dl->AddCircle(s, 9.0f, kItem, 0, 2.0f);
      if (static_cast<int>(i) == flown) m.dl->AddCircle(s, 14.0f, kFlown, 0, 3.0f);
      std::snprintf(label, sizeof label, "%zu", i + 1);
      m.dl->AddText(ImVec2(s.x - 4, s.y - 7), selected ? IM_COL32(0, 0, 0, 255) : kItem, label);
      if (it.action != PlanAction::kWaypoint || it.hold_s > 0) {
        std::snprintf(label, sizeof label, "%s%s", Name(it.action), it.hold_s > 0 ? " (hold)" : "");
        m.dl->AddText(ImVec2(s.x + 11, s.y - 7), kItem, label);
      }
    } else {
      if (it.action == PlanAction::kReturn) {
        m.dl->AddLine(m.ToScreen(at.x(), at.y()), m.ToScreen(0, 0), kLeg, 1.0f);
        at = Eigen::Vector2d::Zero();
      }
      const ImVec2 s = m.ToScreen(at.x(), at.y());
      std::snprintf(label, sizeof label, "%s%zu %s", static_cast<int>(i) == flown ? "> " : "", i + 1, Name(it.action));
      m.dl->AddText(ImVec2(s.x + 11, s.y + 6 + note_dy), static_cast<int>(i) == flown ? kFlown : kItem, label);
      note_dy += 13;
      if (it.action == PlanAction::kSurvey && planner.plan() && !planner.plan()->waypoints.empty()) {
        // The survey's path is drawn by the survey overlay; the mission goes on from its end.
        const auto& w = planner.plan()->waypoints;
        m.dl->AddLine(s, m.ToScreen(w.front().p_N.x(), w.front().p_N.y()), kLeg, 2.0f);
        at = w.back().p_N.head<2>();
      }
    }
  }
}

}  // namespace uav::gcs
