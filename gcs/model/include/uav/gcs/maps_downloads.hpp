#pragma once
// Maps: the live map each vehicle streams while it stitches (map_tile_t), and the downloads of
// the finished map files it offers (uav::FileReceiver), saved once their SHA-256 matched.
#include <cstdint>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <utility>
#include <vector>

#include "uav/gcs/message_log.hpp"
#include "uav/shared/file_transfer.hpp"
#include "uav/shared/operator_messages.hpp"

namespace uav::gcs {

// The map a vehicle is stitching, as far as its tiles have arrived (the newest map only).
struct LiveMap {
  int map_id = 0;
  int tile_px = 0;
  double gsd_m = 0, origin_north_m = 0, origin_east_m = 0;
  bool georeferenced = false;
  struct Tile {
    std::vector<uint8_t> rgba;  // tile_px^2 * 4, alpha 0 where unmapped
    int64_t version = 0;        // increases with every update (panels re-upload then)
  };
  std::map<std::pair<int, int>, Tile> tiles;  // (tile_x, tile_y)
  int64_t received = 0;
  int64_t rejected = 0;
};

struct OutgoingFileRequest {
  std::string vehicle_id;
  FileRequest request;
};

// Per vehicle.
struct VehicleMaps {
  LiveMap live_map;
  FileReceiver files;                  // offers and their downloads
  std::map<int64_t, std::string> saved;  // transfer id -> path written ("" when the download failed)
  // Verified in memory but not written (a full disk, a removed directory): kept, and written
  // when the operator asks to download again.
  std::set<int64_t> unsaved;
  // Wanted in memory only, not saved unless the operator downloads everything: the mission the
  // vehicle holds, on its way into the mission editor.
  std::set<int64_t> for_editor;
};

class MapsDownloads {
 public:
  static constexpr int kMinTilePx = 16, kMaxTilePx = 1024;

  // Decodes the tile; a tile of a newer map replaces the whole live map. A tile that does not
  // decode to tile_px x tile_px is counted as rejected (the first one logged).
  static void OnMapTile(VehicleMaps& v, const std::string& vehicle_id, const MapTile& tile, double now,
                        MessageLog& log);
  // An invalid offer is logged with the reason; with a download directory set, a new offer
  // starts downloading at once.
  void OnFileOffer(VehicleMaps& v, const std::string& vehicle_id, const FileOffer& offer, double now, MessageLog& log);
  static void OnFileChunk(VehicleMaps& v, const FileChunk& chunk) { v.files.OnChunk(chunk); }
  // Downloads every file `v` offers into `dir` (created if missing), and writes again the ones
  // received whose saving failed. Returns false and sets error() when there is no vehicle or the
  // directory cannot be made.
  bool StartDownload(VehicleMaps* v, const std::string& vehicle_id, const std::string& dir, double now, MessageLog& log);
  // From now on every file any vehicle offers is downloaded into `dir` as soon as it is offered.
  void SetDownloadDir(const std::string& dir) { dir_ = dir; }
  // Requests missing chunks and saves finished files (through a temporary name) once the
  // operator has asked for them.
  void Tick(VehicleMaps& v, const std::string& vehicle_id, double now, MessageLog& log);
  std::vector<OutgoingFileRequest> TakeOutgoing() { return std::exchange(outgoing_, {}); }

  const std::string& error() const { return error_; }
  const std::string& dir() const { return dir_; }

 private:
  void StartAll(VehicleMaps& v, const std::string& vehicle_id, double now, MessageLog& log);
  std::string error_;
  std::string dir_;  // where downloads are saved; empty: none started yet
  std::vector<OutgoingFileRequest> outgoing_;
};

}  // namespace uav::gcs
