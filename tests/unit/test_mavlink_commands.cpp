// The command bar's commands as each autopilot takes them (gcs/link/mavlink_commands.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "uav/gcs/mavlink_commands.hpp"

namespace uav::gcs {
namespace {

using mavlink::Autopilot;
const GeodeticPoint kHome{1.2966, 103.7764, 15.0};

TEST(MavlinkCommands, TakeoffPx4AtAmslArduCopterInGuided) {
  const MavlinkPlan px4 = PlanMavlinkCommand("takeoff 10", Autopilot::kPx4, false, kHome);
  ASSERT_EQ(px4.steps.size(), 1u);
  EXPECT_EQ(px4.steps[0].command, mav_cmd::kNavTakeoff);
  EXPECT_FLOAT_EQ(px4.steps[0].param[6], 25.f);  // AMSL: home's 15 m + 10 m
  EXPECT_EQ(px4.completion, MavlinkPlan::Completion::kAltitude);
  const MavlinkPlan apm = PlanMavlinkCommand("takeoff 10", Autopilot::kArduCopter, false, kHome);
  ASSERT_EQ(apm.steps.size(), 2u);
  EXPECT_EQ(apm.steps[0].command, mav_cmd::kDoSetMode);
  EXPECT_FLOAT_EQ(apm.steps[0].param[1], 4.f);  // Guided
  EXPECT_EQ(apm.steps[1].command, mav_cmd::kNavTakeoff);
  EXPECT_FLOAT_EQ(apm.steps[1].param[6], 10.f);  // above home
  // A plane takes off in its Takeoff mode.
  const MavlinkPlan plane = PlanMavlinkCommand("takeoff 30", Autopilot::kArduPlane, false, kHome);
  ASSERT_EQ(plane.steps.size(), 1u);
  EXPECT_FLOAT_EQ(plane.steps[0].param[1], 13.f);
}

TEST(MavlinkCommands, GotoIsARepositionWherePositionsAreIntegers) {
  const MavlinkPlan px4 = PlanMavlinkCommand("goto 100 0 20", Autopilot::kPx4, false, kHome);
  ASSERT_EQ(px4.steps.size(), 1u);
  const MavlinkStep& s = px4.steps[0];
  EXPECT_EQ(s.command, mav_cmd::kDoReposition);
  EXPECT_TRUE(s.command_int);
  EXPECT_EQ(s.frame, 0);
  EXPECT_FLOAT_EQ(s.param[6], 35.f);
  // 100 m north: 100 / 110,574 m per degree of latitude near the equator.
  EXPECT_NEAR(s.x * 1e-7 - kHome.latitude_deg, 100.0 / 110574.0, 2e-6);
  EXPECT_NEAR(s.y * 1e-7, kHome.longitude_deg, 1e-7);
  const MavlinkPlan apm = PlanMavlinkCommand("goto 100 0 20", Autopilot::kArduCopter, false, kHome);
  ASSERT_EQ(apm.steps.size(), 2u);
  EXPECT_EQ(apm.steps[1].frame, 3);  // relative to home
  EXPECT_FLOAT_EQ(apm.steps[1].param[6], 20.f);
  EXPECT_EQ(apm.completion, MavlinkPlan::Completion::kPosition);
}

TEST(MavlinkCommands, MissionModesAndWhatEachCannotDo) {
  const MavlinkPlan px4 = PlanMavlinkCommand("mission", Autopilot::kPx4, false, kHome);
  ASSERT_EQ(px4.steps.size(), 1u);
  EXPECT_EQ(px4.steps[0].command, mav_cmd::kMissionStart);
  const MavlinkPlan apm = PlanMavlinkCommand("mission", Autopilot::kArduCopter, false, kHome);
  ASSERT_EQ(apm.steps.size(), 2u);
  EXPECT_FLOAT_EQ(apm.steps[0].param[1], 3.f);  // Auto
  EXPECT_EQ(apm.steps[1].command, mav_cmd::kMissionStart);
  EXPECT_FLOAT_EQ(PlanMavlinkCommand("hover", Autopilot::kArduPlaneVtol, true, kHome).steps[0].param[1], 19.f);  // QLoiter
  const MavlinkPlan hold = PlanMavlinkCommand("hover", Autopilot::kPx4, false, kHome);
  EXPECT_FLOAT_EQ(hold.steps[0].param[1], 4.f);  // AUTO
  EXPECT_FLOAT_EQ(hold.steps[0].param[2], 3.f);  // LOITER
  EXPECT_FLOAT_EQ(PlanMavlinkCommand("emergency_stop", Autopilot::kArduCopter, false, kHome).steps[0].param[1],
                  kForceDisarmMagic);
  EXPECT_NE(PlanMavlinkCommand("land", Autopilot::kArduPlane, false, kHome).refusal.find("landing sequence"), std::string::npos);
  EXPECT_NE(PlanMavlinkCommand("transition fw", Autopilot::kPx4, false, kHome).refusal.find("not a VTOL"), std::string::npos);
  EXPECT_EQ(PlanMavlinkCommand("transition fw", Autopilot::kPx4, true, kHome).steps[0].param[0], 4.f);
  EXPECT_NE(PlanMavlinkCommand("chirp 1 0.1 1 5 10", Autopilot::kPx4, false, kHome).refusal.find("our own vehicles"),
            std::string::npos);
  EXPECT_FALSE(PlanMavlinkCommand("takeoff 500", Autopilot::kPx4, false, kHome).refusal.empty());  // the grammar's limit
  EXPECT_FALSE(PlanMavlinkCommand("arm", Autopilot::kOther, false, kHome).refusal.empty());
}

}  // namespace
}  // namespace uav::gcs
