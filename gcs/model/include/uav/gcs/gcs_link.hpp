#pragma once
// The GCS's edge to the bus: turns LCM messages into model inputs and model outputs into LCM
// messages, and sends the GCS heartbeat (1 Hz) to every vehicle it knows.
#include <memory>
#include <string>

#include "uav/gcs/gcs_model.hpp"

namespace uav::gcs {

class GcsLink {
 public:
  // Throws std::runtime_error naming the URL when LCM cannot start.
  GcsLink(const std::string& lcm_url, GcsModel& model);
  ~GcsLink();
  // Receives for up to timeout_ms, then sends what the model queued. `now` is the GCS clock [s].
  void Poll(int timeout_ms, double now);
  int64_t dropped_messages() const;  // undecodable, or vehicle id not matching the channel

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::gcs
