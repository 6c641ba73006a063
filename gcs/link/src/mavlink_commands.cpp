#include "uav/gcs/mavlink_commands.hpp"

#include <cmath>
#include <cstdio>

#include "uav/shared/command_grammar.hpp"

namespace uav::gcs {
namespace {

using mavlink::Autopilot;
using Completion = MavlinkPlan::Completion;

std::string Meters(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f m", v);
  return text;
}

MavlinkStep Simple(uint16_t command, std::array<float, 7> p, std::string what) {
  MavlinkStep s;
  s.command = command;
  s.param = p;
  s.what = std::move(what);
  return s;
}

// DO_SET_MODE to a mode of the autopilot's table (param1: MAV_MODE_FLAG_CUSTOM_MODE_ENABLED;
// PX4: param2 the main mode, param3 the sub-mode; ArduPilot: param2 the mode number).
MavlinkStep SetMode(Autopilot a, const char* name) {
  const mavlink::AutopilotMode* m = mavlink::FindModeNamed(a, name);
  const uint32_t c = m ? m->custom_mode : 0;
  if (a == Autopilot::kPx4)
    return Simple(mav_cmd::kDoSetMode, {1.f, static_cast<float>((c >> 16) & 0xFF), static_cast<float>(c >> 24), 0, 0, 0, 0},
                  std::string("set mode ") + name);
  return Simple(mav_cmd::kDoSetMode, {1.f, static_cast<float>(c), 0, 0, 0, 0, 0}, std::string("set mode ") + name);
}

MavlinkStep Reposition(const GeodeticPoint& target, double alt_above_home, const GeodeticPoint& home, bool amsl) {
  MavlinkStep s;
  s.command = mav_cmd::kDoReposition;
  s.command_int = true;
  // param1 ground speed (-1: the vehicle's default), param2 MAV_DO_REPOSITION_FLAGS_CHANGE_MODE,
  // param4 yaw (NaN: the vehicle's choice).
  s.param = {-1.f, 1.f, 0.f, NAN, 0.f, 0.f, 0.f};
  s.x = static_cast<int32_t>(std::lround(target.latitude_deg * 1e7));
  s.y = static_cast<int32_t>(std::lround(target.longitude_deg * 1e7));
  s.frame = amsl ? 0 : 3;
  s.param[6] = static_cast<float>(amsl ? home.altitude_m + alt_above_home : alt_above_home);
  s.what = "DO_REPOSITION to " + Meters(alt_above_home) + " above home";
  return s;
}

}  // namespace

MavlinkPlan PlanMavlinkCommand(const std::string& text, Autopilot a, bool vtol, const GeodeticPoint& home) {
  MavlinkPlan plan;
  const ParseResult parsed = ParseCommand(text);
  if (!parsed.ok()) {
    plan.refusal = parsed.error;
    return plan;
  }
  const Command& c = *parsed.command;
  const std::string who(mavlink::Name(a));
  const bool px4 = a == Autopilot::kPx4;
  const bool copter = a == Autopilot::kArduCopter;
  const bool plane = a == Autopilot::kArduPlane || a == Autopilot::kArduPlaneVtol;
  const bool quadplane = a == Autopilot::kArduPlaneVtol;
  if (a == Autopilot::kOther) {
    plan.refusal = "this autopilot is not PX4 or ArduPilot: its modes and commands are unknown, only watched";
    return plan;
  }
  auto& steps = plan.steps;
  switch (c.id) {
    case CommandId::kArm:
      steps.push_back(Simple(mav_cmd::kArmDisarm, {1, 0, 0, 0, 0, 0, 0}, "arm"));
      break;
    case CommandId::kDisarm:
      steps.push_back(Simple(mav_cmd::kArmDisarm, {0, 0, 0, 0, 0, 0, 0}, "disarm"));
      break;
    case CommandId::kEmergencyStop:
      steps.push_back(Simple(mav_cmd::kArmDisarm, {0, kForceDisarmMagic, 0, 0, 0, 0, 0}, "forced disarm"));
      break;
    case CommandId::kTakeoff: {
      const double alt = c.args[0];
      plan.completion = Completion::kAltitude;
      plan.target_alt_m = alt;
      if (px4) {  // param7: AMSL; param4 yaw and param5/6 position NaN: here, the vehicle's heading
        steps.push_back(Simple(mav_cmd::kNavTakeoff, {NAN, 0, 0, NAN, NAN, NAN, static_cast<float>(home.altitude_m + alt)},
                               "NAV_TAKEOFF to " + Meters(alt) + " above home"));
      } else if (copter || quadplane) {  // in Guided, param7 above home
        steps.push_back(SetMode(a, "Guided"));
        steps.push_back(Simple(mav_cmd::kNavTakeoff, {0, 0, 0, 0, 0, 0, static_cast<float>(alt)},
                               "NAV_TAKEOFF to " + Meters(alt) + " above home"));
      } else {  // a plane takes off in its Takeoff mode, to TKOFF_ALT
        steps.push_back(SetMode(a, "Takeoff"));
        plan.completion = Completion::kOnAccept;
      }
      break;
    }
    case CommandId::kHover:
      steps.push_back(SetMode(a, px4 ? "Hold" : copter ? "Loiter" : quadplane ? "QLoiter" : "Loiter"));
      break;
    case CommandId::kLand:
      plan.completion = Completion::kLanded;
      if (px4) steps.push_back(Simple(mav_cmd::kNavLand, {0, 0, 0, NAN, NAN, NAN, NAN}, "NAV_LAND here"));
      else if (copter) steps.push_back(SetMode(a, "Land"));
      else if (quadplane) steps.push_back(SetMode(a, "QLand"));
      else plan.refusal = "ArduPlane lands through a mission's landing sequence or RTL's autoland: use return or a mission";
      break;
    case CommandId::kReturn:
      plan.completion = Completion::kLanded;
      if (px4) steps.push_back(Simple(mav_cmd::kNavReturn, {0, 0, 0, 0, 0, 0, 0}, "NAV_RETURN_TO_LAUNCH"));
      else steps.push_back(SetMode(a, quadplane ? "QRTL" : "RTL"));
      if (plane && !quadplane) plan.completion = Completion::kOnAccept;  // a plane circles home
      break;
    case CommandId::kGoto: {
      const LocalNedFrame frame(home);
      const GeodeticPoint target = frame.ToGeodetic(Eigen::Vector3d(c.args[0], c.args[1], -c.args[2]));
      plan.completion = Completion::kPosition;
      plan.target_north_m = c.args[0], plan.target_east_m = c.args[1], plan.target_alt_m = c.args[2];
      if (!px4) steps.push_back(SetMode(a, "Guided"));
      steps.push_back(Reposition(target, c.args[2], home, px4));
      if (plane && !quadplane) plan.completion = Completion::kOnAccept;  // a plane loiters around it
      break;
    }
    case CommandId::kMission:
      plan.completion = Completion::kMissionEnd;
      if (!px4) steps.push_back(SetMode(a, "Auto"));
      // PX4 starts from Hold or the ground; ArduPilot needs it to start an Auto mission on the ground.
      steps.push_back(Simple(mav_cmd::kMissionStart, {0, 0, 0, 0, 0, 0, 0}, "MISSION_START"));
      break;
    case CommandId::kResume:
      plan.completion = Completion::kMissionEnd;
      steps.push_back(SetMode(a, px4 ? "Mission" : "Auto"));
      break;
    case CommandId::kFollow:
      if (px4) steps.push_back(SetMode(a, "Follow Me"));
      else if (copter) steps.push_back(SetMode(a, "Follow"));
      else plan.refusal = "ArduPlane has no follow mode";
      break;
    case CommandId::kTransition:
      if (!vtol) {
        plan.refusal = "this vehicle is not a VTOL";
        break;
      }
      // MAV_VTOL_STATE 3: multicopter, 4: fixed wing.
      steps.push_back(Simple(mav_cmd::kVtolTransition, {c.args[0] == 1.0 ? 4.f : 3.f, 0, 0, 0, 0, 0, 0},
                             c.args[0] == 1.0 ? "transition to fixed wing" : "transition to multicopter"));
      break;
    case CommandId::kTrack:
    case CommandId::kChirp:
    case CommandId::kGps:
    case CommandId::kSticks:
    case CommandId::kParam:
      plan.refusal = c.Name() + " is a command of our own vehicles; " + who + " has none like it";
      break;
  }
  if (plan.refusal.empty() && steps.empty()) plan.refusal = c.Name() + ": nothing to send to " + who;
  return plan;
}

const char* MavResultName(uint8_t r) {
  static const char* const kNames[] = {"ACCEPTED", "TEMPORARILY_REJECTED", "DENIED", "UNSUPPORTED", "FAILED",
                                       "IN_PROGRESS", "CANCELLED", "COMMAND_LONG_ONLY", "COMMAND_INT_ONLY",
                                       "UNSUPPORTED_MAV_FRAME"};
  return r < sizeof kNames / sizeof kNames[0] ? kNames[r] : "UNKNOWN_RESULT";
}

const char* MissionResultName(uint8_t r) {
  static const char* const kNames[] = {"ACCEPTED", "ERROR", "UNSUPPORTED_FRAME", "UNSUPPORTED", "NO_SPACE", "INVALID",
                                       "INVALID_PARAM1", "INVALID_PARAM2", "INVALID_PARAM3", "INVALID_PARAM4",
                                       "INVALID_PARAM5_X", "INVALID_PARAM6_Y", "INVALID_PARAM7", "INVALID_SEQUENCE",
                                       "DENIED", "OPERATION_CANCELLED"};
  return r < sizeof kNames / sizeof kNames[0] ? kNames[r] : "UNKNOWN_RESULT";
}

}  // namespace uav::gcs
