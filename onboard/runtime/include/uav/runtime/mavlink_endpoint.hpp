#pragma once
// The vehicle on MAVLink (QGroundControl, Mission Planner, any MAVLink 2 ground station): a
// translator between MAVLink and the vehicle's own link, running on the link thread beside our
// LCM GCS. It presents the vehicle as PX4 (HEARTBEAT custom modes, AUTOPILOT_VERSION) and speaks
// to the vehicle exactly as our GCS does: it reads the state, pre-arm report, parameter table,
// status texts and acknowledgements off the bus, and puts commands, mission uploads, GCS
// heartbeats and track targets on it, signed with the vehicle's key. So every MAVLink command
// goes through the checks of our own, and each GCS sees what the other's commands did.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "uav/shared/signing.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav {
class Bus;
}

namespace uav::runtime {

struct MavlinkParams {
  std::string endpoint;      // udp:HOST:PORT, udpin:[HOST:]PORT or serial:DEVICE[:BAUD] (mavlink_transport.hpp)
  int system_id = 1;         // MAVLink system id of the vehicle (its autopilot is component 1, its camera 100)
  bool insecure = false;     // accept unsigned frames (the frames sent are signed whenever there is a key)
  // RTP/H.264 video of the vehicle's video camera, QGroundControl's default ("" none).
  std::string video_host = "127.0.0.1";
  int video_port = 5600;
  // A command handed to the vehicle on the bus and not answered within `command_resend_s` [s,
  // wall clock] is published again (the bus lost it); after `command_tries` publications the GCS
  // gets MAV_RESULT_FAILED and a status text saying so.
  double command_resend_s = 1.0;
  int command_tries = 5;
};

class MavlinkEndpoint {
 public:
  // `key`: the vehicle's signing key, for MAVLink (SHA-256 of the passphrase the MAVLink GCS
  // types: uav-keygen --passphrase) and for the bus. Without one, frames go unsigned and only
  // `insecure` lets anything in. `say` makes a status text of the vehicle's (both GCSs hear it:
  // a GCS connected, frames refused). Throws naming the endpoint when it cannot be opened.
  using Say = std::function<void(Severity, const std::string&)>;
  MavlinkEndpoint(const std::string& vehicle_id, Bus& bus, const MavlinkParams& params,
                  const std::optional<SigningKey>& key, Say say);
  ~MavlinkEndpoint();
  // On the link thread, after the bus was handled: reads and answers what arrived, sends the
  // telemetry due at the vehicle's clock `utime`.
  void Tick(int64_t utime);

  // What was refused or dropped, for the operator and the tests.
  struct Counts {
    int64_t frames_in = 0, frames_out = 0;
    int64_t bad_checksum = 0, unknown_message = 0, bad_flags = 0, skipped_bytes = 0;
    int64_t unsigned_frames = 0, bad_signature = 0, replayed = 0, stale = 0;
    int64_t commands = 0, commands_refused = 0;
    int64_t commands_resent = 0, commands_unanswered = 0;  // bus publications again; given up
    int64_t bad_bus_messages = 0;  // the vehicle's own channels: messages that did not convert
  };
  Counts counts() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::runtime
