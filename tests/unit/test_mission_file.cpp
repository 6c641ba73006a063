// Mission files: round trips keep the mission; every malformed case is rejected with a message
// that names the field or line; nothing is half-loaded or half-written.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "uav/shared/text_file.hpp"
#include "uav/waypoints/mission_file.hpp"
#include "uav/waypoints/stored_paths.hpp"

namespace uav::waypoints {
namespace {

const GeodeticPoint kHome{1.2966, 103.7764, 15.0};

VehicleLimits SpeedLimit(double v) {
  VehicleLimits l;
  l.max_speed_m_s = v;
  return l;
}

Mission SurveyMission(bool by_distance) {
  SurveyParams p;
  p.camera = {4.8, 3.6, 3.6, 640, 480, true};
  p.altitude_m = 20;
  p.grid_angle_deg = 12.5;
  p.entry_corner = 3;
  p.crosshatch = true;
  p.trigger_distance_m = by_distance ? 3.0 : 0.0;
  const std::vector<GeodeticPoint> area{{1.2968, 103.7766, 0}, {1.2968, 103.7776, 0}, {1.2975, 103.7776, 0},
                                        {1.2975, 103.7771, 0}, {1.2980, 103.7771, 0}, {1.2980, 103.7766, 0}};
  return MissionFromSurvey(area, kHome, p, PlanSurvey(area, kHome, p));
}

void ExpectSameSurvey(const SurveyDefinition& a, const SurveyDefinition& b);

void ExpectSameMission(const Mission& a, const Mission& b, bool with_survey) {
  EXPECT_EQ(a.home.latitude_deg, b.home.latitude_deg);
  EXPECT_EQ(a.home.longitude_deg, b.home.longitude_deg);
  EXPECT_EQ(a.home.altitude_m, b.home.altitude_m);
  ASSERT_EQ(a.items.size(), b.items.size());
  for (std::size_t i = 0; i < a.items.size(); ++i) EXPECT_TRUE(a.items[i] == b.items[i]) << "item " << i;
  if (!with_survey) return;
  ASSERT_EQ(a.surveys.size(), b.surveys.size());
  for (std::size_t k = 0; k < a.surveys.size(); ++k) ExpectSameSurvey(a.surveys[k], b.surveys[k]);
}

void ExpectSameSurvey(const SurveyDefinition& a, const SurveyDefinition& b) {
  EXPECT_EQ(a.first_item, b.first_item);
  EXPECT_EQ(a.item_count, b.item_count);
  ASSERT_EQ(a.polygon.size(), b.polygon.size());
  for (std::size_t i = 0; i < a.polygon.size(); ++i) {
    EXPECT_EQ(a.polygon[i].latitude_deg, b.polygon[i].latitude_deg);
    EXPECT_EQ(a.polygon[i].longitude_deg, b.polygon[i].longitude_deg);
  }
  const SurveyParams &p = a.params, &q = b.params;
  EXPECT_EQ(p.altitude_m, q.altitude_m);
  EXPECT_NEAR(p.front_overlap, q.front_overlap, 1e-12);
  EXPECT_NEAR(p.side_overlap, q.side_overlap, 1e-12);
  EXPECT_EQ(p.grid_angle_deg, q.grid_angle_deg);
  EXPECT_EQ(p.entry_corner, q.entry_corner);
  EXPECT_EQ(p.crosshatch, q.crosshatch);
  EXPECT_EQ(p.trigger_distance_m, q.trigger_distance_m);
  EXPECT_EQ(p.capture_rate_hz, q.capture_rate_hz);
  EXPECT_EQ(p.camera.image_width_px, q.camera.image_width_px);
  EXPECT_EQ(p.camera.focal_length_mm, q.camera.focal_length_mm);
}

TEST(MissionFile, SurveyMissionShape) {
  const Mission m = SurveyMission(false);
  EXPECT_EQ(m.items.front().command, mav_cmd::kNavTakeoff);
  EXPECT_EQ(m.items.back().command, mav_cmd::kNavReturnToLaunch);
  int starts = 0, stops = 0;
  for (const auto& it : m.items) starts += it.command == mav_cmd::kImageStartCapture, stops += it.command == mav_cmd::kImageStopCapture;
  EXPECT_GT(starts, 4);
  EXPECT_EQ(starts, stops);
  const auto start = std::find_if(m.items.begin(), m.items.end(), [](const MissionItem& it) { return it.command == mav_cmd::kImageStartCapture; });
  EXPECT_NEAR(start->param[1], 0.2, 1e-12);  // 5 Hz (thesis 6.1)
}

TEST(MissionFile, PlanRoundTripKeepsTheMissionAndTheSurvey) {
  for (bool by_distance : {false, true}) {
    const Mission m = SurveyMission(by_distance);
    const Mission back = ParsePlan(FormatPlan(m), "test.plan");
    ExpectSameMission(m, back, true);
    EXPECT_EQ(FormatPlan(back), FormatPlan(m));
  }
}

TEST(MissionFile, WplRoundTripKeepsTheItems) {
  const Mission m = SurveyMission(true);
  const Mission back = ParseWpl(FormatWpl(m), "test.waypoints");
  ExpectSameMission(m, back, false);
  EXPECT_TRUE(back.surveys.empty());
  EXPECT_EQ(FormatWpl(back), FormatWpl(m));
}

TEST(MissionFile, ReadsAQgcStylePlanWithNullParams) {
  const std::string text = R"({"fileType": "Plan", "groundStation": "QGroundControl", "version": 1,
    "mission": {"cruiseSpeed": 15, "hoverSpeed": 5, "firmwareType": 12, "vehicleType": 2, "version": 2,
      "plannedHomePosition": [47.3977, 8.5456, 488],
      "items": [
        {"type": "SimpleItem", "autoContinue": true, "command": 22, "doJumpId": 1, "frame": 3,
         "params": [0, 0, 0, null, 47.3977, 8.5456, 20]},
        {"type": "SimpleItem", "autoContinue": true, "command": 16, "doJumpId": 2, "frame": 3,
         "params": [0, 0, 0, null, 47.3985, 8.5460, 25]},
        {"type": "SimpleItem", "autoContinue": true, "command": 20, "doJumpId": 3, "frame": 2,
         "params": [0, 0, 0, 0, 0, 0, 0]}]}})";
  const Mission m = ParsePlan(text, "qgc.plan");
  ASSERT_EQ(m.items.size(), 3u);
  EXPECT_TRUE(std::isnan(m.items[1].param[3]));
  EXPECT_EQ(m.items[1].altitude_m, 25);
  EXPECT_EQ(m.cruise_speed_m_s, 5);
}

