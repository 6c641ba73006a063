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

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

constexpr ImU32 kGrid = IM_COL32(60, 66, 76, 255);
constexpr ImU32 kPolygon = IM_COL32(80, 220, 100, 255);
constexpr ImU32 kCoverage = IM_COL32(90, 150, 230, 60);
constexpr ImU32 kPath = IM_COL32(120, 180, 255, 255);
constexpr ImU32 kMission = IM_COL32(255, 170, 60, 255);
constexpr ImU32 kVehicle = IM_COL32(255, 255, 255, 255);
constexpr ImU32 kTrail = IM_COL32(255, 80, 80, 200);       // the flown estimate
constexpr ImU32 kGpsTrail = IM_COL32(255, 230, 80, 180);   // GPS fixes
constexpr ImU32 kVoTrail = IM_COL32(80, 220, 255, 220);    // the VO+IMU filter
constexpr ImU32 kTruthTrail = IM_COL32(255, 255, 255, 160);  // simulation's truth
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

}  // namespace

void DrawMapPanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  ImGui::Begin("Map");
  ImGui::Checkbox("Edit survey", &st.map_edit_survey);
  RegisterLastItem(ctx, "map:edit");
  ImGui::SameLine();
  if (ImGui::Button("Centre on vehicle")) {
    if (const VehicleModel* v = model.selected(); v && v->state)
      st.map_center_n = v->state->p_N.x(), st.map_center_e = v->state->p_N.y();
  }
  RegisterLastItem(ctx, "map:centre");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(220);
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
  ImGui::TextDisabled("wheel: zoom  drag: pan  click: add vertex  drag vertex: move  right click: delete");

  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 50.0f), size.y = std::max(size.y, 50.0f);
  ImGui::InvisibleButton("map_canvas", size, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  RegisterLastItem(ctx, "map");
  const bool hovered = ImGui::IsItemHovered();
  const ImVec2 c(p0.x + 0.5f * size.x, p0.y + 0.5f * size.y);
  auto to_screen = [&](double n, double e) {
    return ImVec2(c.x + static_cast<float>((e - st.map_center_e) * st.map_px_per_m),
                  c.y - static_cast<float>((n - st.map_center_n) * st.map_px_per_m));
  };
  auto to_map = [&](ImVec2 s) {
    return Eigen::Vector2d(st.map_center_n - (s.y - c.y) / st.map_px_per_m, st.map_center_e + (s.x - c.x) / st.map_px_per_m);
  };
  SurveyPlanner& planner = model.missions().planner();
  const ImGuiIO& io = ImGui::GetIO();

  // ---- Input.
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
  if (ImGui::IsItemActivated() && ImGui::IsMouseDown(0)) {
    st.map_pressed_vertex = st.map_edit_survey ? vertex_at(io.MousePos) : -1;
    st.map_dragged = false;
    st.map_press_x = io.MousePos.x, st.map_press_y = io.MousePos.y;
  }
  if (ImGui::IsItemActive() && ImGui::IsMouseDown(0)) {
    const float dx = io.MousePos.x - st.map_press_x, dy = io.MousePos.y - st.map_press_y;
    if (dx * dx + dy * dy > 9.0f) st.map_dragged = true;
    if (st.map_dragged) {
      if (st.map_pressed_vertex >= 0) {
        planner.MoveVertex(static_cast<std::size_t>(st.map_pressed_vertex), to_map(io.MousePos));
      } else {
        st.map_center_n += io.MouseDelta.y / st.map_px_per_m;
        st.map_center_e -= io.MouseDelta.x / st.map_px_per_m;
      }
    }
  }
  if (ImGui::IsItemDeactivated() && !st.map_dragged && st.map_pressed_vertex < 0 && st.map_edit_survey)
    planner.AddVertex(to_map(ImVec2(st.map_press_x, st.map_press_y)));
  if (ImGui::IsItemDeactivated()) st.map_pressed_vertex = -1;
  if (hovered && st.map_edit_survey && ImGui::IsMouseReleased(1)) {
    const int v = vertex_at(io.MousePos);
    if (v >= 0) planner.DeleteVertex(static_cast<std::size_t>(v));
  }

  ctx.map = {true, c.x, c.y, st.map_center_n, st.map_center_e, st.map_px_per_m};

  // ---- Drawing.
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->PushClipRect(p0, p1, true);
  dl->AddRectFilled(p0, p1, IM_COL32(28, 32, 40, 255));
  const double step = NiceStep(st.map_px_per_m, 60.0);
  const Eigen::Vector2d lo = to_map(ImVec2(p0.x, p1.y)), hi = to_map(ImVec2(p1.x, p0.y));
  for (double n = std::floor(lo.x() / step) * step; n <= hi.x(); n += step)
    dl->AddLine(to_screen(n, lo.y()), to_screen(n, hi.y()), kGrid);
  for (double e = std::floor(lo.y() / step) * step; e <= hi.y(); e += step)
    dl->AddLine(to_screen(lo.x(), e), to_screen(hi.x(), e), kGrid);

  // The basemap (a GeoTIFF) under everything, by its four corners.
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
        q[i] = to_screen(ne.x(), ne.y());
      }
      dl->AddImageQuad(st.basemap_texture, q[0], q[1], q[2], q[3]);
    }
  }

  // The map the vehicle is stitching, to scale under everything else (geo-referenced maps only:
  // their local NED frame is the vehicle's home, which is this map's origin).
  if (const VehicleModel* sel = model.selected(); sel && sel->live_map.georeferenced && !sel->live_map.tiles.empty()) {
    SyncLiveMapTextures(*sel, ctx);
    const LiveMap& lm = sel->live_map;
    const double T = lm.tile_px;
    for (const auto& [key, tile] : lm.tiles) {
      void* texture = ctx.state.live_tiles[key].texture;
      if (!texture) continue;
      const double n0 = lm.origin_north_m - (key.second * T - 0.5) * lm.gsd_m, n1 = n0 - T * lm.gsd_m;
      const double e0 = lm.origin_east_m + (key.first * T - 0.5) * lm.gsd_m, e1 = e0 + T * lm.gsd_m;
      dl->AddImage(texture, to_screen(n0, e0), to_screen(n1, e1));
    }
  }

  // Survey: coverage of each capture leg (footprint width), the path, the polygon.
  const bool have_live_map = model.selected() && !model.selected()->live_map.tiles.empty();
  if (const auto& plan = planner.plan()) {
    const double half = 0.5 * plan->footprint.across_m;
    // The predicted coverage, until the vehicle's real map takes its place.
    for (std::size_t i = 0; i + 1 < plan->waypoints.size() && !have_live_map; ++i) {
      const auto& a = plan->waypoints[i];
      const auto& b = plan->waypoints[i + 1];
      if (a.kind != waypoints::SurveyWaypoint::Kind::kCaptureStart || b.line != a.line) continue;
      Eigen::Vector2d d = (b.p_N - a.p_N).head<2>();
      const double along = 0.5 * plan->footprint.along_m;
      const Eigen::Vector2d u = d.norm() > 1e-9 ? Eigen::Vector2d(d.normalized()) : Eigen::Vector2d(std::cos(a.yaw_rad), std::sin(a.yaw_rad));
      const Eigen::Vector2d n(-u.y(), u.x());
      const Eigen::Vector2d A = a.p_N.head<2>() - along * u, B = b.p_N.head<2>() + along * u;
      const ImVec2 q[4] = {to_screen((A + half * n).x(), (A + half * n).y()), to_screen((B + half * n).x(), (B + half * n).y()),
                           to_screen((B - half * n).x(), (B - half * n).y()), to_screen((A - half * n).x(), (A - half * n).y())};
      dl->AddConvexPolyFilled(q, 4, kCoverage);
    }
    for (std::size_t i = 0; i + 1 < plan->waypoints.size(); ++i)
      dl->AddLine(to_screen(plan->waypoints[i].p_N.x(), plan->waypoints[i].p_N.y()),
                  to_screen(plan->waypoints[i + 1].p_N.x(), plan->waypoints[i + 1].p_N.y()), kPath, 1.5f);
    if (!plan->waypoints.empty())
      dl->AddCircle(to_screen(plan->waypoints[0].p_N.x(), plan->waypoints[0].p_N.y()), 6.0f, kPath, 0, 2.0f);
  }
  const auto poly = planner.polygon_map();
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const auto& a = poly[i];
    const auto& b = poly[(i + 1) % poly.size()];
    if (poly.size() > 1) dl->AddLine(to_screen(a.x(), a.y()), to_screen(b.x(), b.y()), kPolygon, 2.0f);
  }
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const ImVec2 s = to_screen(poly[i].x(), poly[i].y());
    dl->AddCircleFilled(s, 5.0f, kPolygon);
    char label[8];
    std::snprintf(label, sizeof label, "%zu", i);
    dl->AddText(ImVec2(s.x + 6, s.y - 14), kPolygon, label);
  }

  // The mission the selected vehicle accepted, and the vehicle itself.
  const VehicleModel* v = model.selected();
  if (v && v->mission) {
    std::vector<ImVec2> pts;
    for (const auto& it : v->mission->items)
      if (it.command == waypoints::mav_cmd::kNavWaypoint) {
        const Eigen::Vector2d ne = planner.ToMap({it.latitude_deg, it.longitude_deg, 0});
        pts.push_back(to_screen(ne.x(), ne.y()));
      }
    if (pts.size() > 1) dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), kMission, 0, 1.0f);
    for (const auto& p : pts) dl->AddCircleFilled(p, 2.5f, kMission);
  }
  const ImVec2 home = to_screen(0, 0);
  // The geofence the vehicle enforces: its radius around home, red.
  if (v && v->state && v->state->fence_radius_m > 0) {
    {
      const float px = static_cast<float>(v->state->fence_radius_m * st.map_px_per_m);
      dl->AddCircle(home, px, IM_COL32(230, 60, 60, 200), 128, 2.0f);
      char label[64];
      std::snprintf(label, sizeof label, "geofence %.0f m, %.0f m high", v->state->fence_radius_m,
                    v->state->fence_alt_m);
      dl->AddText(ImVec2(home.x + px * 0.7071f + 4, home.y - px * 0.7071f - 14), IM_COL32(230, 60, 60, 220), label);
    }
  }
  dl->AddRect(ImVec2(home.x - 7, home.y - 7), ImVec2(home.x + 7, home.y + 7), kVehicle, 0, 0, 2.0f);
  dl->AddText(ImVec2(home.x + 9, home.y - 7), kVehicle, "H");
  if (v) {
    // Power lines ranged during the flight (thesis 3.6): those in the newest report bright,
    // earlier ones dim.
    auto draw_wire = [&](const std::vector<Eigen::Vector3d>& p_N, ImU32 colour, float width) {
      std::vector<ImVec2> pts;
      for (const auto& p : p_N) pts.push_back(to_screen(p.x(), p.y()));
      if (pts.size() > 1) dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, 0, width);
    };
    for (const auto& w : v->wire_map) draw_wire(w, IM_COL32(255, 120, 40, 110), 1.5f);
    if (const PowerLines* lines = v->FreshPowerLines(ctx.now, model.wires().params()))
      for (const PowerLine& w : lines->wires)
        draw_wire(w.p_N, w.range_m < model.wires().params().warn_distance_m ? IM_COL32(255, 60, 60, 255) : IM_COL32(255, 160, 40, 255), 3.0f);
    // Stereo obstacles (thesis 3.5) to scale: the seen radius filled, the safety radius (radius
    // plus margin) as a ring the vehicle keeps out of.
    if (const Obstacles* obstacles = v->FreshObstacles(ctx.now, model.obstacles().params()))
      for (const Obstacle& o : obstacles->obstacles) {
        const ImVec2 c = to_screen(o.p_NE.x(), o.p_NE.y());
        const float r = std::max(2.0f, static_cast<float>(o.radius_m * st.map_px_per_m));
        dl->AddCircleFilled(c, r, IM_COL32(200, 80, 255, 150), 32);
        dl->AddCircle(c, static_cast<float>(o.safety_radius_m * st.map_px_per_m), IM_COL32(200, 80, 255, 230), 48, 1.5f);
      }
    // The estimate's trail, and beside it (thesis ch. 5) the GPS fixes, the VO+IMU track and,
    // in simulation, the truth.
    auto polyline = [&](const std::deque<Eigen::Vector2d>& points, ImU32 colour, float width) {
      std::vector<ImVec2> line;
      for (const auto& p_N : points) line.push_back(to_screen(p_N.x(), p_N.y()));
      if (line.size() > 1) dl->AddPolyline(line.data(), static_cast<int>(line.size()), colour, 0, width);
    };
    polyline(v->truth_trail, kTruthTrail, 1.0f);
    polyline(v->gps_trail, kGpsTrail, 1.0f);
    polyline(v->vo_trail, kVoTrail, 1.5f);
    polyline(v->trail, kTrail, 1.5f);
    if (v->state) {
      const double h = v->state->euler.psi;
      const ImVec2 s = to_screen(v->state->p_N.x(), v->state->p_N.y());
      auto rot = [&](float fwd, float right) {  // body offset in pixels to screen
        return ImVec2(s.x + static_cast<float>(fwd * std::sin(h) + right * std::cos(h)),
                      s.y - static_cast<float>(fwd * std::cos(h) - right * std::sin(h)));
      };
      dl->AddTriangleFilled(rot(12, 0), rot(-7, -7), rot(-7, 7), kVehicle);
    }
  }

  // Scale bar and pointer readout.
  char text[160];
  std::snprintf(text, sizeof text, "%g m", step);
  const ImVec2 sb(p0.x + 10, p1.y - 12);
  dl->AddLine(sb, ImVec2(sb.x + static_cast<float>(step * st.map_px_per_m), sb.y), kVehicle, 2.0f);
  dl->AddText(ImVec2(sb.x, sb.y - 16), kVehicle, text);
  if (hovered) {
    const Eigen::Vector2d ne = to_map(io.MousePos);
    const GeodeticPoint g = planner.FromMap(ne);
    std::snprintf(text, sizeof text, "N %.1f m  E %.1f m   %.7f, %.7f", ne.x(), ne.y(), g.latitude_deg, g.longitude_deg);
    dl->AddText(ImVec2(p0.x + 10, p0.y + 8), kVehicle, text);
  }
  dl->PopClipRect();
  ImGui::End();
}

}  // namespace uav::gcs
