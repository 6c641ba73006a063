// The mission editor's item list (QGroundControl's Plan view, beside the map): the take-off
// altitude and cruise speed, each item's action, altitude, speed and hold time, buttons that add
// the items without a point of their own, the geofence zones and rally points, upload,
// download of the vehicle's mission, and its file. Opened by the Map panel's "Edit mission";
// the map adds, drags and deletes the items with a point.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "number_field.hpp"
#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

constexpr PlanAction kChoosable[] = {PlanAction::kWaypoint, PlanAction::kLoiter, PlanAction::kLand};
const ImVec4 kProblem(1.0f, 0.45f, 0.35f, 1.0f);
constexpr ImU32 kFlownRow = IM_COL32(40, 110, 60, 200);

// What the fields allow: the vehicle's own limits (its parameters), within the mission format's.
struct FieldLimits {
  double alt_max_m, speed_max_m_s, range_m;
  explicit FieldLimits(const waypoints::VehicleLimits& v)
      : alt_max_m(std::min(v.ceiling_m, waypoints::kMaxSurveyAltitude_m)), speed_max_m_s(v.max_speed_m_s), range_m(v.range_m) {}
};

// A position typed as north/east of home [m] or as latitude/longitude [deg].
void PositionCells(GcsModel& model, UiContext& ctx, PlanItem& it, const std::string& n, const FieldLimits& lim) {
  const SurveyPlanner& planner = model.missions().planner();
  if (ctx.state.mission_latlon) {
    ImGui::TableNextColumn();
    NumberField(ctx, "mission:lat:" + n, &it.latitude_deg, -90, 90, "%.7f", "deg");
    ImGui::TableNextColumn();
    NumberField(ctx, "mission:lon:" + n, &it.longitude_deg, -180, 180, "%.7f", "deg");
    return;
  }
  Eigen::Vector2d ne = planner.ToMap({it.latitude_deg, it.longitude_deg, 0});
  ImGui::TableNextColumn();
  bool moved = NumberField(ctx, "mission:north:" + n, &ne.x(), -lim.range_m, lim.range_m, "%.1f", "m");
  ImGui::TableNextColumn();
  moved |= NumberField(ctx, "mission:east:" + n, &ne.y(), -lim.range_m, lim.range_m, "%.1f", "m");
  if (moved) {
    const GeodeticPoint g = planner.FromMap(ne);
    it.latitude_deg = g.latitude_deg, it.longitude_deg = g.longitude_deg;
  }
}

void DrawRow(GcsModel& model, UiContext& ctx, std::size_t i, const FieldLimits& lim, const std::string& problem,
             bool flown, bool* erase) {
  MissionEditor& editor = model.missions().editor();
  PlanItem& it = editor.item(i);
  const std::string n = std::to_string(i + 1);
  ImGui::TableNextRow();
  if (flown) ImGui::TableSetBgColor(ImGuiTableBgTarget_RowBg0, kFlownRow);
  ImGui::TableNextColumn();
  if (!problem.empty()) ImGui::PushStyleColor(ImGuiCol_Text, kProblem);
  const std::string mark = (flown ? "> " : "") + n + (problem.empty() ? "" : " !");
  if (ImGui::Selectable(mark.c_str(), editor.selected == static_cast<int>(i))) editor.selected = static_cast<int>(i);
  if (!problem.empty()) {
    ImGui::PopStyleColor();
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", problem.c_str());
  }
  RegisterLastItem(ctx, "mission:select:" + n);
  ImGui::TableNextColumn();
  if (it.HasPosition()) {
    // A point item may become another point item (waypoint, loiter, land).
    ImGui::SetNextItemWidth(-1);
    if (ImGui::BeginCombo(("##mission:action:" + n).c_str(), Name(it.action))) {
      for (PlanAction a : kChoosable)
        if (ImGui::Selectable(Name(a), a == it.action)) it.action = a;
      ImGui::EndCombo();
    }
    RegisterLastItem(ctx, "mission:action:" + n);
    PositionCells(model, ctx, it, n, lim);
  } else {
    ImGui::TextUnformatted(Name(it.action));
    ImGui::TableNextColumn();
    ImGui::TableNextColumn();
  }
  ImGui::TableNextColumn();
  if (it.action == PlanAction::kWaypoint || it.action == PlanAction::kLoiter)
    NumberField(ctx, "mission:alt:" + n, &it.altitude_m, 1.0, lim.alt_max_m, "%.1f", "m");
  ImGui::TableNextColumn();
  if (it.action != PlanAction::kCameraStop)
    NumberField(ctx, "mission:speed:" + n, &it.speed_m_s, 0.0, lim.speed_max_m_s, "%.1f", "m/s");
  ImGui::TableNextColumn();
  if (it.action == PlanAction::kWaypoint || it.action == PlanAction::kLoiter)
    NumberField(ctx, "mission:hold:" + n, &it.hold_s, 0.0, 3600.0, "%.0f", "s");
  ImGui::TableNextColumn();
  if (ImGui::SmallButton(("x##mission:delete:" + n).c_str())) *erase = true;
  RegisterLastItem(ctx, "mission:delete:" + n);
}

