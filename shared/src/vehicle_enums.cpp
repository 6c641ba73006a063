#include "uav/shared/vehicle_enums.hpp"


namespace uav {
namespace {

// One table per enum: value and name, in wire order. Name(), FromWire() and FromName() read it.
template <class E>
struct Entry {
  E value;
  std::string_view name;
};
constexpr Entry<Task> kTasks[] = {{Task::kIdle, "idle"}, {Task::kTakeoff, "takeoff"}, {Task::kHover, "hover"},
                                  {Task::kGoto, "goto"}, {Task::kLand, "land"},       {Task::kTrack, "track"},
                                  {Task::kMission, "mission"}, {Task::kReturn, "return"},
                                  {Task::kFollow, "follow"}, {Task::kSticks, "sticks"}};
constexpr Entry<CommandResult> kResults[] = {{CommandResult::kAccepted, "accepted"},
                                             {CommandResult::kRejected, "rejected"},
                                             {CommandResult::kInProgress, "in_progress"},
                                             {CommandResult::kCompleted, "completed"},
                                             {CommandResult::kFailed, "failed"},
                                             {CommandResult::kReplaced, "replaced"}};
constexpr Entry<FailsafeAction> kFailsafes[] = {{FailsafeAction::kNone, "none"},     {FailsafeAction::kHold, "hold"},
                                                {FailsafeAction::kReturn, "return"}, {FailsafeAction::kLand, "land"},
                                                {FailsafeAction::kManual, "manual"}};
constexpr Entry<Severity> kSeverities[] = {{Severity::kError, "error"}, {Severity::kWarning, "warning"},
                                           {Severity::kInfo, "info"}};
constexpr Entry<AttitudeMode> kAttitudeModes[] = {{AttitudeMode::kDirect, "direct"},
                                                  {AttitudeMode::kGyroHover, "gyro_hover"},
                                                  {AttitudeMode::kGyroCruise, "gyro_cruise"}};
constexpr Entry<FlightMode> kFlightModes[] = {{FlightMode::kManual, "manual"}, {FlightMode::kAuto, "auto"}};
constexpr Entry<AvoidState> kAvoidStates[] = {{AvoidState::kOff, "off"},         {AvoidState::kClear, "clear"},
                                              {AvoidState::kAvoiding, "avoiding"}, {AvoidState::kBlocked, "blocked"},
                                              {AvoidState::kNoPath, "no_path"},    {AvoidState::kNoData, "no_data"}};
constexpr Entry<VehicleType> kVehicleTypes[] = {{VehicleType::kQuadrotor, "quadrotor"}, {VehicleType::kTailSitter, "tail_sitter"}};
constexpr Entry<VtolMode> kVtolModes[] = {{VtolMode::kHover, "hover"},
                                          {VtolMode::kTransitionToWing, "transition_to_wing"},
                                          {VtolMode::kCruise, "cruise"},
                                          {VtolMode::kTransitionToHover, "transition_to_hover"}};

template <class E, std::size_t N>
std::string_view NameIn(const Entry<E> (&table)[N], E v) {
  for (const auto& e : table)
    if (e.value == v) return e.name;
  return "unknown";
}
template <class E, std::size_t N>
std::optional<E> FromWireIn(const Entry<E> (&table)[N], int v) {
  for (const auto& e : table)
    if (static_cast<int>(e.value) == v) return e.value;
  return std::nullopt;
}
template <class E, std::size_t N>
std::optional<E> FromNameIn(const Entry<E> (&table)[N], std::string_view name) {
  for (const auto& e : table)
    if (e.name == name) return e.value;
  return std::nullopt;
}

}  // namespace

std::string_view Name(Task v) { return NameIn(kTasks, v); }
std::string_view Name(CommandResult v) { return NameIn(kResults, v); }
std::string_view Name(FailsafeAction v) { return NameIn(kFailsafes, v); }
std::string_view Name(Severity v) { return NameIn(kSeverities, v); }
std::string_view Name(AttitudeMode v) { return NameIn(kAttitudeModes, v); }
std::string_view Name(FlightMode v) { return NameIn(kFlightModes, v); }
std::string_view Name(AvoidState v) { return NameIn(kAvoidStates, v); }
std::string Spoken(std::string_view name) {
  std::string s(name);
  for (char& c : s)
    if (c == '_') c = ' ';
  return s;
}

std::string_view Name(VehicleType v) { return NameIn(kVehicleTypes, v); }
std::string_view Name(VtolMode v) { return NameIn(kVtolModes, v); }
std::optional<Task> TaskFromWire(int v) { return FromWireIn(kTasks, v); }
std::optional<VehicleType> VehicleTypeFromWire(int v) { return FromWireIn(kVehicleTypes, v); }
std::optional<VtolMode> VtolModeFromWire(int v) { return FromWireIn(kVtolModes, v); }
std::optional<CommandResult> CommandResultFromWire(int v) { return FromWireIn(kResults, v); }
std::optional<FailsafeAction> FailsafeFromWire(int v) { return FromWireIn(kFailsafes, v); }
std::optional<Severity> SeverityFromWire(int v) { return FromWireIn(kSeverities, v); }
std::optional<AttitudeMode> AttitudeModeFromWire(int v) { return FromWireIn(kAttitudeModes, v); }
std::optional<FlightMode> FlightModeFromWire(int v) { return FromWireIn(kFlightModes, v); }
std::optional<AvoidState> AvoidStateFromWire(int v) { return FromWireIn(kAvoidStates, v); }
std::optional<Task> TaskFromName(std::string_view n) { return FromNameIn(kTasks, n); }
std::optional<CommandResult> CommandResultFromName(std::string_view n) { return FromNameIn(kResults, n); }

}  // namespace uav
