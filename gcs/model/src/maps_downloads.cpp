#include "uav/gcs/maps_downloads.hpp"

#include <cmath>
#include <filesystem>

#include "uav/gcs/video_tracking.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::gcs {

void MapsDownloads::OnMapTile(VehicleMaps& v, const std::string& vehicle_id, const MapTile& t, double now,
                              MessageLog& log) {
  LiveMap& map = v.live_map;
  std::string problem;
  std::vector<uint8_t> rgba;
  if (t.tile_px < kMinTilePx || t.tile_px > kMaxTilePx || !(t.gsd_m > 0) || !std::isfinite(t.origin_north_m) ||
      !std::isfinite(t.origin_east_m) || t.map_id < map.map_id)
    problem = "bad tile header (tile_px, gsd, origin or an older map)";
  else
    DecodeJpeg(t.jpeg, t.tile_px, t.tile_px, &rgba, &problem);
  if (!problem.empty()) {
    if (map.rejected++ == 0) log.Add(now, vehicle_id, "map tile rejected: " + problem, Severity::kWarning);
    return;
  }
  if (t.map_id > map.map_id) {  // a new survey: a new map
    map = LiveMap();
    map.map_id = t.map_id;
  }
  map.tile_px = t.tile_px;
  map.gsd_m = t.gsd_m;
  map.origin_north_m = t.origin_north_m;
  map.origin_east_m = t.origin_east_m;
  map.georeferenced = t.georeferenced;
  LiveMap::Tile& tile = map.tiles[{t.tile_x, t.tile_y}];
  tile.rgba = std::move(rgba);
  // Unmapped pixels travel as black; JPEG leaves them near black.
  for (size_t i = 0; i < tile.rgba.size(); i += 4)
    if (tile.rgba[i] < 8 && tile.rgba[i + 1] < 8 && tile.rgba[i + 2] < 8) tile.rgba[i + 3] = 0;
  ++tile.version;
  ++map.received;
}

void MapsDownloads::OnFileOffer(VehicleMaps& v, const std::string& vehicle_id, const FileOffer& offer, double now,
                                MessageLog& log) {
  const bool known = v.files.progress(offer.transfer_id).has_value();
  std::string error;
  if (!v.files.OnOffer(offer, &error)) {
    log.Add(now, vehicle_id, "file offer refused: " + error, Severity::kWarning);
    return;
  }
  if (known) return;
  log.Add(now, vehicle_id, "file offered: " + offer.name + " (" + std::to_string((offer.size + 1023) / 1024) + " kB)",
          Severity::kInfo);
  // Once there is a download directory, files offered later (the rest of a map's files, the
  // next map) follow into it.
  if (!dir_.empty()) StartAll(v, vehicle_id, now, log);
}

bool MapsDownloads::StartDownload(VehicleMaps* v, const std::string& vehicle_id, const std::string& dir, double now,
                                  MessageLog& log) {
  error_.clear();
  if (!v) {
    error_ = "no vehicle selected";
    return false;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    error_ = "cannot use '" + dir + "' as the download directory";
    log.Add(now, vehicle_id, "download: " + error_, Severity::kError);
    return false;
  }
  dir_ = dir;
  StartAll(*v, vehicle_id, now, log);
  log.Add(now, vehicle_id,
          "download to " + dir + ": " + std::to_string(v->files.offers().size()) + " file(s) offered so far",
          Severity::kInfo);
  return true;
}

void MapsDownloads::StartAll(VehicleMaps& v, const std::string& vehicle_id, double now, MessageLog& log) {
  v.unsaved.clear();  // the next tick writes them again
  for (const FileOffer& o : v.files.offers()) {
    const auto p = v.files.progress(o.transfer_id);
    if (p->started && !p->failed) continue;
    std::string error;
    if (!v.files.Start(o.transfer_id, &error)) log.Add(now, vehicle_id, "download of " + o.name + ": " + error, Severity::kError);
  }
}

void MapsDownloads::Tick(VehicleMaps& v, const std::string& id, double now, MessageLog& log) {
  for (FileRequest& r : v.files.Poll(now)) outgoing_.push_back({id, std::move(r)});
  for (const FileOffer& o : v.files.offers()) {
    const auto p = v.files.progress(o.transfer_id);
    if (p->failed && !v.saved.count(o.transfer_id)) {
      v.saved[o.transfer_id] = "";
      log.Add(now, id, "download of " + o.name + " failed: " + p->error, Severity::kError);
    }
    if (!p->complete || v.saved.count(o.transfer_id) || v.unsaved.count(o.transfer_id)) continue;
    if (dir_.empty()) continue;  // fetched for the mission editor, not asked to be saved
    const std::string path = (std::filesystem::path(dir_) / o.name).string();
    try {
      // Through a temporary name: on a full disk nothing is left behind, not even half a file.
      std::filesystem::create_directories(dir_);
      WriteFileAtomically(path, *v.files.Contents(o.transfer_id));
      v.saved[o.transfer_id] = path;
      log.Add(now, id, "saved " + path + " (" + std::to_string((o.size + 1023) / 1024) + " kB, SHA-256 verified)",
              Severity::kInfo);
    } catch (const std::exception& e) {
      v.unsaved.insert(o.transfer_id);
      log.Add(now, id,
              "download of " + o.name + " received but not saved: " + e.what() +
                  "; it is kept: make room and download again",
              Severity::kError);
    }
  }
}

}  // namespace uav::gcs
