#pragma once
// The vehicle's task, command result, failsafe action, message severity and attitude wiring:
// declared once here with their names, and each value checked against the LCM constants that
// carry it (vehicle_enums.cpp, at compile time). Compare these, never their names.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace uav {

// What the task manager is doing (vehicle_state_t.TASK_*, heartbeat_t.task).
enum class Task : int8_t { kIdle = 0, kTakeoff = 1, kHover = 2, kGoto = 3, kLand = 4, kTrack = 5, kMission = 6, kReturn = 7, kFollow = 8, kSticks = 9 };
// Answer to a command (command_ack_t.RESULT_*).
enum class CommandResult : int8_t { kAccepted = 0, kRejected = 1, kInProgress = 2, kCompleted = 3, kFailed = 4, kReplaced = 5 };
// A result the operator must look at (red): refused, or started and not finished on its own.
inline bool IsFailure(CommandResult r) { return r == CommandResult::kRejected || r == CommandResult::kFailed; }
// The acknowledgement source of what the vehicle does on its own (a failsafe's hold, return or
// landing): its own rows in the GCS command list, never under an operator's command.
inline constexpr std::string_view kVehicleInitiatedSource = "vehicle";
// Strictest failsafe action required now (vehicle_state_t.FAILSAFE_*), ordered by strictness.
enum class FailsafeAction : int8_t { kNone = 0, kHold = 1, kReturn = 2, kLand = 3, kManual = 4 };
// Syslog / MAVLink STATUSTEXT severity (status_text_t.SEVERITY_*).
enum class Severity : int8_t { kError = 3, kWarning = 4, kInfo = 6 };
// How the servo board's four outputs reach the rotors (thesis 2.5, Fig. 2.21;
// vehicle_state_t.ATTITUDE_*).
enum class AttitudeMode : int8_t {
  kDirect = 0,      // outputs are the rotor inputs M_1..M_4; the autopilot mixes (Eq. 2.11)
  kGyroHover = 1,   // outputs go to the gyro, which holds roll and pitch angles (Eq. 2.17-2.19)
  kGyroCruise = 2,  // outputs go to the gyro, which holds the body rates (Eq. 2.20-2.22)
};
// The airframe the vehicle file describes (its vehicle_type; vehicle_state_t.VEHICLE_*).
enum class VehicleType : int8_t { kQuadrotor = 0, kTailSitter = 1 };
// A tail-sitter's flight mode (thesis 2.6; vehicle_state_t.VTOL_*): on its rotor, on its wing, or
// between the two. A quadrotor always hovers.
enum class VtolMode : int8_t { kHover = 0, kTransitionToWing = 1, kCruise = 2, kTransitionToHover = 3 };
// Who flies: the autopilot, or the pilot through the fail-safe switch (vehicle_state_t.MODE_*).
enum class FlightMode : int8_t { kManual = 0, kAuto = 1 };
// What obstacle avoidance's safety layer is doing (vehicle_state_t.AVOID_*).
enum class AvoidState : int8_t {
  kOff = 0,       // no task that travels, or avoidance disabled
  kClear = 1,     // the task's own straight way is clear: flown as the task planned it
  kAvoiding = 2,  // flying the planner's path around what is in the way
  kBlocked = 3,   // stopped short of occupied or unseen space (a textureless wall, a turn)
  kNoPath = 4,    // no way to the goal: holding
  kNoData = 5,    // perception or plan older than avd_stale: braking and holding
};

// Lower-case names as the operator reads and types them ("in_progress", "gyro_hover").
std::string_view Name(Task v);
std::string_view Name(CommandResult v);
std::string_view Name(FailsafeAction v);
std::string_view Name(Severity v);
std::string_view Name(AttitudeMode v);
std::string_view Name(FlightMode v);
std::string_view Name(AvoidState v);
std::string_view Name(VehicleType v);
std::string_view Name(VtolMode v);

// A name as the operator reads it in a sentence: "transition to wing" for "transition_to_wing".
std::string Spoken(std::string_view name);

// The enum for a wire value; nullopt when the value names none (a newer or broken sender).
std::optional<Task> TaskFromWire(int value);
std::optional<CommandResult> CommandResultFromWire(int value);
std::optional<FailsafeAction> FailsafeFromWire(int value);
std::optional<Severity> SeverityFromWire(int value);
std::optional<AttitudeMode> AttitudeModeFromWire(int value);
std::optional<FlightMode> FlightModeFromWire(int value);
std::optional<AvoidState> AvoidStateFromWire(int value);
std::optional<VehicleType> VehicleTypeFromWire(int value);
std::optional<VtolMode> VtolModeFromWire(int value);

// The enum whose Name() is `name` (for parameter files and scripts); nullopt when none is.
std::optional<Task> TaskFromName(std::string_view name);
std::optional<CommandResult> CommandResultFromName(std::string_view name);

}  // namespace uav
