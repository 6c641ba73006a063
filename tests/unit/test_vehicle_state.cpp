// The vehicle-state signal table against the LCM type it reads: every field of vehicle_state_t
// declared once, with a unit; the typed decoding round trip and its refusals; the enums' names.
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <gtest/gtest.h>

#include "uav/wire/messages.hpp"
#include "uav/shared/vehicle_state.hpp"
#include "uavmsg/vehicle_state_t.hpp"

namespace uav {
namespace {

// Field names of an .lcm struct ("rotor_input[0]".."[3]" for arrays), constants and the
// header/utime excluded.
std::vector<std::string> LcmFields(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<std::string> out;
  const std::regex field(R"(^\s*(?!const|package)\w+\s+(\w+)(?:\[(\d+)\])?\s*;)");
  for (std::string line; std::getline(in, line);) {
    line = line.substr(0, line.find("//"));
    std::smatch m;
    if (!std::regex_search(line, m, field)) continue;
    const std::string name = m[1];
    if (name == "utime" || name == "header") continue;
    if (m[2].matched) {
      for (int i = 0; i < std::stoi(m[2]); ++i) out.push_back(name + "[" + std::to_string(i) + "]");
    } else {
      out.push_back(name);
    }
  }
  return out;
}

TEST(VehicleStateSignals, EveryFieldOfTheMessageIsDeclaredOnceWithAUnit) {
  const auto fields = LcmFields(std::string(UAV_RESOURCE_DIR) + "/../shared/lcmtypes/vehicle_state_t.lcm");
  ASSERT_GT(fields.size(), 40u);
  std::map<std::string, int> declared;
  std::map<std::string, int> names;
  for (const auto& s : VehicleStateSignals()) {
    EXPECT_FALSE(s.def.unit.empty()) << s.def.name;
    ++names[std::string(s.def.name)];
    if (!s.def.field.empty()) ++declared[std::string(s.def.field)];
  }
  for (const auto& f : fields) EXPECT_EQ(declared[f], 1) << "vehicle_state_t." << f;
  EXPECT_EQ(declared.size(), fields.size()) << "a signal reads a field the message does not have";
  for (const auto& [name, n] : names) EXPECT_EQ(n, 1) << "signal name " << name << " declared twice";
}

TEST(VehicleStateSignals, ReadTheTypedStateAndFormatForTheOperator) {
  VehicleState s;
  s.p_N = {1, 2, -30};
  s.euler.psi = M_PI / 2;
  s.task = Task::kMission;
  s.battery_remaining = 0.5;
  std::map<std::string, const Signal<VehicleState>*> by_name;
  for (const auto& sig : VehicleStateSignals()) by_name[std::string(sig.def.name)] = &sig;
  EXPECT_DOUBLE_EQ(by_name["alt"]->read(s), 30.0);
  EXPECT_EQ(FormatForDisplay(by_name["alt"]->def, by_name["alt"]->read(s)), "30.00 m");
  EXPECT_EQ(FormatForDisplay(by_name["psi"]->def, by_name["psi"]->read(s)), "90.0 deg");  // degrees in the UI
  EXPECT_EQ(FormatForDisplay(by_name["task"]->def, by_name["task"]->read(s)), "mission");
  EXPECT_EQ(FormatForDisplay(by_name["battery_remaining"]->def, 0.5), "50 %");
  EXPECT_EQ(FormatForDisplay(by_name["x"]->def, 7.66e-05), "0.00 m");  // no 7.66e-05 for a position
  EXPECT_EQ(FormatForLog(by_name["x"]->def, 1.0), "1.0000");
  EXPECT_EQ(FormatForLog(by_name["task"]->def, 6.0), "6");
}

TEST(VehicleStateMessage, RoundTripsAndRefusesWhatTheTypedStateCannotHold) {
  VehicleState s;
  s.utime = 123456789;
  s.p_N = {1.5, -2.5, -10};
  s.euler = {0.1, -0.2, 0.3};
  s.task = Task::kReturn;
  s.failsafe = FailsafeAction::kLand;
  s.attitude_mode = AttitudeMode::kGyroHover;
  s.flight_mode = FlightMode::kManual;
  s.rotor_input = {0.25, 0.5, -0.25, 1};
  s.chirp_channel = 3;
  s.home = {1.3, 103.8, 15};
  uavmsg::vehicle_state_t m{};
  ToMessage(s, &m);
  const VehicleState back = FromMessage(m);
  EXPECT_EQ(back.utime, s.utime);
  EXPECT_EQ(back.p_N, s.p_N);
  EXPECT_EQ(back.task, Task::kReturn);
  EXPECT_EQ(back.failsafe, FailsafeAction::kLand);
  EXPECT_EQ(back.attitude_mode, AttitudeMode::kGyroHover);
  EXPECT_EQ(back.flight_mode, FlightMode::kManual);
  EXPECT_EQ(back.rotor_input, s.rotor_input);
  EXPECT_EQ(back.chirp_channel, 3);
  EXPECT_DOUBLE_EQ(back.home.longitude_deg, 103.8);

  auto refused = [](uavmsg::vehicle_state_t bad) -> std::string {
    try {
      FromMessage(bad);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  uavmsg::vehicle_state_t bad = m;
  bad.task = 99;
  EXPECT_NE(refused(bad).find("vehicle_state_t.task = 99"), std::string::npos);
  bad = m;
  bad.z = NAN;
  EXPECT_NE(refused(bad).find("x/y/z is not finite"), std::string::npos);
  bad = m;
  bad.failsafe = -1;
  EXPECT_NE(refused(bad).find("failsafe"), std::string::npos);
}

TEST(VehicleEnums, NamesAndWireValuesGoBothWays) {
  for (int i = 0; i < 10; ++i) {
    const auto t = TaskFromWire(i);
    ASSERT_TRUE(t);
    EXPECT_EQ(TaskFromName(Name(*t)), t);
  }
  EXPECT_FALSE(TaskFromWire(10));
  EXPECT_EQ(Name(CommandResult::kInProgress), "in_progress");
  EXPECT_EQ(CommandResultFromName("failed"), CommandResult::kFailed);
  EXPECT_FALSE(SeverityFromWire(5));
  EXPECT_EQ(Name(FailsafeAction::kManual), "manual");
}

}  // namespace
}  // namespace uav