// The geofence zones and rally points: what a map click adds, a row per zone (keep in or out,
// a circle's radius, delete) and per rally point (its altitude, delete).
void DrawFenceSection(MissionEditor& editor, UiContext& ctx, const FieldLimits& lim) {
  ImGui::Separator();
  ImGui::TextUnformatted("Geofence and rally points");
  ImGui::TextUnformatted("map click adds:");
  ImGui::SameLine();
  const struct {
    MapTool tool;
    const char* label;
    const char* id;
  } tools[] = {{MapTool::kWaypoint, "waypoint", "mission:tool_waypoint"},
               {MapTool::kFenceVertex, "fence vertex", "mission:tool_fence"},
               {MapTool::kRallyPoint, "rally point", "mission:tool_rally"}};
  for (const auto& t : tools) {
    if (ImGui::RadioButton(t.label, editor.tool == t.tool)) editor.tool = t.tool;
    RegisterLastItem(ctx, t.id);
    ImGui::SameLine();
  }
  ImGui::NewLine();
  const struct {
    bool inclusion, circle;
    const char* label;
    const char* id;
  } zones[] = {{true, false, "+ keep-in polygon", "mission:add_inclusion"},
               {false, false, "+ keep-out polygon", "mission:add_exclusion"},
               {true, true, "+ keep-in circle", "mission:add_inclusion_circle"},
               {false, true, "+ keep-out circle", "mission:add_exclusion_circle"}};
  for (const auto& z : zones) {
    if (ImGui::Button(z.label)) {
      FenceDraft f;
      f.inclusion = z.inclusion;
      f.circle = z.circle;
      editor.fences.push_back(f);
      editor.fence_selected = static_cast<int>(editor.fences.size()) - 1;
      editor.tool = MapTool::kFenceVertex;  // the next clicks draw it
    }
    RegisterLastItem(ctx, z.id);
    ImGui::SameLine();
  }
  ImGui::NewLine();
  std::optional<std::size_t> erase_zone, erase_rally;
  for (std::size_t z = 0; z < editor.fences.size(); ++z) {
    FenceDraft& f = editor.fences[z];
    const std::string n = std::to_string(z + 1);
    ImGui::PushID(static_cast<int>(z));
    char label[96];
    std::snprintf(label, sizeof label, "%s: %zu %s", editor.ZoneLabel(z).c_str(), f.vertices.size(),
                  f.circle ? "centre" : "vertices");
    if (ImGui::Selectable(label, editor.fence_selected == static_cast<int>(z), 0, ImVec2(260, 0))) {
      editor.fence_selected = static_cast<int>(z);
      editor.tool = MapTool::kFenceVertex;
    }
    RegisterLastItem(ctx, "mission:fence:" + n);
    if (f.circle) {
      ImGui::SameLine();
      NumberField(ctx, "mission:radius:" + n, &f.radius_m, 1.0, 10000.0, "%.0f", "m", 70);
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("x")) erase_zone = z;
    RegisterLastItem(ctx, "mission:fence_delete:" + n);
    ImGui::PopID();
  }
  for (std::size_t k = 0; k < editor.rally.size(); ++k) {
    const std::string n = std::to_string(k + 1);
    ImGui::PushID(1000 + static_cast<int>(k));
    ImGui::AlignTextToFramePadding();
    ImGui::Text("rally %s, alt [m]", n.c_str());
    ImGui::SameLine();
    NumberField(ctx, "mission:rally_alt:" + n, &editor.rally[k].altitude_m, 1.0, lim.alt_max_m, "%.1f", "m", 70);
    ImGui::SameLine();
    if (ImGui::SmallButton("x")) erase_rally = k;
    RegisterLastItem(ctx, "mission:rally_delete:" + n);
    ImGui::PopID();
  }
  if (erase_zone) {
    editor.fences.erase(editor.fences.begin() + static_cast<std::ptrdiff_t>(*erase_zone));
    editor.fence_selected = -1;
  }
  if (erase_rally) editor.rally.erase(editor.rally.begin() + static_cast<std::ptrdiff_t>(*erase_rally));
}

}  // namespace

void DrawMissionPanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  if (!st.map_edit_mission) return;
  // Under the map it edits, over the survey panel (whose files it has).
  PlaceWindow("Mission");
  if (!ImGui::Begin("Mission", &st.map_edit_mission)) {
    ImGui::End();
    return;
  }
  MissionEditor& editor = model.missions().editor();
  bool limits_from_vehicle = false;
  const waypoints::VehicleLimits vehicle = model.MissionLimits(&limits_from_vehicle);
  const FieldLimits lim(vehicle);
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted("take-off [m]");
  ImGui::SameLine();
  NumberField(ctx, "mission:takeoff", &editor.takeoff_alt_m, 1.0, lim.alt_max_m, "%.1f", "m", 70);
  ImGui::SameLine();
  ImGui::TextUnformatted("cruise [m/s]");
  ImGui::SameLine();
  NumberField(ctx, "mission:cruise", &editor.cruise_speed_m_s, 0.5, lim.speed_max_m_s, "%.1f", "m/s", 70);
  ImGui::SameLine();
  ImGui::TextDisabled("limits: %.0f m up, %.1f m/s, %.0f m out (%s)", lim.alt_max_m, lim.speed_max_m_s, lim.range_m,
                      limits_from_vehicle ? "the vehicle's parameters" : "defaults: no parameters from a vehicle yet");
  // Items without a point of their own go after the selected item (or at the end).
  const std::size_t at = editor.selected >= 0 ? static_cast<std::size_t>(editor.selected) + 1 : editor.items().size();
  for (PlanAction a : {PlanAction::kPhoto, PlanAction::kSurvey, PlanAction::kReturn}) {
    const std::string label = std::string("+ ") + Name(a);
    if (ImGui::Button(label.c_str())) {
      PlanItem p;
      p.action = a;
      editor.Insert(at, p);
    }
    RegisterLastItem(ctx, std::string("mission:add_") + Name(a));
    ImGui::SameLine();
  }
  if (ImGui::Button("Clear")) editor.Clear();
  RegisterLastItem(ctx, "mission:clear");
  ImGui::SameLine();
  ImGui::Checkbox("lat/lon", &st.mission_latlon);
  RegisterLastItem(ctx, "mission:latlon");
  ImGui::TextDisabled(editor.items().empty() ? "click the map to add waypoints; with no items the survey is the mission"
                                             : "speed 0: unchanged   hold: seconds at the point");
  // Checked as the vehicle will check it; the item the selected vehicle flies is highlighted when
  // it holds this mission.
  const EditorCheck check = editor.Check(model.missions().planner(), model.missions().planner().origin(), vehicle);
  const VehicleModel* v = model.selected();
  const int flown_row = FlownRow(v, check);
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY | ImGuiTableFlags_BordersInnerV;
  std::optional<std::size_t> erase;
  const float fence_rows = 5.0f + static_cast<float>(editor.fences.size() + editor.rally.size() +
                                                      std::min<std::size_t>(check.problems.size(), 3) +
                                                      st.number_refused.size());
  if (ImGui::BeginTable("mission_items", 8, flags, ImVec2(0, -ImGui::GetFrameHeightWithSpacing() * (2 + fence_rows)))) {
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableSetupColumn("#", ImGuiTableColumnFlags_WidthFixed, 40);
    ImGui::TableSetupColumn("action", ImGuiTableColumnFlags_WidthStretch, 1.3f);
    ImGui::TableSetupColumn(st.mission_latlon ? "lat [deg]" : "N [m]", ImGuiTableColumnFlags_WidthStretch, st.mission_latlon ? 1.6f : 1.0f);
    ImGui::TableSetupColumn(st.mission_latlon ? "lon [deg]" : "E [m]", ImGuiTableColumnFlags_WidthStretch, st.mission_latlon ? 1.6f : 1.0f);
    ImGui::TableSetupColumn("alt [m]", ImGuiTableColumnFlags_WidthStretch, 0.9f);
    ImGui::TableSetupColumn("speed [m/s]", ImGuiTableColumnFlags_WidthStretch, 0.9f);
    ImGui::TableSetupColumn("hold [s]", ImGuiTableColumnFlags_WidthStretch, 0.8f);
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 20);
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < editor.items().size(); ++i) {
      bool e = false;
      ImGui::PushID(static_cast<int>(i));
      DrawRow(model, ctx, i, lim, i < check.row_problems.size() ? check.row_problems[i] : "", static_cast<int>(i) == flown_row, &e);
      ImGui::PopID();
      if (e) erase = i;
    }
    ImGui::EndTable();
  }
  if (erase) editor.Delete(*erase);
  DrawNumberFieldRefusals(ctx, "mission:");
  DrawFenceSection(editor, ctx, lim);
  // What the vehicle would refuse, as it will say it; whole, wrapped at the window's edge.
  ImGui::PushTextWrapPos(0.0f);
  for (std::size_t k = 0; k < check.problems.size() && k < 3; ++k)
    ImGui::TextColored(kProblem, "%s", check.problems[k].text.c_str());
  if (check.problems.size() > 3) ImGui::TextColored(kProblem, "and %zu more", check.problems.size() - 3);
  if (!check.mission) ImGui::TextColored(kProblem, "%s", check.error.c_str());
  ImGui::PopTextWrapPos();
  if (check.mission) ImGui::Text("%zu mission items", check.mission->items.size());
  else ImGui::TextDisabled("not uploadable");
  ImGui::SameLine();
  // Disabled (greyed, never hidden) with the reason.
  BeginDisabledBecause(ctx, !check.mission || !v, !check.mission ? check.error : "no vehicle selected");
  if (ImGui::Button("Upload to vehicle")) model.UploadMission(ctx.now);
  RegisterLastItem(ctx, "mission:upload");
  EndDisabledBecause(ctx);
  ImGui::SameLine();
  BeginDisabledBecause(ctx, !v, "no vehicle selected");
  if (ImGui::Button("Download from vehicle")) model.DownloadMission(ctx.now);
  RegisterLastItem(ctx, "mission:download");
  EndDisabledBecause(ctx);
  // The mission's file (the survey panel's, which this window covers).
  DrawMissionFileRow(model, ctx, "mission:file", "mission:export", "mission:import");
  ImGui::End();
}

}  // namespace uav::gcs
