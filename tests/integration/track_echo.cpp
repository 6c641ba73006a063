// A stand-in for the onboard tracker (a later issue), for the GCS's target-selection scenario:
// it answers every track_target_t on <VEHICLE>/TRACK_TARGET with track_status_t at 10 Hz on
// <VEHICLE>/TRACK_STATUS: tracking a box at the selection's centre and size, idle after a
// cancel. It also logs each selection to stdout so the test can check what the GCS sent.
// Usage: track_echo LCM_URL VEHICLE_ID SECONDS
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "uav/shared/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/time.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: track_echo LCM_URL VEHICLE_ID SECONDS\n");
    return 2;
  }
  const std::string id = argv[2];
  uav::Bus bus(argv[1]);
  uavmsg::track_status_t status{};
  status.header.vehicle_id = id;
  bus.Subscribe<uavmsg::track_target_t>(
      uav::Channel(id, uav::Topic::kTrackTarget), [&](const std::string&, const uavmsg::track_target_t& m) {
        std::printf("target %lld method %d x %.4f y %.4f w %.4f h %.4f frame %lld\n",
                    static_cast<long long>(m.target_seq), m.method, m.x, m.y, m.width, m.height,
                    static_cast<long long>(m.frame_utime));
        std::fflush(stdout);
        status.target_seq = m.target_seq;
        status.state = m.method == uavmsg::track_target_t::METHOD_CANCEL ? uavmsg::track_status_t::STATE_IDLE
                                                                          : uavmsg::track_status_t::STATE_TRACKING;
        status.center_x = m.x + 0.5 * m.width;
        status.center_y = m.y + 0.5 * m.height;
        status.width = m.width;
        status.height = m.height;
        status.angle_rad = 0.2;
      });
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::atof(argv[3]));
  auto next = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() < end) {
    bus.Handle(20);
    if (std::chrono::steady_clock::now() >= next && status.target_seq > 0) {
      next += std::chrono::milliseconds(100);
      status.utime = uav::WallTimeMicros();
      ++status.header.seq;
      bus.Publish(uav::Channel(id, uav::Topic::kTrackStatus), status);
    }
  }
  return 0;
}
