#pragma once
// The command bar's commands as a MAVLink autopilot takes them: each of ours becomes one or more
// MAVLink commands (COMMAND_LONG, or COMMAND_INT where a position travels), sent one after the
// other, each waiting for its COMMAND_ACK. PX4 flies most as commands (NAV_TAKEOFF at an AMSL
// altitude, DO_REPOSITION, MISSION_START) and the rest as its modes; ArduPilot flies by modes
// (Guided before a take-off or a go-to, Auto for the mission) and takes altitudes above home.
// A plain function of the text, the autopilot and home: the reference page is generated from it.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/geodesy.hpp"
#include "uav/shared/mavlink_autopilots.hpp"

namespace uav::gcs {

// MAV_CMD values the GCS sends.
namespace mav_cmd {
constexpr uint16_t kNavReturn = 20, kNavLand = 21, kNavTakeoff = 22, kDoSetMode = 176, kDoReposition = 192,
                   kMissionStart = 300, kArmDisarm = 400, kSetMessageInterval = 511, kRequestMessage = 512, kTrackRectangle = 2005,
                   kStopTracking = 2010, kVtolTransition = 3000;
}  // namespace mav_cmd
constexpr float kForceDisarmMagic = 21196.f;  // COMPONENT_ARM_DISARM param2: disarm in flight

struct MavlinkStep {
  uint16_t command = 0;
  std::array<float, 7> param{};  // for COMMAND_INT, param[4], param[5] are unused (x, y carry them)
  bool command_int = false;      // COMMAND_INT with x, y (1e-7 degrees) and z in `frame`
  int32_t x = 0, y = 0;
  uint8_t frame = 0;             // MAV_FRAME: 0 global (AMSL), 3 relative to home
  uint8_t component = 1;         // the autopilot
  std::string what;              // "set mode Guided", "NAV_TAKEOFF to 10 m"
};

// What our command becomes, how the GCS knows it is done, or why it cannot be sent.
struct MavlinkPlan {
  std::vector<MavlinkStep> steps;
  // After the last step's ACCEPTED: done at once (arm, a mode), or when the vehicle gets there.
  enum class Completion { kOnAccept, kAltitude, kPosition, kLanded, kMissionEnd };
  Completion completion = Completion::kOnAccept;
  double target_alt_m = 0;          // kAltitude, kPosition: above home [m]
  double target_north_m = 0, target_east_m = 0;  // kPosition: from home [m]
  std::string refusal;              // non-empty: not sent, this is why
};

// `text`: a command of our grammar (command_grammar.hpp). `vtol`: the vehicle is a VTOL.
MavlinkPlan PlanMavlinkCommand(const std::string& text, mavlink::Autopilot a, bool vtol, const GeodeticPoint& home);

// MAV_RESULT as a word ("ACCEPTED", "DENIED", ...).
const char* MavResultName(uint8_t result);
// MAV_MISSION_RESULT as a word ("ACCEPTED", "INVALID_SEQUENCE", ...).
const char* MissionResultName(uint8_t result);

}  // namespace uav::gcs
