// The mission editor's item list (QGroundControl's Plan view, beside the map): the take-off
// altitude and cruise speed, each item's action, altitude, speed and hold time, buttons that add
// the items without a point of their own, the geofence zones and rally points, upload, and
// download of the vehicle's mission. Opened by the Map panel's "Edit mission";
// the map adds, drags and deletes the items with a point.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

// A number field (its label drawn apart, so the registered rectangle is the field); width -1
// fills the table cell.
void NumberCell(UiContext& ctx, const std::string& id, double* value, double min, double max, const char* format,
                float width = -1) {
  ImGui::SetNextItemWidth(width);
  double shown = *value;
  if (ImGui::InputDouble(("##" + id).c_str(), &shown, 0, 0, format) && std::isfinite(shown))
    *value = std::clamp(shown, min, max);
  RegisterLastItem(ctx, id);
}

constexpr PlanAction kChoosable[] = {PlanAction::kWaypoint, PlanAction::kLoiter, PlanAction::kLand};

void DrawRow(MissionEditor& editor, UiContext& ctx, std::size_t i, bool* erase) {
  PlanItem& it = editor.item(i);
  const std::string n = std::to_string(i + 1);
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  if (ImGui::Selectable(n.c_str(), editor.selected == static_cast<int>(i))) editor.selected = static_cast<int>(i);
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
  } else {
    ImGui::TextUnformatted(Name(it.action));
  }
  ImGui::TableNextColumn();
  if (it.action == PlanAction::kWaypoint || it.action == PlanAction::kLoiter)
    NumberCell(ctx, "mission:alt:" + n, &it.altitude_m, 1.0, 120.0, "%.1f");
  ImGui::TableNextColumn();
  if (it.action != PlanAction::kCameraStop) NumberCell(ctx, "mission:speed:" + n, &it.speed_m_s, 0.0, 15.0, "%.1f");
  ImGui::TableNextColumn();
  if (it.action == PlanAction::kWaypoint || it.action == PlanAction::kLoiter)
    NumberCell(ctx, "mission:hold:" + n, &it.hold_s, 0.0, 3600.0, "%.0f");
  ImGui::TableNextColumn();
  if (ImGui::SmallButton(("x##mission:delete:" + n).c_str())) *erase = true;
  RegisterLastItem(ctx, "mission:delete:" + n);
}

// The geofence zones and rally points: what a map click adds, a row per zone (keep in or out,
// a circle's radius, delete) and per rally point (its altitude, delete).
void DrawFenceSection(MissionEditor& editor, UiContext& ctx) {
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
    std::snprintf(label, sizeof label, "%s %s %s: %zu %s", f.inclusion ? "keep in" : "keep out",
                  f.circle ? "circle" : "polygon", n.c_str(), f.vertices.size(), f.circle ? "centre" : "vertices");
    if (ImGui::Selectable(label, editor.fence_selected == static_cast<int>(z), 0, ImVec2(260, 0))) {
      editor.fence_selected = static_cast<int>(z);
      editor.tool = MapTool::kFenceVertex;
    }
    RegisterLastItem(ctx, "mission:fence:" + n);
    if (f.circle) {
      ImGui::SameLine();
      NumberCell(ctx, "mission:radius:" + n, &f.radius_m, 1.0, 10000.0, "%.0f", 70);
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
    NumberCell(ctx, "mission:rally_alt:" + n, &editor.rally[k].altitude_m, 1.0, 120.0, "%.1f", 70);
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
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  // Over the plots, beside the map it edits, leaving the survey panel in view.
  ImGui::SetNextWindowPos(ImVec2(0.22f * d.x, 0.04f * d.y), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(0.40f * d.x, 0.51f * d.y), ImGuiCond_FirstUseEver);
  if (!ImGui::Begin("Mission", &st.map_edit_mission)) {
    ImGui::End();
    return;
  }
  MissionEditor& editor = model.missions().editor();
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted("take-off [m]");
  ImGui::SameLine();
  NumberCell(ctx, "mission:takeoff", &editor.takeoff_alt_m, 1.0, 120.0, "%.1f", 70);
  ImGui::SameLine();
  ImGui::TextUnformatted("cruise [m/s]");
  ImGui::SameLine();
  NumberCell(ctx, "mission:cruise", &editor.cruise_speed_m_s, 0.5, 15.0, "%.1f", 70);
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
  ImGui::TextDisabled(editor.items().empty() ? "click the map to add waypoints; with no items the survey is the mission"
                                             : "speed 0: unchanged   hold: seconds at the point");
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY | ImGuiTableFlags_BordersInnerV;
  std::optional<std::size_t> erase;
  const float fence_rows = 3.0f + static_cast<float>(editor.fences.size() + editor.rally.size());
  if (ImGui::BeginTable("mission_items", 6, flags, ImVec2(0, -ImGui::GetFrameHeightWithSpacing() * (2 + fence_rows)))) {
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableSetupColumn("#", ImGuiTableColumnFlags_WidthFixed, 24);
    ImGui::TableSetupColumn("action", ImGuiTableColumnFlags_WidthStretch, 1.4f);
    ImGui::TableSetupColumn("alt [m]", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableSetupColumn("speed [m/s]", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableSetupColumn("hold [s]", ImGuiTableColumnFlags_WidthStretch, 1.0f);
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 20);
    ImGui::TableHeadersRow();
    for (std::size_t i = 0; i < editor.items().size(); ++i) {
      bool e = false;
      ImGui::PushID(static_cast<int>(i));
      DrawRow(editor, ctx, i, &e);
      ImGui::PopID();
      if (e) erase = i;
    }
    ImGui::EndTable();
  }
  if (erase) editor.Delete(*erase);
  DrawFenceSection(editor, ctx);
  std::string error;
  const auto mission = editor.MakeMission(model.missions().planner(), model.missions().planner().origin(), &error);
  if (mission) ImGui::Text("%zu mission items", mission->items.size());
  else ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", error.c_str());
  ImGui::SameLine();
  BeginDisabledBecause(ctx, !mission || !model.selected(), !mission ? error : "no vehicle selected");
  if (ImGui::Button("Upload to vehicle")) model.UploadMission(ctx.now);
  RegisterLastItem(ctx, "mission:upload");
  EndDisabledBecause(ctx);
  ImGui::SameLine();
  BeginDisabledBecause(ctx, !model.selected(), "no vehicle selected");
  if (ImGui::Button("Download from vehicle")) model.DownloadMission(ctx.now);
  RegisterLastItem(ctx, "mission:download");
  EndDisabledBecause(ctx);
  ImGui::End();
}

}  // namespace uav::gcs
