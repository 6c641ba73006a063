#pragma once
// The GCS's edge to the bus: decodes each message once into the model's typed inputs, and turns
// the model's outgoing requests into LCM messages, with the GCS heartbeat (1 Hz) to every
// vehicle it knows. The same decoding serves a recorded event log (replay): Dispatch() takes a
// channel and the bytes as they were on the bus.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uav/shared/channels.hpp"

#include "uav/gcs/gcs_model.hpp"
#include "uav/shared/signing.hpp"

namespace uav {
class Bus;
}

namespace uav::gcs {

class GcsLink {
 public:
  static constexpr double kHeartbeatPeriod = 1.0;  // [s] GCS heartbeat to each vehicle

  // Receives and sends on `bus` (a UDP multicast bus, or memq:// in tests); `bus` == nullptr:
  // decode only (replay), nothing is ever sent. With `key`, every message that changes what a
  // vehicle does (commands, mission uploads, targets, file requests, heartbeats) is signed
  // (shared/signing.hpp) on link `link_id`; without, they go unsigned (--insecure).
  GcsLink(Bus* bus, GcsModel& model, const std::optional<SigningKey>& key, int link_id = 0);
  ~GcsLink();
  // Receives for up to timeout_ms, then sends what the model queued. `now` is the GCS clock [s].
  void Poll(int timeout_ms, double now);
  // The two halves, for a GCS with other links: receive; then send the entries of `out` (what
  // the other links left of GcsModel::TakeOutgoing()) and the heartbeats to our vehicles.
  void Receive(int timeout_ms, double now);
  void Send(GcsOutgoing& out, double now);
  // Decodes one message as it was on `channel` and feeds the model. Returns false (and counts it
  // in dropped_messages()) when the channel is not ours, the bytes do not decode, or the
  // content is refused (a vehicle id not matching the channel, an unknown enum value).
  bool Dispatch(const std::string& channel, const void* data, int size, double now);
  // The topics Dispatch decodes, in Topic order (the fuzz target and its seeds index them).
  static std::vector<Topic> Topics();
  int64_t dropped_messages() const;
  const std::string& last_drop_reason() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::gcs