std::string PlanError(const std::string& text) {
  try {
    ParsePlan(text, "bad.plan");
  } catch (const MissionFileError& e) {
    return e.what();
  }
  return "accepted";
}

std::string WplError(const std::string& text) {
  try {
    ParseWpl(text, "bad.waypoints");
  } catch (const MissionFileError& e) {
    return e.what();
  }
  return "accepted";
}

// Edits one field of a good .plan, to test each malformation on its own.
std::string EditedPlan(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = nlohmann::json::parse(FormatPlan(SurveyMission(false)));
  edit(j);
  return j.dump();
}

struct BadPlan {
  const char* name;
  std::function<void(nlohmann::json&)> edit;
  const char* expected;  // must appear in the message
};

class MalformedPlan : public testing::TestWithParam<BadPlan> {};

TEST_P(MalformedPlan, IsRejectedNamingTheField) {
  const std::string msg = PlanError(EditedPlan(GetParam().edit));
  EXPECT_NE(msg.find(GetParam().expected), std::string::npos) << msg;
  EXPECT_EQ(msg.rfind("bad.plan: ", 0), 0u) << msg;
}

INSTANTIATE_TEST_SUITE_P(
    Cases, MalformedPlan,
    testing::Values(
        BadPlan{"missing_params", [](auto& j) { j["mission"]["items"][0].erase("params"); },
                "mission.items[0]: missing field \"params\""},
        BadPlan{"missing_home", [](auto& j) { j["mission"].erase("plannedHomePosition"); }, "plannedHomePosition"},
        BadPlan{"null_latitude", [](auto& j) { j["mission"]["items"][0]["params"][4] = nullptr; },
                "mission.items[0]: latitude = nan"},
        BadPlan{"latitude_out_of_range", [](auto& j) { j["mission"]["items"][0]["params"][4] = 95.0; },
                "latitude = 95 is outside [-90, 90]"},
        BadPlan{"altitude_out_of_range",
                [](auto& j) { j["mission"]["items"][2]["TransectStyleComplexItem"]["Items"][1]["params"][6] = 500.0; },
                "mission.items[2].TransectStyleComplexItem.Items[1]: altitude = 500"},
        BadPlan{"string_param", [](auto& j) { j["mission"]["items"][1]["params"][1] = "fast"; },
                "mission.items[1].params[1] (param2): is not a number"},
        BadPlan{"unknown_frame", [](auto& j) { j["mission"]["items"][0]["frame"] = 1; }, "frame 1 is not supported"},
        BadPlan{"wrong_file_type", [](auto& j) { j["fileType"] = "Fence"; }, "fileType"},
        BadPlan{"zero_area_polygon",
                [](auto& j) {
                  auto& poly = j["mission"]["items"][2]["polygon"];
                  for (auto& v : poly) v[0] = 1.2970;  // all on one parallel
                },
                "polygon"},
        BadPlan{"self_intersecting_polygon",
                [](auto& j) {
                  auto& poly = j["mission"]["items"][2]["polygon"];
                  std::swap(poly[0], poly[1]);
                },
                "self-intersecting"},
        BadPlan{"too_many_items",
                [](auto& j) {
                  auto& items = j["mission"]["items"];
                  const auto one = items[1];
                  for (int i = 0; i < 5001; ++i) items.push_back(one);
                },
                "more than 5000"},
        BadPlan{"bad_overlap",
                [](auto& j) { j["mission"]["items"][2]["TransectStyleComplexItem"]["CameraCalc"]["SideOverlap"] = 120; },
                "side_overlap"}),
    [](const testing::TestParamInfo<BadPlan>& info) { return std::string(info.param.name); });

