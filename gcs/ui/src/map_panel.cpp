// Map view: top-down in local metres (north up) around the map origin (the selected vehicle's
// home). Shows a basemap the operator loads (a GeoTIFF), the map the vehicle is stitching (live tiles, to scale), the vehicle with heading
// and trail, home, the power lines it has ranged, the survey being planned (polygon,
// coverage of the capture legs, path) and the mission the vehicle accepted. Mouse: wheel zooms
// about the pointer; drag on empty ground pans; with "Edit survey" a click adds a vertex, a drag
// on a vertex moves it and a right click deletes it. Latitude/longitude under the pointer.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "overlays/overlays.hpp"
#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

constexpr ImU32 kGrid = IM_COL32(60, 66, 76, 255);
constexpr ImU32 kVehicle = IM_COL32(255, 255, 255, 255);
constexpr float kVertexPickPx = 9.0f;
constexpr int kBasemapTextureSlot = 1;  // 0: the video; 100 on: live-map tiles

// Largest 1-2-5 step whose pixel size is at least `min_px`.
double NiceStep(double px_per_m, double min_px) {
  double step = 1e-2;
  for (int i = 0; i < 40; ++i) {
    for (double m : {1.0, 2.0, 5.0})
      if (step * m * px_per_m >= min_px) return step * m;
    step *= 10;
  }
  return step;
}


