#pragma once
// The GCS's MAVLink edge: PX4 and ArduPilot vehicles in the same model as ours. It listens (or
// connects) on one endpoint, recognises each vehicle's autopilot from its HEARTBEAT and feeds the
// model the typed data our own link does: heartbeat and state, status texts, the pre-arm
// state from SYS_STATUS, the parameter table (parameter service), the mission it holds (mission
// service), acknowledgements. The model's commands, whole-mission uploads, mission downloads,
// parameter changes and track targets for these vehicles go out as MAVLink (mavlink_commands.hpp
// for the commands). Video arrives as RTP/H.264 on a UDP port and is shown as the vehicle's
// camera. With a key, every frame sent is signed and every frame received must be signed with it.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "uav/gcs/gcs_model.hpp"
#include "uav/shared/mavlink_autopilots.hpp"
#include "uav/shared/signing.hpp"

namespace uav::gcs {

struct MavlinkLinkParams {
  // udpin:[HOST:]PORT, udp:HOST:PORT or serial:DEVICE[:BAUD]; "": none (bytes come from
  // ReceiveBytes, nothing is sent: a recording, the fuzzer).
  std::string endpoint = "udpin:14550";
  std::optional<SigningKey> key;         // none: unsigned, and unsigned frames accepted
  int video_port = 5600;                 // RTP/H.264 in (QGroundControl's default); 0: off
  // The services' patience: a request unanswered for `retry_s` is sent again, `max_tries` times.
  double retry_s = 1.5;
  int max_tries = 5;
};

class MavlinkLink {
 public:
  // Throws std::invalid_argument naming what is wrong with the endpoint, std::runtime_error when
  // it cannot be opened.
  MavlinkLink(const MavlinkLinkParams& params, GcsModel& model);
  ~MavlinkLink();
  // Reads what arrived, feeds the model, runs the services' resends and timeouts. `now`: GCS clock [s].
  void Receive(double now);
  // Bytes from elsewhere than the endpoint, as if received (then as Receive).
  void ReceiveBytes(const uint8_t* data, std::size_t size, double now);
  // Takes the entries of `out` for this link's vehicles and sends them.
  void Send(GcsOutgoing& out, double now);

  struct Counts {
    int64_t frames_in = 0, frames_out = 0;
    int64_t refused = 0;          // by the signature check
    int64_t unknown_messages = 0, bad_checksum = 0;
  };
  Counts counts() const;
  // Our id for a MAVLink vehicle: its autopilot and system id ("px4-1", "arducopter-7").
  static std::string VehicleIdOf(mavlink::Autopilot a, int system_id);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::gcs