TEST(MissionFile, BadJsonNamesTheLine) {
  const std::string msg = PlanError("{\n  \"fileType\": \"Plan\",\n  \"mission\": {\"x\": NaN}\n}");
  EXPECT_NE(msg.find("not valid JSON"), std::string::npos) << msg;
  EXPECT_NE(msg.find("line 3"), std::string::npos) << msg;
}

TEST(MissionFile, MalformedWplIsRejectedNamingTheLine) {
  const std::string good = FormatWpl(SurveyMission(true));
  EXPECT_EQ(WplError(good), "accepted");
  auto replace_line = [&](int line_no, const std::string& text) {
    std::istringstream in(good);
    std::string out, line;
    for (int n = 1; std::getline(in, line); ++n) out += (n == line_no ? text : line) + "\n";
    return out;
  };
  EXPECT_NE(WplError("QGC WPL 100\n").find("bad.waypoints:1: first line must be"), std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "1\t0\t3\t22\t0\t0\t0")).find("bad.waypoints:3: has 7 tab-separated fields"),
            std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "1\t0\t3\t22\t0\t0\t0\tnan\tnan\t103.7764\t20\t1")).find("bad.waypoints:3: field 9 (latitude) is NaN"),
            std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "1\t0\t3\t22\t0\t0\t0\t0\t-91\t103.7764\t20\t1")).find("bad.waypoints:3: item 1 (NAV_TAKEOFF): latitude = -91"),
            std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "1\t0\t3\t22\t0\t0\t0\t0\t1.2966\t103.7764\t121\t1")).find("altitude = 121"),
            std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "7\t0\t3\t22\t0\t0\t0\t0\t1.2966\t103.7764\t20\t1")).find("index 7 out of sequence"),
            std::string::npos);
  EXPECT_NE(WplError(replace_line(3, "1\t0\t3\t22\t0\t0\t0\t0\t1.2966\tabc\t20\t1")).find("field 10 (longitude) \"abc\" is not a number"),
            std::string::npos);
  std::string many = "QGC WPL 110\n0\t1\t0\t16\t0\t0\t0\t0\t1.2966\t103.7764\t15\t1\n";
  for (int i = 1; i <= 5001; ++i) many += std::to_string(i) + "\t0\t3\t16\t0\t0\t0\t0\t1.2966\t103.7764\t20\t1\n";
  EXPECT_NE(WplError(many).find("more than 5000"), std::string::npos);
}

TEST(MissionFile, FailedReadLeavesTheCallersMissionAndFailedWriteLeavesTheFile) {
  const auto dir = std::filesystem::temp_directory_path() / ("uav_mission_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string good_path = (dir / "good.plan").string(), bad_path = (dir / "bad.plan").string();
  const Mission good = SurveyMission(false);
  WriteMissionFile(good_path, good);
  WriteFileAtomically(bad_path, EditedPlan([](auto& j) { j["mission"]["items"][0]["params"][4] = 95.0; }));
  Mission loaded = ReadMissionFile(good_path);
  EXPECT_THROW(loaded = ReadMissionFile(bad_path), MissionFileError);
  ExpectSameMission(loaded, good, true);
  // An invalid mission is never written, and the old file stays whole.
  Mission invalid = good;
  invalid.items[2].latitude_deg = NAN;
  EXPECT_THROW(WriteMissionFile(good_path, invalid), std::invalid_argument);
  ExpectSameMission(ReadMissionFile(good_path), good, true);
  EXPECT_THROW(WriteMissionFile((dir / "missing" / "x.plan").string(), good), std::runtime_error);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 2);  // no temporaries left
  std::filesystem::remove_all(dir);
}