// Wheel zooms about the pointer; a drag on empty ground pans; with "Edit survey" a click adds a
// vertex, a drag on a vertex moves it and a right click deletes it; with "Edit mission" the same
// for the mission's items (a click adds a waypoint after the selected item).
void HandleMapInput(GcsModel& model, UiContext& ctx, const MapCanvas& m, bool hovered) {
  UiState& st = ctx.state;
  SurveyPlanner& planner = model.missions().planner();
  const ImGuiIO& io = ImGui::GetIO();
  auto to_map = [&](ImVec2 s) {
    return Eigen::Vector2d(st.map_center_n - (s.y - m.centre.y) / st.map_px_per_m,
                           st.map_center_e + (s.x - m.centre.x) / st.map_px_per_m);
  };
  if (hovered && io.MouseWheel != 0.0f) {
    const Eigen::Vector2d before = to_map(io.MousePos);
    st.map_px_per_m = std::clamp(st.map_px_per_m * std::pow(1.2, io.MouseWheel), 0.01, 200.0);
    const Eigen::Vector2d after = to_map(io.MousePos);
    st.map_center_n += before.x() - after.x();
    st.map_center_e += before.y() - after.y();
  }
  auto vertex_at = [&](ImVec2 s) {
    return planner.VertexNear(to_map(s), kVertexPickPx / st.map_px_per_m);
  };
  MissionEditor& editor = model.missions().editor();
  auto item_at = [&](ImVec2 s) { return editor.ItemNear(planner, to_map(s), kVertexPickPx / st.map_px_per_m); };
  if (ImGui::IsItemActivated() && ImGui::IsMouseDown(0)) {
    st.map_pressed_vertex = st.map_edit_survey ? vertex_at(io.MousePos) : -1;
    st.map_pressed_item = st.map_edit_mission ? item_at(io.MousePos) : -1;
    if (st.map_pressed_item >= 0) editor.selected = st.map_pressed_item;
    st.map_dragged = false;
    st.map_press_x = io.MousePos.x, st.map_press_y = io.MousePos.y;
  }
  if (ImGui::IsItemActive() && ImGui::IsMouseDown(0)) {
    const float dx = io.MousePos.x - st.map_press_x, dy = io.MousePos.y - st.map_press_y;
    if (dx * dx + dy * dy > 9.0f) st.map_dragged = true;
    if (st.map_dragged) {
      if (st.map_pressed_vertex >= 0) {
        planner.MoveVertex(static_cast<std::size_t>(st.map_pressed_vertex), to_map(io.MousePos));
      } else if (st.map_pressed_item >= 0) {
        editor.MoveTo(static_cast<std::size_t>(st.map_pressed_item), planner.FromMap(to_map(io.MousePos)));
      } else {
        st.map_center_n += io.MouseDelta.y / st.map_px_per_m;
        st.map_center_e -= io.MouseDelta.x / st.map_px_per_m;
        st.map_follow = false;
      }
    }
  }
  // Adds happen on the left button's release only (a right click also activates the canvas).
  const bool left_click = ImGui::IsItemDeactivated() && ImGui::IsMouseReleased(0) && !st.map_dragged;
  if (left_click && st.map_pressed_vertex < 0 && st.map_edit_survey)
    planner.AddVertex(to_map(ImVec2(st.map_press_x, st.map_press_y)));
  if (left_click && st.map_pressed_item < 0 && st.map_edit_mission) {
    const GeodeticPoint g = planner.FromMap(to_map(ImVec2(st.map_press_x, st.map_press_y)));
    if (editor.tool == MapTool::kFenceVertex) {
      editor.AddFenceVertex(g);
    } else if (editor.tool == MapTool::kRallyPoint) {
      editor.rally.push_back({g.latitude_deg, g.longitude_deg, editor.takeoff_alt_m});
    } else {
      // A waypoint after the selected item, at the altitude of the position item before it.
      PlanItem w;
      w.latitude_deg = g.latitude_deg, w.longitude_deg = g.longitude_deg;
      const std::size_t at = editor.selected >= 0 ? static_cast<std::size_t>(editor.selected) + 1 : editor.items().size();
      w.altitude_m = editor.takeoff_alt_m;
      for (std::size_t k = at; k-- > 0;)
        if (editor.items()[k].HasPosition() && editor.items()[k].action != PlanAction::kLand) {
          w.altitude_m = editor.items()[k].altitude_m;
          break;
        }
      editor.Insert(at, w);
    }
  }
  if (ImGui::IsItemDeactivated()) st.map_pressed_vertex = -1, st.map_pressed_item = -1;
  if (hovered && st.map_edit_survey && ImGui::IsMouseReleased(1)) {
    const int v = vertex_at(io.MousePos);
    if (v >= 0) planner.DeleteVertex(static_cast<std::size_t>(v));
  }
  if (hovered && st.map_edit_mission && ImGui::IsMouseReleased(1) &&
      !editor.DeleteFenceNear(planner, to_map(io.MousePos), kVertexPickPx / st.map_px_per_m)) {
    const int i = item_at(io.MousePos);
    if (i >= 0) editor.Delete(static_cast<std::size_t>(i));
  }
  // Click-to-go: outside the editors a right click offers a goto there, to be confirmed.
  if (hovered && !st.map_edit_survey && !st.map_edit_mission && ImGui::IsMouseReleased(1)) {
    const Eigen::Vector2d ne = to_map(io.MousePos);
    st.map_goto_n = ne.x(), st.map_goto_e = ne.y();
    ImGui::OpenPopup("map:goto");
  }

}

// The confirmation of a click-to-go: the selected vehicle flies to the point at its altitude.
void DrawClickToGo(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  if (!ImGui::BeginPopup("map:goto")) return;
  const VehicleModel* v = model.selected();
  const bool flying = v && v->state && !v->state->landed;
  const double alt = flying ? v->state->altitude() : 0.0;
  char command[96];
  std::snprintf(command, sizeof command, "goto %.1f %.1f %.1f", st.map_goto_n, st.map_goto_e, alt);
  if (flying) ImGui::Text("Go to N %.1f m, E %.1f m at %.1f m?", st.map_goto_n, st.map_goto_e, alt);
  else ImGui::TextDisabled("%s is not flying: take off first", v ? v->id.c_str() : "no vehicle");
  BeginDisabledBecause(ctx, !flying, "the selected vehicle is not flying");
  if (ImGui::Button("Go here")) {
    model.SubmitCommand(command, ctx.now);
    ImGui::CloseCurrentPopup();
  }
  RegisterLastItem(ctx, "map:goto_confirm");
  EndDisabledBecause(ctx);
  ImGui::SameLine();
  if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
  RegisterLastItem(ctx, "map:goto_cancel");
  ImGui::EndPopup();
}

