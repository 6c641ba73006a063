#pragma once
// CMM thread: the GCS link. Receives commands, mission uploads and GCS heartbeats, publishes telemetry (50 Hz),
// heartbeat (1 Hz), acknowledgements and status texts. Messages stay here, at the edge.
#include <cstdint>
#include <memory>
#include <string>

#include "uav/app/blackboard.hpp"
#include "uav/app/command_intake.hpp"
#include "uav/app/event_log.hpp"
#include "uav/app/mission_store.hpp"
#include "uav/shared/bus.hpp"

namespace uav::app {

class LinkWorker {
 public:
  // Accepted mission uploads go to `missions`.
  // Accepted mission uploads go to `missions`; every bus message goes to `events` when given.
  LinkWorker(const std::string& vehicle_id, const std::string& lcm_url, Blackboard& board,
             MissionStore& missions, std::unique_ptr<EventLog> events = nullptr);
  ~LinkWorker();
  // Called at the telemetry rate (50 Hz).
  void Tick(int64_t utime);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::app
