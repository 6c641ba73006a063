// A mission against the vehicle's limits and its own geofence: each problem an operator could
// plan (a waypoint in a keep-out zone, above the ceiling, 111 km away, too fast, a leg through a
// keep-out zone) is found, named by the item as the editor names it, with both numbers.
#include <gtest/gtest.h>

#include "uav/waypoints/geofence.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {
namespace {

const GeodeticPoint kHome{1.2966, 103.7764, 15.0};

// Items at north/east metres from home.
MissionItem At(int command, double north_m, double east_m, double alt_m, double param1 = 0) {
  const GeodeticPoint g = LocalNedFrame(kHome).ToGeodetic(Eigen::Vector3d(north_m, east_m, 0));
  MissionItem it;
  it.command = command;
  it.param = {param1, 0, 0, 0};
  it.latitude_deg = g.latitude_deg, it.longitude_deg = g.longitude_deg, it.altitude_m = alt_m;
  return it;
}

// Take off to 10 m, fly 40 m north, return; a 10 m keep-out square at 15..25 m east of the leg
// and a keep-in circle of 200 m around home.
Mission Base() {
  Mission m;
  m.home = kHome;
  m.items.push_back(At(mav_cmd::kNavTakeoff, 0, 0, 10));
  m.items.push_back(At(mav_cmd::kNavWaypoint, 40, 0, 10));
  MissionItem rtl;
  rtl.command = mav_cmd::kNavReturnToLaunch;
  rtl.frame = mav_frame::kMission;
  m.items.push_back(rtl);
  for (auto [n, e] : {std::pair{15.0, 15.0}, {15.0, 25.0}, {25.0, 25.0}, {25.0, 15.0}})
    m.items.push_back(At(mav_cmd::kNavFencePolygonVertexExclusion, n, e, 0, 4));
  m.items.push_back(At(mav_cmd::kNavFenceCircleInclusion, 0, 0, 0, 200));
  return m;
}

std::string All(const std::vector<MissionProblem>& problems) {
  std::string s;
  for (const auto& p : problems) s += p.text + "\n";
  return s;
}

TEST(CheckMission, AMissionWithinTheLimitsHasNoProblems) {
  EXPECT_EQ(All(CheckMission(Base(), VehicleLimits{})), "");
}

TEST(CheckMission, AWaypointInsideAKeepOutZoneIsNamedByItemAndZone) {
  Mission m = Base();
  m.items[1] = At(mav_cmd::kNavWaypoint, 20, 20, 10);
  const auto problems = CheckMission(m, VehicleLimits{});
  ASSERT_EQ(problems.size(), 1u) << All(problems);
  EXPECT_EQ(problems[0].item, 1u);
  EXPECT_EQ(problems[0].text, "item 1 (NAV_WAYPOINT): inside keep-out polygon 1");
}

TEST(CheckMission, AWaypointOutsideEveryKeepInZone) {
  Mission m = Base();
  m.items[1] = At(mav_cmd::kNavWaypoint, 300, 0, 10);
  const auto problems = CheckMission(m, VehicleLimits{});
  ASSERT_FALSE(problems.empty());
  EXPECT_EQ(problems[0].text, "item 1 (NAV_WAYPOINT): outside every keep-in zone");
}

TEST(CheckMission, TheCeilingWithBothNumbers) {
  Mission m = Base();
  VehicleLimits limits;
  limits.ceiling_m = 8;
  const auto problems = CheckMission(m, limits);
  ASSERT_EQ(problems.size(), 2u) << All(problems);
  EXPECT_EQ(problems[0].text, "item 0 (NAV_TAKEOFF): 10.0 m above home, above the vehicle's 8 m ceiling (fs_fence_alt)");
  EXPECT_EQ(problems[1].item, 1u);
}

TEST(CheckMission, AWaypoint111KmAwayIsBeyondTheRange) {
  Mission m = Base();
  m.items.resize(3);  // no zones
  m.items[1] = At(mav_cmd::kNavWaypoint, 0, 0, 10);
  m.items[1].latitude_deg += 1.0;  // one degree north: ~111 km
  const auto problems = CheckMission(m, VehicleLimits{});
  ASSERT_EQ(problems.size(), 1u) << All(problems);
  EXPECT_EQ(problems[0].text, "item 1 (NAV_WAYPOINT): 110.6 km from home, beyond the vehicle's 500 m range (fs_fence_radius)");
}

TEST(CheckMission, SpeedsAboveTheVehiclesOwn) {
  Mission m = Base();
  m.cruise_speed_m_s = 5;
  MissionItem speed;
  speed.command = mav_cmd::kDoChangeSpeed;
  speed.frame = mav_frame::kMission;
  speed.param = {1, 12, -1, 0};
  m.items.insert(m.items.begin() + 1, speed);
  VehicleLimits limits;
  limits.max_speed_m_s = 3;
  const auto problems = CheckMission(m, limits);
  ASSERT_EQ(problems.size(), 2u) << All(problems);
  EXPECT_EQ(problems[0].item, MissionProblem::kCruise);
  EXPECT_EQ(problems[0].text, "cruise speed: 5.0 m/s is above the vehicle's 3.0 m/s (ctl_speed_max_xy)");
  EXPECT_EQ(problems[1].text, "item 1 (DO_CHANGE_SPEED): 12.0 m/s is above the vehicle's 3.0 m/s (ctl_speed_max_xy)");
  EXPECT_EQ(DescribeProblems(problems), problems[0].text + " (and 1 more problem)");
}

TEST(CheckMission, ALegThroughAKeepOutZoneBetweenAllowedPoints) {
  Mission m = Base();
  m.items[1] = At(mav_cmd::kNavWaypoint, 40, 40, 10);  // beyond the square: home -> here -> home cross it
  const auto problems = CheckMission(m, VehicleLimits{});
  ASSERT_EQ(problems.size(), 2u) << All(problems);
  EXPECT_EQ(problems[0].text, "item 1 (NAV_WAYPOINT): the leg from home crosses keep-out polygon 1");
  EXPECT_EQ(problems[1].text, "item 2 (NAV_RETURN_TO_LAUNCH): the leg from item 1 crosses keep-out polygon 1");
}

TEST(CheckMission, TheReturnLegCounts) {
  Mission m = Base();
  // Around the square by its north side, then straight home through it.
  m.items[1] = At(mav_cmd::kNavWaypoint, 40, 40, 10);
  m.items.insert(m.items.begin() + 1, At(mav_cmd::kNavWaypoint, 40, 0, 10));
  const auto problems = CheckMission(m, VehicleLimits{});
  ASSERT_EQ(problems.size(), 1u) << All(problems);
  EXPECT_EQ(problems[0].text, "item 3 (NAV_RETURN_TO_LAUNCH): the leg from item 2 crosses keep-out polygon 1");
}

TEST(CheckMission, FenceItemsAreNamedAsTheEditorNamesThem) {
  Mission m = Base();
  EXPECT_EQ(ItemLabel(m, 3), "keep-out polygon 1 (item 3)");
  EXPECT_EQ(ItemLabel(m, 6), "keep-out polygon 1 (item 6)");
  EXPECT_EQ(ItemLabel(m, 7), "keep-in circle 1 (item 7)");
  m.items[7].param[0] = -5;
  try {
    ValidateMission(m);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("keep-in circle 1 (item 7): param1 (radius)"), std::string::npos) << e.what();
  }
}

TEST(CheckMission, CompileRefusesWithTheFirstProblem) {
  Mission m = Base();
  m.items[1] = At(mav_cmd::kNavWaypoint, 20, 20, 10);
  try {
    CompileMission(m, LocalNedFrame(kHome), VehicleLimits{});
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "item 1 (NAV_WAYPOINT): inside keep-out polygon 1");
  }
}

TEST(VehicleLimits, FromTheVehiclesParameters) {
  auto quad = VehicleLimits::Of([](const std::string& n) {
    if (n == "fs_fence_alt") return 60.0;
    if (n == "ctl_speed_max_xy") return 4.0;
    return std::nan("");
  });
  EXPECT_EQ(quad.ceiling_m, 60.0);
  EXPECT_EQ(quad.max_speed_m_s, 4.0);
  EXPECT_EQ(quad.range_m, 500.0);  // the schema's default
  auto wing = VehicleLimits::Of([](const std::string& n) {
    if (n == "vehicle_type") return 1.0;
    if (n == "ts_cruise_speed") return 12.0;
    return std::nan("");
  });
  EXPECT_EQ(wing.max_speed_m_s, 12.0);
}

}  // namespace
}  // namespace uav::waypoints
