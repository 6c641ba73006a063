// Live map panel: the map the selected vehicle is stitching, growing as its tiles arrive, with
// the vehicle's position on it; below, the files it offers (its finished maps), a save location
// and the Download action, with a progress bar per file.
#include <imgui.h>
#include <algorithm>
#include <cstdio>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void SyncLiveMapTextures(const VehicleModel& v, UiContext& ctx) {
  const LiveMap& map = v.live_map;
  UiState& ui = ctx.state;
  if (ui.live_map_vehicle != v.id || ui.live_map_id != map.map_id) {  // another vehicle or a new map
    ui.live_tiles.clear();
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
// An overview of the live map fitted into the panel, north up (the Map panel shows it to scale).
void DrawTiles(const VehicleModel& v, UiContext& ctx, float reserve_y) {
  const LiveMap& map = v.live_map;
  SyncLiveMapTextures(v, ctx);
  if (map.tiles.empty()) {
    ImGui::TextDisabled("no map tiles yet: they stream while the survey camera captures");
    RegisterLastItem(ctx, "livemap");
    return;
  }
  ImGui::Text("map %d: %zu tiles at %.3f m/px%s", map.map_id, map.tiles.size(), map.gsd_m,
              map.georeferenced ? "" : " (not geo-referenced)");
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
  const float px = std::min(avail.x / (x1 - x0), avail.y / (y1 - y0));  // screen pixels per tile
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("##livemap", ImVec2(px * (x1 - x0), px * (y1 - y0)));
  RegisterLastItem(ctx, "livemap");
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + px * (x1 - x0), origin.y + px * (y1 - y0)), IM_COL32(25, 25, 30, 255));
  for (const auto& [key, tile] : map.tiles) {
    const ImVec2 a(origin.x + px * (key.first - x0), origin.y + px * (key.second - y0));
    if (void* texture = ctx.state.live_tiles[key].texture) draw->AddImage(texture, a, ImVec2(a.x + px, a.y + px));
  }
  // The vehicle on the map.
  const auto n = v.latest.find("STATE.x"), e = v.latest.find("STATE.y");
  if (map.georeferenced && n != v.latest.end() && e != v.latest.end()) {
    const double c = (e->second - map.origin_east_m) / map.gsd_m, r = (map.origin_north_m - n->second) / map.gsd_m;
    const ImVec2 p(origin.x + static_cast<float>((c / map.tile_px - x0) * px),
                   origin.y + static_cast<float>((r / map.tile_px - y0) * px));
    draw->AddCircleFilled(p, 4.0f, IM_COL32(255, 80, 40, 255));
  }
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
  if (!model.download_error().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", model.download_error().c_str());
  const std::vector<FileOffer> offers = v->files.offers();
  DrawTiles(*v, ctx, (offers.size() + 2) * ImGui::GetFrameHeightWithSpacing());
  if (offers.empty()) ImGui::TextDisabled("no map offered yet: the vehicle offers it after the survey, at landing");
  for (const FileOffer& o : offers) {
    const auto p = v->files.progress(o.transfer_id);
    const float fraction = o.chunks ? static_cast<float>(p->received) / o.chunks : 1.0f;
    char overlay[96];
    std::snprintf(overlay, sizeof overlay, "%s  %lld kB  %s", o.name.c_str(), static_cast<long long>((o.size + 1023) / 1024),
                  p->complete ? "saved" : p->failed ? "failed" : p->started ? "downloading" : "offered");
    ImGui::ProgressBar(p->complete ? 1.0f : fraction, ImVec2(-1, 0), overlay);
  }
  if (!v->saved.empty() && !model.download_dir().empty()) ImGui::TextDisabled("saved in %s", model.download_dir().c_str());
  ImGui::End();
}

}  // namespace uav::gcs
