#pragma once
// Where MAVLink bytes go: a UDP peer (QGroundControl and Mission Planner listen on 14550), a UDP
// port that answers whoever speaks to it, or a serial device (a telemetry radio). Non-blocking:
// the link thread polls it once a tick.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace uav::mavlink {

class MavlinkTransport {
 public:
  virtual ~MavlinkTransport() = default;
  // What arrived since the last call, in the pieces the link delivers (empty: nothing): one per
  // UDP datagram, one for a serial line's bytes.
  virtual std::vector<std::vector<uint8_t>> Receive() = 0;
  // Whether each piece holds whole frames (a datagram: a sender never splits a frame across two,
  // so a damaged or truncated datagram is dropped alone instead of swallowing the frames after
  // it) or is part of a stream (a serial line: a frame may span two reads).
  virtual bool datagrams() const = 0;
  // Sends one frame (dropped, and counted by the caller, when the peer is unknown or the link full).
  virtual bool Send(const std::vector<uint8_t>& bytes) = 0;
  virtual std::string Describe() const = 0;
  // What the link carries [bytes/s]: a serial line's baud rate / 10; 0 for a network.
  virtual int bytes_per_second() const { return 0; }
};

// "udp:HOST:PORT"     send to HOST:PORT from a port of our own, and read what comes back;
// "udpin:[HOST:]PORT" listen on PORT and answer the latest sender;
// "serial:DEVICE[:BAUD]" a serial device, raw 8N1 (57600 by default).
// Throws std::invalid_argument naming what is wrong with `spec`, std::runtime_error when the
// socket or device cannot be opened.
std::unique_ptr<MavlinkTransport> OpenMavlinkTransport(const std::string& spec);

}  // namespace uav::mavlink
