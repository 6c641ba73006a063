#pragma once
// How a vehicle speaks to a MAVLink ground station as PX4 (QGroundControl allows mode changes
// and guided commands only to an autopilot it knows): PX4's custom modes (px4_custom_mode.h,
// main mode in bits 16-23 of HEARTBEAT.custom_mode, AUTO's sub-mode in bits 24-31) and which of
// our tasks each stands for. The vehicle's endpoint reports and accepts modes from this table;
// the reference page (docs/reference/mavlink.md) is generated from it.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "uav/shared/vehicle_enums.hpp"

namespace uav::mavlink {

namespace px4 {
constexpr uint8_t kMainPosctl = 3, kMainAuto = 4;
constexpr uint8_t kAutoTakeoff = 2, kAutoLoiter = 3, kAutoMission = 4, kAutoRtl = 5, kAutoLand = 6, kAutoFollow = 8;
}  // namespace px4

struct Px4Mode {
  uint8_t main_mode = 0, sub_mode = 0;
  const char* name = "";        // as QGroundControl shows it
  std::vector<Task> tasks;      // ours that the heartbeat reports as this mode
  const char* command = "";     // what DO_SET_MODE to it asks of the vehicle ("" refused)
  uint32_t custom_mode() const { return (uint32_t{main_mode} << 16) | (uint32_t{sub_mode} << 24); }
};

// Every PX4 mode the vehicle reports or accepts.
const std::vector<Px4Mode>& Px4Modes();
// The mode the heartbeat reports while `task` runs.
const Px4Mode& Px4ModeOf(Task task);
// The mode DO_SET_MODE names (custom main and sub mode), or null for one this vehicle does not fly.
const Px4Mode* FindPx4Mode(uint8_t main_mode, uint8_t sub_mode);

}  // namespace uav::mavlink
