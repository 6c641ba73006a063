#pragma once
// The operator's messages that are not vehicle reports, as plain data shared by the vehicle
// and the GCS: one struct per message, converted to and from its LCM type once, in the wire
// (uav/wire/messages.hpp).
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/vehicle_enums.hpp"

namespace uav {

// A JPEG preview of one of the vehicle's cameras (video_frame_t).
struct VideoFrame {
  int64_t utime = 0;                        // [us] vehicle clock of the exposure
  std::string camera;
  int width = 0, height = 0;                // of the JPEG
  int source_width = 0, source_height = 0;  // of the camera image
  std::vector<uint8_t> jpeg;
};

// A tile of the map the vehicle is stitching (map_tile_t): JPEG, unmapped pixels black.
struct MapTile {
  int map_id = 0, tile_x = 0, tile_y = 0, tile_px = 0;
  double gsd_m = 0, origin_north_m = 0, origin_east_m = 0;  // [m] ground sample distance, map origin
  bool georeferenced = false;
  std::vector<uint8_t> jpeg;
};

// The vehicle's answer to a command (command_ack_t): to whom, which command, how it stands.
struct CommandAck {
  std::string source;        // the GCS that sent the command
  int64_t command_seq = 0;   // its sequence number there
  std::string command;       // the command's name
  CommandResult result = CommandResult::kAccepted;
  int percent = 0;           // progress, 0..100
  std::string reason;        // why refused or failed; a note while in progress
};

}  // namespace uav
