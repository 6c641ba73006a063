#pragma once
// Mission upload GCS -> vehicle in chunks that each fit one UDP datagram (LCM 1.3.1 fragments
// larger messages, drops them whole on any loss and can corrupt them when a fragment is
// duplicated). Stop-and-wait: the GCS sends a chunk, the vehicle acknowledges how many items it
// holds, the GCS sends the next or resends after a timeout. The last acknowledgement accepts
// or rejects the whole mission, checked against a digest of its content. Plain classes; the
// LCM messages (mission_upload_t, mission_ack_t) are converted at the edges.
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {

// 12 items of ~70 bytes plus the header stay under a 1400-byte datagram.
constexpr int kItemsPerChunk = 12;

// FNV-1a 64 over every field that the vehicle flies (home, speed, items), bit-exact.
uint64_t MissionDigest(const Mission& m);

struct MissionChunk {
  int64_t upload_id = 0;
  int total_items = 0;
  int first_index = 0;
  std::vector<MissionItem> items;
  GeodeticPoint home;
  double cruise_speed_m_s = 0;
  uint64_t digest = 0;  // of the whole mission
};

struct MissionUploadAck {
  enum class Result { kInProgress, kAccepted, kRejected };
  int64_t upload_id = 0;
  int received_items = 0;  // items held so far: the next chunk starts here
  int total_items = 0;
  Result result = Result::kInProgress;
  std::string reason;      // why rejected
  uint64_t digest = 0;
};

std::vector<MissionChunk> SplitMission(const Mission& m, int64_t upload_id);

// Vehicle side: assembles chunks from one GCS. `accept` validates and stores a complete mission
// and returns "" or the reason it was refused.
class MissionAssembler {
 public:
  MissionUploadAck Receive(const MissionChunk& c, const std::function<std::string(const Mission&)>& accept);

 private:
  std::optional<MissionUploadAck> finished_;  // answer for a repeated last chunk
  int64_t upload_id_ = -1;
  Mission mission_;
  int total_ = 0;
};

// GCS side: drives one upload.
class MissionUploader {
 public:
  static constexpr double kResendTimeout = 0.5;  // [s]
  static constexpr int kMaxTries = 8;            // per chunk

  MissionUploader(const Mission& m, int64_t upload_id);
  // Chunks to send now (the first one at once, a resend after the timeout).
  std::vector<MissionChunk> Tick(double now);
  void OnAck(const MissionUploadAck& ack, double now);

  enum class State { kSending, kAccepted, kRejected, kFailed };
  State state() const { return state_; }
  const std::string& reason() const { return reason_; }
  int64_t upload_id() const { return upload_id_; }
  int acknowledged_items() const { return acked_; }
  int total_items() const { return total_; }
  const Mission& mission() const { return mission_; }

 private:
  Mission mission_;
  std::vector<MissionChunk> chunks_;
  int64_t upload_id_;
  int total_;
  int acked_ = 0;
  std::size_t next_ = 0;     // chunk being sent
  double last_sent_ = -1e9;
  int tries_ = 0;
  State state_ = State::kSending;
  std::string reason_;
  uint64_t digest_;
};

}  // namespace uav::waypoints
