#pragma once
// LCM channel names: "<VEHICLE>/<TOPIC>", so several vehicles share one bus.
#include <string>
#include <string_view>

namespace uav {

enum class Topic {
  kHeartbeat,
  kGcsHeartbeat,
  kState,
  kCommand,
  kCommandAck,
  kStatusText,
  kMissionUpload,
  kMissionAck,
  kVideo,
  kFileOffer,
  kFileRequest,
  kFileChunk,
  kMapTile,
  kTrackTarget,
  kTrackStatus,
  kPowerLines,
  kObstacles,
  kPointCloud,
  kMonoDepth,
  kActiveStereo,
  kVisualOdometry,
  kSensing
};

const char* TopicName(Topic t);
std::string Channel(std::string_view vehicle_id, Topic t);

// A vehicle id is 1..32 characters of [A-Za-z0-9_-]: it forms channel names.
bool IsValidVehicleId(std::string_view id);

// Default LCM URL: UDP multicast that stays on this machine (ttl=0) with a receive buffer large
// enough for bursts of telemetry (the kernel default drops them).
constexpr const char* kDefaultLcmUrl = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608";

}  // namespace uav