// The basemap (a GeoTIFF) under everything, by its four corners.
void DrawBasemap(GcsModel& model, UiContext& ctx, const MapCanvas& m) {
  UiState& st = ctx.state;
  const SurveyPlanner& planner = model.missions().planner();
  if (const auto& base = model.basemap().image()) {
    if (st.basemap_version != base->version) {
      // A new basemap: the view moves onto it.
      Eigen::Vector2d centre = Eigen::Vector2d::Zero();
      for (const GeodeticPoint& corner : base->corners) centre += 0.25 * planner.ToMap(corner);
      st.map_center_n = centre.x(), st.map_center_e = centre.y();
      if (ctx.update_texture)
        st.basemap_texture = ctx.update_texture(kBasemapTextureSlot, base->rgba.data(), base->width, base->height);
      st.basemap_version = base->version;
    }
    if (st.basemap_texture) {
      ImVec2 q[4];
      for (int i = 0; i < 4; ++i) {
        const Eigen::Vector2d ne = planner.ToMap(base->corners[i]);
        q[i] = m.ToScreen(ne.x(), ne.y());
      }
      m.dl->AddImageQuad(st.basemap_texture, q[0], q[1], q[2], q[3]);
    }
  }

}

// The map the vehicle is stitching, to scale under everything else (geo-referenced maps only:
// their local NED frame is the vehicle's home, which is this map's origin).
void DrawLiveMap(const GcsModel& model, UiContext& ctx, const MapCanvas& m) {
  if (const VehicleModel* sel = model.selected(); sel && sel->live_map.georeferenced && !sel->live_map.tiles.empty()) {
    SyncLiveMapTextures(*sel, ctx);
    const LiveMap& lm = sel->live_map;
    const double T = lm.tile_px;
    for (const auto& [key, tile] : lm.tiles) {
      void* texture = ctx.state.live_tiles[key].texture;
      if (!texture) continue;
      const double n0 = lm.origin_north_m - (key.second * T - 0.5) * lm.gsd_m, n1 = n0 - T * lm.gsd_m;
      const double e0 = lm.origin_east_m + (key.first * T - 0.5) * lm.gsd_m, e1 = e0 + T * lm.gsd_m;
      m.dl->AddImage(texture, m.ToScreen(n0, e0), m.ToScreen(n1, e1));
    }
  }
}

}  // namespace

void DrawMapPanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  ImGui::Begin("Map");
  if (ImGui::Checkbox("Edit survey", &st.map_edit_survey) && st.map_edit_survey) st.map_edit_mission = false;
  RegisterLastItem(ctx, "map:edit");
  ImGui::SameLine();
  if (ImGui::Checkbox("Edit mission", &st.map_edit_mission) && st.map_edit_mission) st.map_edit_survey = false;
  RegisterLastItem(ctx, "map:edit_mission");
  ImGui::SameLine();
  if (ImGui::Button("Centre on vehicle")) {
    if (const VehicleModel* v = model.selected(); v && v->state)
      st.map_center_n = v->state->p_N.x(), st.map_center_e = v->state->p_N.y();
  }
  RegisterLastItem(ctx, "map:centre");
  ImGui::SameLine();
  // Keeps the selected vehicle in the middle (a fast tail-sitter leaves any fixed view); a drag
  // to pan lets go.
  ImGui::Checkbox("Follow", &st.map_follow);
  RegisterLastItem(ctx, "map:follow");
  if (st.map_follow)
    if (const VehicleModel* v = model.selected(); v && v->state)
      st.map_center_n = v->state->p_N.x(), st.map_center_e = v->state->p_N.y();
  // The basemap and the mouse's hints on a line of their own: the panel is narrower than both
  // rows together, and every line above the map takes from its height.
  ImGui::SetNextItemWidth(150);
  ImGui::InputText("##basemap", &st.basemap_file);
  RegisterLastItem(ctx, "map:basemap");
  ImGui::SameLine();
  if (ImGui::Button("Load basemap")) model.LoadBasemap(st.basemap_file, ctx.now);
  RegisterLastItem(ctx, "map:load_basemap");
  if (model.basemap().image()) {
    ImGui::SameLine();
    if (ImGui::Button("Clear basemap")) model.ClearBasemap();
    RegisterLastItem(ctx, "map:clear_basemap");
  }
  ImGui::SameLine();
  ImGui::TextDisabled(st.map_edit_survey    ? "click: add vertex, drag: move, right: delete"
                      : st.map_edit_mission ? "click: add, drag: move, right: delete"
                                            : "right click: go there");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("wheel: zoom about the pointer; drag on empty ground: pan%s",
                      st.map_edit_survey    ? "; click: add a vertex; drag a vertex: move it; right click: delete it"
                      : st.map_edit_mission ? "; click: add what the Mission window's tool says; drag an item: move it; right click: delete it"
                                            : "; right click: go there (confirmed in the command bar)");

  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 50.0f), size.y = std::max(size.y, 50.0f);
  ImGui::InvisibleButton("map_canvas", size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  RegisterLastItem(ctx, "map");
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 c(p0.x + 0.5f * size.x, p0.y + 0.5f * size.y);
  auto to_map = [&](ImVec2 s) {
    return Eigen::Vector2d(st.map_center_n - (s.y - c.y) / st.map_px_per_m, st.map_center_e + (s.x - c.x) / st.map_px_per_m);
  };

  ImDrawList* dl = ImGui::GetWindowDrawList();
  HandleMapInput(model, ctx, {dl, c, st.map_center_n, st.map_center_e, st.map_px_per_m}, hovered);
  DrawClickToGo(model, ctx);
  ctx.map = {true, c.x, c.y, st.map_center_n, st.map_center_e, st.map_px_per_m};
  const MapCanvas m{dl, c, st.map_center_n, st.map_center_e, st.map_px_per_m};

  // ---- Drawing, bottom up.
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->PushClipRect(p0, p1, true);
  dl->AddRectFilled(p0, p1, IM_COL32(28, 32, 40, 255));
  const double step = NiceStep(st.map_px_per_m, 60.0);
  const Eigen::Vector2d lo = to_map(ImVec2(p0.x, p1.y)), hi = to_map(ImVec2(p1.x, p0.y));
  for (double n = std::floor(lo.x() / step) * step; n <= hi.x(); n += step)
    dl->AddLine(m.ToScreen(n, lo.y()), m.ToScreen(n, hi.y()), kGrid);
  for (double e = std::floor(lo.y() / step) * step; e <= hi.y(); e += step)
    dl->AddLine(m.ToScreen(lo.x(), e), m.ToScreen(hi.x(), e), kGrid);
  DrawBasemap(model, ctx, m);
  DrawLiveMap(model, ctx, m);
  DrawSurveyOnMap(model, m);
  DrawMissionPlanOnMap(model, m);
  const VehicleModel* v = model.selected();
  if (v) {
    DrawAvoidanceOnMap(*v, m, ctx.now);
    DrawPowerLinesOnMap(model, *v, m, ctx.now);
    DrawObstaclesOnMap(model, *v, m, ctx.now);
  }
  DrawVehicleOnMap(model, v, m);

  // Scale bar and pointer readout.
  char text[160];
  std::snprintf(text, sizeof text, "%g m", step);
  const ImVec2 sb(p0.x + 10, p1.y - 12);
  dl->AddLine(sb, ImVec2(sb.x + static_cast<float>(step * st.map_px_per_m), sb.y), kVehicle, 2.0f);
  dl->AddText(ImVec2(sb.x, sb.y - 16), kVehicle, text);
  if (hovered) {
    const Eigen::Vector2d ne = to_map(ImGui::GetIO().MousePos);
    const GeodeticPoint g = model.missions().planner().FromMap(ne);
    std::snprintf(text, sizeof text, "N %.1f m  E %.1f m   %.7f, %.7f", ne.x(), ne.y(), g.latitude_deg, g.longitude_deg);
    dl->AddText(ImVec2(p0.x + 10, p0.y + 8), kVehicle, text);
  }
  dl->PopClipRect();
  ImGui::End();
}

}  // namespace uav::gcs
