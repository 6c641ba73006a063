// Live map panel: the map the selected vehicle is stitching, growing as its tiles arrive, with
// the vehicle's position on it; below, the files it offers (its finished maps, its flight log at
// each landing, the mission it holds), a save location
// and the Download action, with a progress bar per file.
#include <imgui.h>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void SyncLiveMapTextures(const VehicleModel& v, UiContext& ctx) {
  const LiveMap& map = v.live_map;
  UiState& ui = ctx.state;
  if (ui.live_map_vehicle != v.id || ui.live_map_id != map.map_id) {  // another vehicle or a new map
    ui.live_tiles.clear();
    ui.live_zoom = 1.0;
    ui.live_pan_x = ui.live_pan_y = 0.0;
    ui.live_map_vehicle = v.id;
    ui.live_map_id = map.map_id;
  }
  for (const auto& [key, tile] : map.tiles) {
    UiState::TileTexture& tex = ui.live_tiles[key];
    if (tex.slot == 0) tex.slot = ui.next_texture_slot++;
    if (ctx.update_texture && tex.version != tile.version) {
      tex.texture = ctx.update_texture(tex.slot, tile.rgba.data(), map.tile_px, map.tile_px);
      tex.version = tile.version;
    }
  }
}

namespace {
// The live map, north up, fitted into the panel at zoom 1: the wheel zooms about the cursor, a
// drag pans, Fit returns to the whole map (the Map panel shows it to scale under the plan).
void DrawTiles(const VehicleModel& v, UiContext& ctx, float reserve_y) {
  const LiveMap& map = v.live_map;
  UiState& st = ctx.state;
  SyncLiveMapTextures(v, ctx);
  if (map.tiles.empty()) {
    ImGui::TextDisabled("no map tiles yet: they stream while the survey camera captures");
    RegisterLastItem(ctx, "livemap");
    return;
  }
  ImGui::Text("map %d: %zu tiles at %.3f m/px%s, zoom %.1fx", map.map_id, map.tiles.size(), map.gsd_m,
              map.georeferenced ? "" : " (not geo-referenced)", st.live_zoom);
  ImGui::SameLine();
  if (ImGui::SmallButton("Fit")) st.live_zoom = 1.0, st.live_pan_x = st.live_pan_y = 0.0;
  RegisterLastItem(ctx, "livemap:fit");
  int x0 = 1 << 30, y0 = 1 << 30, x1 = -(1 << 30), y1 = -(1 << 30);
  for (const auto& [key, tile] : map.tiles) {
    x0 = std::min(x0, key.first);
    x1 = std::max(x1, key.first + 1);
    y0 = std::min(y0, key.second);
    y1 = std::max(y1, key.second + 1);
  }
  ImVec2 avail = ImGui::GetContentRegionAvail();
  avail.y -= reserve_y;  // the file list below
  if (avail.x < 20 || avail.y < 20) return;
  const ImVec2 view0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##livemap", avail);
  RegisterLastItem(ctx, "livemap");
  const ImVec2 view1(view0.x + avail.x, view0.y + avail.y);
  const ImVec2 mid(0.5f * (view0.x + view1.x), 0.5f * (view0.y + view1.y));
  const double fit = std::min(avail.x / (x1 - x0), avail.y / (y1 - y0));  // screen px per tile at zoom 1
  // Tile coordinates at the view's centre.
  double cx = 0.5 * (x0 + x1) + st.live_pan_x, cy = 0.5 * (y0 + y1) + st.live_pan_y;
  double px = fit * st.live_zoom;
  const ImGuiIO& io = ImGui::GetIO();
  if (ImGui::IsItemHovered() && io.MouseWheel != 0.0f) {
    const double ux = cx + (io.MousePos.x - mid.x) / px, uy = cy + (io.MousePos.y - mid.y) / px;
    st.live_zoom = std::clamp(st.live_zoom * std::pow(1.25, io.MouseWheel), 0.25, 64.0);
    px = fit * st.live_zoom;
    cx = ux - (io.MousePos.x - mid.x) / px;  // the point under the cursor stays there
    cy = uy - (io.MousePos.y - mid.y) / px;
  }
  if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 1.0f)) {
    cx -= io.MouseDelta.x / px;
    cy -= io.MouseDelta.y / px;
  }
  st.live_pan_x = cx - 0.5 * (x0 + x1);
  st.live_pan_y = cy - 0.5 * (y0 + y1);
  auto screen = [&](double tx, double ty) {
    return ImVec2(static_cast<float>(mid.x + (tx - cx) * px), static_cast<float>(mid.y + (ty - cy) * px));
  };
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->PushClipRect(view0, view1, true);
  draw->AddRectFilled(view0, view1, IM_COL32(25, 25, 30, 255));
  for (const auto& [key, tile] : map.tiles) {
    if (void* texture = st.live_tiles[key].texture)
      draw->AddImage(texture, screen(key.first, key.second), screen(key.first + 1, key.second + 1));
  }
  // The vehicle on the map.
  if (map.georeferenced && v.state) {
    const double c = (v.state->p_N.y() - map.origin_east_m) / map.gsd_m;
    const double r = (map.origin_north_m - v.state->p_N.x()) / map.gsd_m;
    draw->AddCircleFilled(screen(c / map.tile_px, r / map.tile_px), 4.0f, IM_COL32(255, 80, 40, 255));
  }
  draw->PopClipRect();
}
}  // namespace

void DrawLiveMapPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Live map");
  const VehicleModel* v = model.selected();
  if (!v) {
    ImGui::TextDisabled("no vehicle selected");
    ImGui::End();
    return;
  }
  ImGui::TextUnformatted("Save to");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(ImGui::GetContentRegionAvail().x * 0.6f);
  ImGui::InputText("##map:dir", &ctx.state.download_dir);
  RegisterLastItem(ctx, "map:dir");
  ImGui::SameLine();
  if (ImGui::Button("Download")) model.StartDownload(ctx.state.download_dir, ctx.now);
  RegisterLastItem(ctx, "map:download");
  if (!model.maps().error().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", model.maps().error().c_str());
  const std::vector<FileOffer> offers = v->files.offers();
  DrawTiles(*v, ctx, (offers.size() + 2) * ImGui::GetFrameHeightWithSpacing());
  if (offers.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextDisabled("no file offered yet: the vehicle offers its map after a survey, its flight log at each landing, its mission on each upload");
    ImGui::PopTextWrapPos();
  }
  for (const FileOffer& o : offers) {
    const auto p = v->files.progress(o.transfer_id);
    const float fraction = o.chunks ? static_cast<float>(p->received) / o.chunks : 1.0f;
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s  %lld kB  %s", o.name.c_str(), static_cast<long long>((o.size + 1023) / 1024),
                  p->complete ? "saved" : p->failed ? "failed" : p->started ? "downloading" : "offered");
    ImGui::ProgressBar(p->complete ? 1.0f : fraction, ImVec2(-1, 0), overlay);
  }
  if (!v->saved.empty() && !model.maps().dir().empty()) ImGui::TextDisabled("saved in %s", model.maps().dir().c_str());
  ImGui::End();
}

}  // namespace uav::gcs