TEST(StoredPaths, ShippedPathsLoadAndCompile) {
  for (int n : {1, 2}) {
    const Mission m = LoadStoredPath(kStoredPathsDir, n);
    LocalNedFrame frame(kHome);
    const auto steps = CompileMission(m, frame, SpeedLimit(3.0));
    EXPECT_GE(steps.size(), 4u) << "track " << n;
  }
  EXPECT_THROW(LoadStoredPath(kStoredPathsDir, 99), MissionFileError);
}

TEST(CompileMission, RejectsWhatTheVehicleCannotFly) {
  Mission m = SurveyMission(false);
  LocalNedFrame frame(kHome);
  EXPECT_NO_THROW(CompileMission(m, frame, SpeedLimit(3.0)));
  try {
    CompileMission(m, frame, SpeedLimit(2.0));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("above the vehicle's 2.0 m/s (ctl_speed_max_xy)"), std::string::npos) << e.what();
  }
  m.items[2].command = 183;  // DO_SET_SERVO
  try {
    CompileMission(m, frame, SpeedLimit(3.0));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("item 2 (command 183): this vehicle cannot fly it"), std::string::npos) << e.what();
  }
}

// Every item type the editor makes, mixed with two surveys: take off, a waypoint with a hold, a
// loiter, a photo, the first survey, a speed change, a waypoint, the second survey, a land.
Mission MixedMission() {
  Mission a = SurveyMission(false), b = SurveyMission(true);
  Mission m;
  m.home = kHome;
  m.cruise_speed_m_s = 3.0;
  const double nan = std::nan("");
  auto item = [&](int command, int frame, std::array<double, 4> param, double lat, double lon, double alt) {
    MissionItem it;
    it.command = command, it.frame = frame, it.param = param;
    it.latitude_deg = lat, it.longitude_deg = lon, it.altitude_m = alt;
    m.items.push_back(it);
  };
  item(mav_cmd::kNavTakeoff, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, kHome.latitude_deg, kHome.longitude_deg, 12);
  item(mav_cmd::kNavWaypoint, mav_frame::kGlobalRelativeAlt, {4, 0, 0, nan}, 1.2967, 103.7765, 12);
  item(mav_cmd::kNavLoiterTime, mav_frame::kGlobalRelativeAlt, {6, 0, 0, nan}, 1.2968, 103.7765, 15);
  item(mav_cmd::kImageStartCapture, mav_frame::kMission, {0, 0, 1, 0}, 0, 0, 0);
  for (const Mission* s : {&a, &b}) {
    SurveyDefinition def = s->surveys.at(0);
    const std::size_t from = def.first_item;
    def.first_item = m.items.size();
    m.items.insert(m.items.end(), s->items.begin() + from, s->items.begin() + from + def.item_count);
    m.surveys.push_back(def);
    if (s == &a) {
      item(mav_cmd::kDoChangeSpeed, mav_frame::kMission, {1, 2.5, -1, 0}, 0, 0, 0);
      item(mav_cmd::kNavWaypoint, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, 1.2970, 103.7770, 25);
    }
  }
  item(mav_cmd::kNavLand, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, 1.2966, 103.7765, 0);
  ValidateMission(m);
  return m;
}

TEST(MissionFile, MixedMissionRoundTripsThroughPlanAndWpl) {
  const Mission m = MixedMission();
  const Mission plan = ParsePlan(FormatPlan(m), "mixed.plan");
  ExpectSameMission(m, plan, true);
  EXPECT_EQ(plan.surveys.size(), 2u);
  EXPECT_EQ(FormatPlan(plan), FormatPlan(m));
  // QGroundControl's shape: simple items around two ComplexItem surveys.
  const auto j = nlohmann::json::parse(FormatPlan(m));
  std::vector<std::string> types;
  for (const auto& it : j["mission"]["items"]) types.push_back(it["type"]);
  ASSERT_EQ(types.size(), 9u);
  EXPECT_EQ(types[4], "ComplexItem");
  EXPECT_EQ(types[7], "ComplexItem");
  EXPECT_EQ(std::count(types.begin(), types.end(), "SimpleItem"), 7);
  const Mission wpl = ParseWpl(FormatWpl(m), "mixed.waypoints");
  ExpectSameMission(m, wpl, false);
  EXPECT_EQ(FormatWpl(wpl), FormatWpl(m));
}

