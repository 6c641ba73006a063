// The mission editor: a mix of every item type and a survey builds a valid mission, survives the
// .plan and WPL round trips item for item, and what it cannot show is refused by name with
// nothing changed.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "uav/gcs/mission_editor.hpp"
#include "uav/gcs/survey_planner.hpp"
#include "uav/waypoints/geofence.hpp"
#include "uav/waypoints/mission_file.hpp"

namespace uav::gcs {
namespace {

constexpr GeodeticPoint kHome{1.2966, 103.7764, 15.0};

PlanItem At(PlanAction a, const SurveyPlanner& planner, double n, double e, double alt) {
  PlanItem p;
  p.action = a;
  const GeodeticPoint g = planner.FromMap({n, e});
  p.latitude_deg = g.latitude_deg, p.longitude_deg = g.longitude_deg, p.altitude_m = alt;
  return p;
}

// Waypoint (held 3 s), loiter (5 s), photo, the survey, a waypoint at 2 m/s, land.
void MixedEdit(MissionEditor* editor, SurveyPlanner* planner) {
  for (const auto& v : {Eigen::Vector2d(10, 5), Eigen::Vector2d(40, 5), Eigen::Vector2d(40, 30), Eigen::Vector2d(10, 30)})
    planner->AddVertex(v);
  planner->params().altitude_m = 12;
  planner->ParamsChanged();
  ASSERT_TRUE(planner->problem().empty()) << planner->problem();
  editor->takeoff_alt_m = 8;
  PlanItem wp = At(PlanAction::kWaypoint, *planner, 5, -5, 8);
  wp.hold_s = 3;
  editor->Insert(0, wp);
  PlanItem loiter = At(PlanAction::kLoiter, *planner, 5, 5, 10);
  loiter.hold_s = 5;
  editor->Insert(1, loiter);
  PlanItem photo;
  photo.action = PlanAction::kPhoto;
  editor->Insert(2, photo);
  PlanItem survey;
  survey.action = PlanAction::kSurvey;
  editor->Insert(3, survey);
  PlanItem fast = At(PlanAction::kWaypoint, *planner, 45, 0, 15);
  fast.speed_m_s = 2;
  editor->Insert(4, fast);
  editor->Insert(5, At(PlanAction::kLand, *planner, 2, 2, 0));
}

void ExpectSameItems(const MissionEditor& a, const MissionEditor& b) {
  ASSERT_EQ(a.items().size(), b.items().size());
  for (std::size_t i = 0; i < a.items().size(); ++i) {
    const PlanItem &p = a.items()[i], &q = b.items()[i];
    EXPECT_EQ(p.action, q.action) << i;
    EXPECT_NEAR(p.speed_m_s, q.speed_m_s, 1e-12) << i;
    if (!p.HasPosition()) continue;
    EXPECT_NEAR(p.latitude_deg, q.latitude_deg, 1e-12) << i;
    EXPECT_NEAR(p.longitude_deg, q.longitude_deg, 1e-12) << i;
    if (p.action != PlanAction::kLand) {
      EXPECT_NEAR(p.altitude_m, q.altitude_m, 1e-12) << i;
    }
    EXPECT_NEAR(p.hold_s, q.hold_s, 1e-12) << i;
  }
}

TEST(MissionEditor, MixedMissionRoundTripsThroughPlanAndWpl) {
  SurveyPlanner planner(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor;
  ASSERT_NO_FATAL_FAILURE(MixedEdit(&editor, &planner));
  std::string error;
  const auto m = editor.MakeMission(planner, kHome, &error);
  ASSERT_TRUE(m) << error;
  ASSERT_EQ(m->surveys.size(), 1u);
  EXPECT_EQ(m->items.front().command, waypoints::mav_cmd::kNavTakeoff);
  EXPECT_EQ(m->items.front().altitude_m, 8);
  EXPECT_EQ(m->items.back().command, waypoints::mav_cmd::kNavLand);
  EXPECT_GT(m->items.size(), 10u);

  // .plan: the survey comes back as the survey item, the planner gets its polygon.
  SurveyPlanner planner2(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor2;
  ASSERT_TRUE(editor2.Load(waypoints::ParsePlan(waypoints::FormatPlan(*m), "mixed.plan"), &planner2, &error)) << error;
  ExpectSameItems(editor, editor2);
  EXPECT_EQ(planner2.polygon().size(), 4u);
  EXPECT_EQ(editor2.takeoff_alt_m, 8);
  const auto m2 = editor2.MakeMission(planner2, kHome, &error);
  ASSERT_TRUE(m2) << error;
  EXPECT_EQ(waypoints::FormatPlan(*m2), waypoints::FormatPlan(*m));

  // WPL keeps no survey: its lines come back as waypoints with the camera switched on and off,
  // and the mission built from them is the same item for item.
  SurveyPlanner planner3(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor3;
  ASSERT_TRUE(editor3.Load(waypoints::ParseWpl(waypoints::FormatWpl(*m), "mixed.waypoints"), &planner3, &error)) << error;
  int camera_on = 0;
  for (const auto& it : editor3.items()) camera_on += it.action == PlanAction::kCameraStart;
  EXPECT_GT(camera_on, 1);
  const auto m3 = editor3.MakeMission(planner3, kHome, &error);
  ASSERT_TRUE(m3) << error;
  EXPECT_EQ(waypoints::FormatWpl(*m3), waypoints::FormatWpl(*m));
}

TEST(MissionEditor, WithoutItemsTheSurveyIsTheMissionAndLoadsBackAsTheSurvey) {
  SurveyPlanner planner(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor;
  std::string error;
  EXPECT_FALSE(editor.MakeMission(planner, kHome, &error));  // nothing planned
  for (const auto& v : {Eigen::Vector2d(10, 5), Eigen::Vector2d(40, 5), Eigen::Vector2d(40, 30)}) planner.AddVertex(v);
  const auto m = editor.MakeMission(planner, kHome, &error);
  ASSERT_TRUE(m) << error;
  std::string direct_error;
  EXPECT_EQ(waypoints::FormatPlan(*m), waypoints::FormatPlan(*planner.MakeMission(&direct_error)));
  ASSERT_TRUE(editor.Load(*m, &planner, &error)) << error;
  EXPECT_TRUE(editor.items().empty());  // still edited as a survey
  // The same through a .plan (as the vehicle offers it back).
  ASSERT_TRUE(editor.Load(waypoints::ParsePlan(waypoints::FormatPlan(*m), "survey.plan"), &planner, &error)) << error;
  EXPECT_TRUE(editor.items().empty());
}

TEST(MissionEditor, RefusesWhatItCannotShowAndKeepsItsItems) {
  SurveyPlanner planner(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor;
  ASSERT_NO_FATAL_FAILURE(MixedEdit(&editor, &planner));
  std::string error;
  auto m = editor.MakeMission(planner, kHome, &error);
  ASSERT_TRUE(m) << error;
  waypoints::Mission bad = *m;
  bad.items[2].command = 183;  // DO_SET_SERVO
  bad.items[2].frame = waypoints::mav_frame::kMission;
  EXPECT_FALSE(editor.Load(bad, &planner, &error));
  EXPECT_NE(error.find("item 2 (command 183)"), std::string::npos) << error;
  EXPECT_EQ(editor.items().size(), 6u);
  // A survey item without a flyable survey names the item.
  planner.Clear();
  EXPECT_FALSE(editor.MakeMission(planner, kHome, &error));
  EXPECT_NE(error.find("item 4 (survey)"), std::string::npos) << error;
  // Editing: delete, insert, drag.
  editor.Delete(3);
  EXPECT_EQ(editor.items().size(), 5u);
  const GeodeticPoint g = planner.FromMap({20, 20});
  editor.MoveTo(0, g);
  EXPECT_EQ(editor.ItemNear(planner, {20, 20}, 1.0), 0);
  ASSERT_TRUE(editor.MakeMission(planner, kHome, &error)) << error;
}

TEST(MissionEditor, GeofenceAndRallyPointsRoundTripAsQGroundControlWritesThem) {
  SurveyPlanner planner(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor;
  editor.Insert(0, At(PlanAction::kWaypoint, planner, 20, 0, 10));
  FenceDraft keep_in;
  for (const auto& v : {Eigen::Vector2d(-50, -50), Eigen::Vector2d(60, -50), Eigen::Vector2d(60, 50), Eigen::Vector2d(-50, 50)})
    keep_in.vertices.push_back(planner.FromMap(v));
  FenceDraft keep_out;
  keep_out.inclusion = false;
  keep_out.circle = true;
  keep_out.vertices.push_back(planner.FromMap({30, 30}));
  keep_out.radius_m = 8;
  editor.fences = {keep_out, keep_in};  // drawn circle first: written polygons first, as the .plan
  GeodeticPoint rally = planner.FromMap({-20, 10});
  rally.altitude_m = 12;
  editor.rally.push_back(rally);
  std::string error;
  const auto m = editor.MakeMission(planner, kHome, &error);
  ASSERT_TRUE(m) << error;
  const std::string plan = waypoints::FormatPlan(*m);
  const auto j = nlohmann::json::parse(plan);
  ASSERT_EQ(j["geoFence"]["polygons"].size(), 1u);
  EXPECT_EQ(j["geoFence"]["polygons"][0]["inclusion"], true);
  EXPECT_EQ(j["geoFence"]["polygons"][0]["polygon"].size(), 4u);
  ASSERT_EQ(j["geoFence"]["circles"].size(), 1u);
  EXPECT_EQ(j["geoFence"]["circles"][0]["inclusion"], false);
  EXPECT_EQ(j["geoFence"]["circles"][0]["circle"]["radius"], 8);
  ASSERT_EQ(j["rallyPoints"]["points"].size(), 1u);
  EXPECT_EQ(j["rallyPoints"]["points"][0][2], 12);
  EXPECT_EQ(j["mission"]["items"].size(), 2u);  // take-off and the waypoint: the fence is apart
  // Back into an editor: the same zones and rally point; the same file again.
  SurveyPlanner planner2(UAV_RESOURCE_DIR "/cameras", kHome);
  MissionEditor editor2;
  ASSERT_TRUE(editor2.Load(waypoints::ParsePlan(plan, "fenced.plan"), &planner2, &error)) << error;
  ASSERT_EQ(editor2.fences.size(), 2u);
  EXPECT_TRUE(editor2.fences[0].inclusion && !editor2.fences[0].circle);
  EXPECT_TRUE(!editor2.fences[1].inclusion && editor2.fences[1].circle);
  EXPECT_EQ(editor2.fences[1].radius_m, 8);
  ASSERT_EQ(editor2.rally.size(), 1u);
  EXPECT_NEAR(editor2.rally[0].altitude_m, 12, 1e-12);
  EXPECT_EQ(waypoints::FormatPlan(*editor2.MakeMission(planner2, kHome, &error)), plan);
  // The vehicle's view: the waypoint is allowed, the circle is not, the rally point is there.
  const auto fence = waypoints::CompileGeofence(*m, LocalNedFrame(kHome));
  EXPECT_EQ(fence.Breach({20, 0}), "");
  EXPECT_EQ(fence.Breach({30, 32}), "inside keep-out circle 1");
  EXPECT_EQ(fence.Breach({100, 0}), "outside every keep-in zone");
  ASSERT_NE(fence.NearestRally({0, 0}), nullptr);
  EXPECT_NEAR(fence.NearestRally({0, 0})->x(), -20, 1e-6);
  // A polygon of two vertices cannot be uploaded, and says which zone.
  editor.fences[1].vertices.resize(2);
  EXPECT_FALSE(editor.MakeMission(planner, kHome, &error));
  EXPECT_NE(error.find("keep-in polygon 1: a polygon needs at least 3 vertices"), std::string::npos) << error;
}

}  // namespace
}  // namespace uav::gcs
