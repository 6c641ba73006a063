// Mission files: round trips keep the mission; every malformed case is rejected with a message
// that names the field or line; nothing is half-loaded or half-written.
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

void ExpectSameMission(const Mission& a, const Mission& b, bool with_survey) {
  EXPECT_EQ(a.home.latitude_deg, b.home.latitude_deg);
  EXPECT_EQ(a.home.longitude_deg, b.home.longitude_deg);
  EXPECT_EQ(a.home.altitude_m, b.home.altitude_m);
  ASSERT_EQ(a.items.size(), b.items.size());
  for (std::size_t i = 0; i < a.items.size(); ++i) EXPECT_TRUE(a.items[i] == b.items[i]) << "item " << i;
  if (!with_survey) return;
  ASSERT_TRUE(a.survey && b.survey);
  EXPECT_EQ(a.survey->first_item, b.survey->first_item);
  EXPECT_EQ(a.survey->item_count, b.survey->item_count);
  ASSERT_EQ(a.survey->polygon.size(), b.survey->polygon.size());
  for (std::size_t i = 0; i < a.survey->polygon.size(); ++i) {
    EXPECT_EQ(a.survey->polygon[i].latitude_deg, b.survey->polygon[i].latitude_deg);
    EXPECT_EQ(a.survey->polygon[i].longitude_deg, b.survey->polygon[i].longitude_deg);
  }
  const SurveyParams &p = a.survey->params, &q = b.survey->params;
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
  EXPECT_FALSE(back.survey.has_value());
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
    const auto steps = CompileMission(m, frame, 3.0);
    EXPECT_GE(steps.size(), 4u) << "track " << n;
  }
  EXPECT_THROW(LoadStoredPath(kStoredPathsDir, 99), MissionFileError);
}

TEST(CompileMission, RejectsWhatTheVehicleCannotFly) {
  Mission m = SurveyMission(false);
  LocalNedFrame frame(kHome);
  EXPECT_NO_THROW(CompileMission(m, frame, 3.0));
  try {
    CompileMission(m, frame, 2.0);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("above this vehicle's limit of 2 m/s"), std::string::npos) << e.what();
  }
  m.items[2].command = 183;  // DO_SET_SERVO
  try {
    CompileMission(m, frame, 3.0);
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("item 2 (command 183): this vehicle cannot fly it"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uav::waypoints
