#pragma once
// CMM thread: the GCS link. A thin shell that owns the bus and one translator per topic
// (link_translators.hpp): inbound ones turn commands, mission uploads, file requests and GCS
// heartbeats into blackboard and store inputs; outbound ones publish the state (every tick,
// 50 Hz), heartbeat, acknowledgements, status texts, video, live-map tiles and file offers.
// Messages stay here, at the edge.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/event_log.hpp"
#include "uav/runtime/mavlink_endpoint.hpp"
#include "uav/runtime/mission_store.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/signing.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav {
class Bus;
}

namespace uav::runtime {

struct LinkParams {
  double heartbeat_period_s = 1.0;  // link_heartbeat_period
  double tile_period_s = 0.2;       // link_tile_period: at most one live-map tile per period
  // The simulator's asked pace (--speed; 0: as fast as it goes; < 0: real hardware), reported
  // in the heartbeat with the measured one.
  double sim_rate_asked = -1.0;
  AttitudeMode attitude_mode = AttitudeMode::kDirect;  // reported in the state
  // Message signing (shared/signing.hpp): without a key (--insecure) unsigned messages are
  // executed. The newest accepted timestamp is kept in `signing_state_file` across restarts.
  std::optional<SigningKey> signing_key;
  std::string signing_state_file;
  // A MAVLink endpoint beside the LCM link (off when unset), signing with `signing_key`.
  std::optional<MavlinkParams> mavlink;
  static LinkParams FromParameters(const ParameterSet& p, AttitudeMode attitude_mode);
};

class LinkWorker {
 public:
  // Accepted mission uploads go to `missions`; every bus message goes to `events` when given.
  LinkWorker(const std::string& vehicle_id, const std::string& lcm_url, const LinkParams& params, Blackboard& board,
             MissionStore& missions, std::unique_ptr<EventLog> events = nullptr);
  // The same on a bus the caller owns (a test's memq:// shared with a GCS in the same process;
  // the caller's thread must not handle it while this one ticks).
  LinkWorker(const std::string& vehicle_id, Bus& bus, const LinkParams& params, Blackboard& board, MissionStore& missions,
             std::unique_ptr<EventLog> events = nullptr);
  ~LinkWorker();
  // Called at the telemetry rate (50 Hz).
  void Tick(int64_t utime);

 private:
  void Start(std::unique_ptr<EventLog> events);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::runtime