TEST(CompileMission, HoldsLoitersAndTakesOnePhoto) {
  const Mission m = MixedMission();
  LocalNedFrame frame(kHome);
  const auto steps = CompileMission(m, frame, SpeedLimit(3.0));
  using Kind = MissionStep::Kind;
  auto of_item = [&](std::size_t item) {
    std::vector<MissionStep> r;
    for (const auto& s : steps) if (s.item == item && !(s.kind == Kind::kSetSpeed && item == 0 && &s == &steps[0])) r.push_back(s);
    return r;
  };
  const auto wp = of_item(1);
  ASSERT_EQ(wp.size(), 2u);
  EXPECT_EQ(wp[0].kind, Kind::kWaypoint);
  EXPECT_EQ(wp[1].kind, Kind::kHold);
  EXPECT_EQ(wp[1].value, 4.0);
  const auto loiter = of_item(2);
  ASSERT_EQ(loiter.size(), 2u);
  EXPECT_EQ(loiter[0].kind, Kind::kWaypoint);
  EXPECT_NEAR(-loiter[0].p_N.z(), 15.0, 1e-9);
  EXPECT_EQ(loiter[1].kind, Kind::kHold);
  EXPECT_EQ(loiter[1].value, 6.0);
  // One photo: the camera on at one a second for half a second, then off.
  const auto photo = of_item(3);
  ASSERT_EQ(photo.size(), 3u);
  EXPECT_EQ(photo[0].kind, Kind::kCaptureStart);
  EXPECT_EQ(photo[1].kind, Kind::kHold);
  EXPECT_EQ(photo[2].kind, Kind::kCaptureStop);
  EXPECT_LT(photo[1].value, photo[0].value);
  EXPECT_EQ(steps.back().kind, Kind::kLand);
  // A hold time out of range is refused naming the item.
  Mission bad = m;
  bad.items[1].param[0] = -1;
  try {
    CompileMission(bad, frame, SpeedLimit(3.0));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("item 1 (NAV_WAYPOINT): param1 (hold time)"), std::string::npos) << e.what();
  }
}

TEST(ResumeSteps, StartsAtTheInterruptedStepOrItsCaptureLegWithTheSettingsInForce) {
  const Mission m = SurveyMission(false);
  LocalNedFrame frame(kHome);
  const auto steps = CompileMission(m, frame, SpeedLimit(3.0));
  using Kind = MissionStep::Kind;
  // The end point of the third capture leg: the camera is on while the vehicle flies to it.
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (steps[i].kind == Kind::kCaptureStart) starts.push_back(i);
  ASSERT_GE(starts.size(), 3u);
  const std::size_t leg_end = starts[2] + 1, leg_start = starts[2] - 1;
  ASSERT_EQ(steps[leg_end].kind, Kind::kWaypoint);
  ASSERT_EQ(steps[leg_start].kind, Kind::kWaypoint);
  ASSERT_TRUE(CaptureBefore(steps, leg_end).has_value());

  // In the air: the speed in force, then the leg from its first point with the camera off there.
  const auto air = ResumeSteps(steps, leg_end, true);
  ASSERT_GE(air.steps.size(), 2u);
  EXPECT_EQ(air.first, leg_start);
  EXPECT_EQ(air.prefix, 1u);
  EXPECT_EQ(air.steps[0].kind, Kind::kSetSpeed);
  EXPECT_EQ(air.steps[1].item, steps[leg_start].item);
  EXPECT_EQ(air.steps[1].kind, Kind::kWaypoint);
  EXPECT_FALSE(CaptureBefore(air.steps, 2).has_value());
  EXPECT_EQ(air.steps.size(), 1 + steps.size() - leg_start);
  // On the ground (after a return): a take-off to the mission's altitude first.
  const auto ground = ResumeSteps(steps, leg_end, false);
  ASSERT_EQ(ground.steps[0].kind, Kind::kTakeoff);
  EXPECT_NEAR(ground.steps[0].altitude_m, steps[1].altitude_m, 1e-9);
  EXPECT_EQ(ground.steps.size(), air.steps.size() + 1);
  EXPECT_EQ(ground.prefix, 2u);
  // Between legs (flying to a leg's first point) it resumes exactly there, camera off.
  const auto between = ResumeSteps(steps, leg_start, true);
  EXPECT_EQ(between.first, leg_start);
  EXPECT_EQ(between.steps[1].item, steps[leg_start].item);
  EXPECT_THROW(ResumeSteps(steps, steps.size(), true), std::invalid_argument);
}

}  // namespace
}  // namespace uav::waypoints
