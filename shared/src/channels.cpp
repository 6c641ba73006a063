#include "uav/shared/channels.hpp"

#include <cctype>

namespace uav {

const char* TopicName(Topic t) {
  switch (t) {
    case Topic::kHeartbeat: return "HEARTBEAT";
    case Topic::kGcsHeartbeat: return "GCS_HEARTBEAT";
    case Topic::kState: return "STATE";
    case Topic::kCommand: return "COMMAND";
    case Topic::kCommandAck: return "COMMAND_ACK";
    case Topic::kStatusText: return "STATUS_TEXT";
    case Topic::kMissionUpload: return "MISSION_UPLOAD";
    case Topic::kMissionAck: return "MISSION_ACK";
    case Topic::kVideo: return "VIDEO";
    case Topic::kFileOffer: return "FILE_OFFER";
    case Topic::kFileRequest: return "FILE_REQUEST";
    case Topic::kFileChunk: return "FILE_CHUNK";
    case Topic::kMapTile: return "MAP_TILE";
    case Topic::kTrackTarget: return "TRACK_TARGET";
    case Topic::kTrackStatus: return "TRACK_STATUS";
    case Topic::kPowerLines: return "POWER_LINES";
    case Topic::kObstacles: return "OBSTACLES";
    case Topic::kPointCloud: return "POINT_CLOUD";
    case Topic::kMonoDepth: return "MONO_DEPTH";
    case Topic::kActiveStereo: return "ACTIVE_STEREO";
    case Topic::kVisualOdometry: return "VISUAL_ODOMETRY";
    case Topic::kSensing: return "SENSING";
  }
  return "UNKNOWN";
}

std::string Channel(std::string_view vehicle_id, Topic t) {
  return std::string(vehicle_id) + "/" + TopicName(t);
}

bool IsValidVehicleId(std::string_view id) {
  if (id.empty() || id.size() > 32) return false;
  for (char c : id)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  return true;
}

}  // namespace uav
