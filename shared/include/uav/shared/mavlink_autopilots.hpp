#pragma once
// What a ground station must know of the autopilot behind a MAVLink HEARTBEAT: which one it is,
// its flight modes (HEARTBEAT.custom_mode), how its parameters put integers into PARAM_VALUE's
// float, and whether its mission list starts with home. From the autopilots' documentation:
// PX4 (px4_custom_mode.h; parameters byte-wise; the mission starts at item 0), ArduPilot
// (Copter and Plane mode numbers from their mode.h; parameters C-cast to float; item 0 of the
// mission is home). The reference page (docs/reference/mavlink.md) is generated from these tables.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "uav/shared/vehicle_enums.hpp"

namespace uav::mavlink {

// HEARTBEAT.autopilot (MAV_AUTOPILOT) and HEARTBEAT.type (MAV_TYPE) values we tell apart.
constexpr uint8_t kAutopilotArduPilot = 3, kAutopilotPx4 = 12;

enum class Autopilot { kPx4, kArduCopter, kArduPlane, kArduPlaneVtol, kOther };
std::string_view Name(Autopilot a);  // "PX4", "ArduCopter", "ArduPlane", "ArduPlane VTOL", "generic"
bool IsArduPilot(Autopilot a);
// From the first HEARTBEAT: PX4 by its autopilot id; ArduPilot's firmware by the vehicle type
// (multirotors and helicopters: Copter; fixed wing: Plane; the VTOL types: a QuadPlane).
Autopilot RecognizeAutopilot(uint8_t heartbeat_autopilot, uint8_t mav_type);
// What our state list shows for HEARTBEAT.type: "quadrotor", "fixed wing", "VTOL tail-sitter".
std::string_view VehicleTypeName(uint8_t mav_type);
bool IsVtolType(uint8_t mav_type);
bool IsFixedWingType(uint8_t mav_type);

// One of an autopilot's flight modes, and the task of ours it stands for (what the GCS's state
// list, plots and scripts show as `task`; none for the pilot's own modes).
struct AutopilotMode {
  uint32_t custom_mode = 0;  // PX4: main mode << 16 | sub mode << 24; ArduPilot: the mode number
  const char* name = "";     // as QGroundControl and Mission Planner show it
  std::optional<Task> task;
};
const std::vector<AutopilotMode>& ModesOf(Autopilot a);
// The mode HEARTBEAT.custom_mode names, or null for one the table does not hold.
const AutopilotMode* FindMode(Autopilot a, uint32_t custom_mode);
// By name (case-insensitive), or null.
const AutopilotMode* FindModeNamed(Autopilot a, std::string_view name);
// "Mission", or "mode 0x00040000" for a custom mode the table does not hold.
std::string ModeName(Autopilot a, uint32_t custom_mode);

// How PARAM_VALUE and PARAM_SET carry a value in their float field (mavlink.io, parameter
// protocol: "Parameter encoding"): PX4 copies an integer's bytes into it, ArduPilot casts it.
enum class ParamEncoding { kBytewise, kCCast };
ParamEncoding ParamEncodingOf(Autopilot a);
// AUTOPILOT_VERSION.capabilities bits that say which (they win over the autopilot's default).
constexpr uint64_t kCapabilityParamBytewise = 16, kCapabilityParamCCast = 131072;
// MAV_PARAM_TYPE: 1 UINT8 .. 6 INT32, 9 REAL32 (7, 8, 10 are 64-bit: not carried by a float).
constexpr uint8_t kParamUint8 = 1, kParamInt32 = 6, kParamReal32 = 9;
// The value `wire` stands for; nullopt for a type the float cannot carry (64-bit) or an unknown one.
std::optional<double> DecodeParamValue(float wire, uint8_t param_type, ParamEncoding e);
// The float to send for `value`; nullopt (and `why`) when the type cannot hold it: a fraction or
// out-of-range number for an integer type, a 64-bit or unknown type.
std::optional<float> EncodeParamValue(double value, uint8_t param_type, ParamEncoding e, std::string* why);

// ArduPilot keeps home as item 0 of the mission list: uploads put it there, downloads start with
// it, MISSION_CURRENT and MISSION_ITEM_REACHED count it. PX4 starts the mission at item 0.
bool HomeIsMissionItemZero(Autopilot a);

}  // namespace uav::mavlink
