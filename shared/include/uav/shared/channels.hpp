#pragma once
// LCM channel names: "<VEHICLE>/<TOPIC>", so several vehicles share one bus.
#include <string>
#include <string_view>

namespace uav {

// A topic: the last part of a channel's name. The operator's own topics are declared here; each
// vehicle report declares its own beside its message (Report<T>::kTopic in uav/wire/reports.hpp).
struct Topic {
  const char* name;

  friend constexpr bool operator==(Topic a, Topic b) { return std::string_view(a.name) == b.name; }
  friend constexpr bool operator!=(Topic a, Topic b) { return !(a == b); }
  friend constexpr bool operator<(Topic a, Topic b) { return std::string_view(a.name) < b.name; }

  static const Topic kHeartbeat, kGcsHeartbeat, kState, kCommand, kCommandAck, kStatusText, kMissionUpload,
      kMissionAck, kVideo, kFileOffer, kFileRequest, kFileChunk, kMapTile, kTrackTarget, kTrackStatus,
      kManualControl;
};
inline constexpr Topic Topic::kHeartbeat{"HEARTBEAT"};
inline constexpr Topic Topic::kGcsHeartbeat{"GCS_HEARTBEAT"};
inline constexpr Topic Topic::kState{"STATE"};
inline constexpr Topic Topic::kCommand{"COMMAND"};
inline constexpr Topic Topic::kCommandAck{"COMMAND_ACK"};
inline constexpr Topic Topic::kStatusText{"STATUS_TEXT"};
inline constexpr Topic Topic::kMissionUpload{"MISSION_UPLOAD"};
inline constexpr Topic Topic::kMissionAck{"MISSION_ACK"};
inline constexpr Topic Topic::kVideo{"VIDEO"};
inline constexpr Topic Topic::kFileOffer{"FILE_OFFER"};
inline constexpr Topic Topic::kFileRequest{"FILE_REQUEST"};
inline constexpr Topic Topic::kFileChunk{"FILE_CHUNK"};
inline constexpr Topic Topic::kMapTile{"MAP_TILE"};
inline constexpr Topic Topic::kTrackTarget{"TRACK_TARGET"};
inline constexpr Topic Topic::kTrackStatus{"TRACK_STATUS"};
inline constexpr Topic Topic::kManualControl{"MANUAL_CONTROL"};

constexpr const char* TopicName(Topic t) { return t.name; }
std::string Channel(std::string_view vehicle_id, Topic t);

// A vehicle id is 1..32 characters of [A-Za-z0-9_-]: it forms channel names.
bool IsValidVehicleId(std::string_view id);

// Default LCM URL: UDP multicast that stays on this machine (ttl=0) with a receive buffer large
// enough for bursts of telemetry (the kernel default drops them).
constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608";

}  // namespace uav
