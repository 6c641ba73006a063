// GcsLink over an in-process bus (memq://): every message path in both directions, decoded once
// into the model's typed state; and LogReplay of recorded event logs, whole, damaged and truncated.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <lcm/lcm-cpp.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/wire/messages.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/log_replay.hpp"
#include "uav/gcs/script.hpp"
#include "uav/wire/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/sha256.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/mono_depth_t.hpp"
#include "uavmsg/obstacles_t.hpp"
#include "uavmsg/point_cloud_t.hpp"
#include "uavmsg/power_lines_t.hpp"
#include "uavmsg/sensing_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"
#include "unit/gcs_test_util.hpp"
#include "unit/report_examples.hpp"
#include "uav/wire/reports.hpp"

namespace uav::gcs {
namespace {

uavmsg::vehicle_state_t StateMsg(int64_t seq, double t, double alt) {
  uavmsg::vehicle_state_t m{};
  m.utime = static_cast<int64_t>(t * 1e6);
  m.header = {"UAV1", seq};
  m.z = -alt;
  m.x = 3.0;
  m.psi = 0.5;
  m.task = uavmsg::vehicle_state_t::TASK_HOVER;
  m.flight_mode = uavmsg::vehicle_state_t::MODE_AUTO;
  m.attitude_mode = uavmsg::vehicle_state_t::ATTITUDE_GYRO_CRUISE;
  m.failsafe = uavmsg::vehicle_state_t::FAILSAFE_RETURN;
  m.home_latitude_deg = 1.3;
  m.home_longitude_deg = 103.8;
  m.home_altitude_m = 15;
  m.armed = true;
  m.battery_remaining = 0.75f;
  return m;
}

uavmsg::map_tile_t TileMsg(int64_t seq, int tx) {
  uavmsg::map_tile_t m{};
  m.utime = seq;
  m.header = {"UAV1", seq};
  m.map_id = 1;
  m.tile_x = tx;
  m.tile_px = 64;
  m.gsd_m = 0.05;
  m.georeferenced = true;
  m.jpeg = Jpeg(64, 64);
  m.size = static_cast<int32_t>(m.jpeg.size());
  return m;
}

class LinkTest : public ::testing::Test {
 protected:
  Bus bus_{"memq://"};
  GcsModel model_{"gcs", 100};
  GcsLink link_{&bus_, model_, std::nullopt};  // unsigned; signing: test_signing.cpp
  double now_ = 10.0;
  void Poll() { link_.Poll(0, now_ += 0.02); }
};

TEST_F(LinkTest, VehicleMessagesReachTheModelTyped) {
  uavmsg::heartbeat_t hb{};
  hb.header = {"UAV1", 1};
  hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
  hb.task = uavmsg::vehicle_state_t::TASK_MISSION;
  hb.armed = true;
  bus_.Publish("UAV1/HEARTBEAT", hb);
  bus_.Publish("UAV1/STATE", StateMsg(1, 5.0, 12.5));
  uavmsg::status_text_t st{};
  st.header = {"UAV1", 1};
  st.severity = uavmsg::status_text_t::SEVERITY_WARNING;
  st.text = "battery low";
  bus_.Publish("UAV1/STATUS_TEXT", st);
  uavmsg::video_frame_t vf{};
  vf.header = {"UAV1", 1};
  vf.utime = 7;
  vf.camera = "down";
  vf.width = 32, vf.height = 24, vf.source_width = 640, vf.source_height = 480;
  vf.jpeg = Jpeg(32, 24);
  vf.size = static_cast<int32_t>(vf.jpeg.size());
  bus_.Publish("UAV1/VIDEO", vf);
  bus_.Publish("UAV1/MAP_TILE", TileMsg(1, 3));
  uavmsg::track_status_t ts{};
  ts.header = {"UAV1", 1};
  ts.utime = 5000000;
  ts.state = 1;
  ts.center_x = 0.25, ts.center_y = 0.5, ts.width = 0.1, ts.height = 0.1;
  bus_.Publish("UAV1/TRACK_STATUS", ts);
  const std::string contents = "map bytes";
  uavmsg::file_offer_t fo{};
  fo.header = {"UAV1", 1};
  fo.transfer_id = 9;
  fo.name = "map.tif";
  fo.size = static_cast<int64_t>(contents.size());
  fo.chunk_bytes = 4096;
  fo.chunks = 1;
  fo.sha256 = Sha256::HexOf(contents.data(), contents.size());
  bus_.Publish("UAV1/FILE_OFFER", fo);
  Poll();

  ASSERT_EQ(model_.vehicles().count("UAV1"), 1u);
  const VehicleModel& v = model_.vehicles().at("UAV1");
  ASSERT_TRUE(v.state);
  EXPECT_DOUBLE_EQ(v.state->altitude(), 12.5);
  EXPECT_EQ(v.state->task, Task::kHover);
  EXPECT_EQ(v.state->attitude_mode, AttitudeMode::kGyroCruise);
  EXPECT_EQ(v.state->failsafe, FailsafeAction::kReturn);
  EXPECT_EQ(v.task, Task::kHover);  // the state is newer than the heartbeat
  ASSERT_TRUE(v.heartbeat);
  EXPECT_EQ(v.heartbeat->task, Task::kMission);
  ASSERT_TRUE(v.home);
  EXPECT_DOUBLE_EQ(v.home->latitude_deg, 1.3);
  EXPECT_DOUBLE_EQ(*v.Latest(Sig("STATE.alt")), 12.5);
  EXPECT_DOUBLE_EQ(*v.Latest(Sig("STATE.battery_remaining")), 0.75);
  EXPECT_EQ(v.video.frames, 1);
  EXPECT_EQ(v.video.width, 32);
  EXPECT_EQ(v.live_map.tiles.size(), 1u);
  ASSERT_TRUE(v.track);
  EXPECT_DOUBLE_EQ(v.track->center_x, 0.25);
  EXPECT_EQ(v.files.offers().size(), 1u);
  EXPECT_EQ(model_.log().lines().back().severity, Severity::kInfo);  // the offer, after the warning
  bool warned = false;
  for (const auto& l : model_.log().lines()) warned |= l.text == "battery low" && l.severity == Severity::kWarning;
  EXPECT_TRUE(warned);
  EXPECT_EQ(link_.dropped_messages(), 0);
}

TEST_F(LinkTest, CommandsGoOutAndAcknowledgementsComeBack) {
  bus_.Publish("UAV1/STATE", StateMsg(1, 1.0, 0.0));
  Poll();
  std::vector<uavmsg::command_t> sent;
  bus_.Subscribe<uavmsg::command_t>("UAV1/COMMAND", [&](const std::string&, const uavmsg::command_t& m) { sent.push_back(m); });
  ASSERT_TRUE(model_.SubmitCommand("takeoff 10", now_));
  Poll();
  bus_.Handle(0);
  ASSERT_EQ(sent.size(), 1u);
  EXPECT_EQ(sent[0].text, "takeoff 10");
  EXPECT_EQ(sent[0].source, "gcs");
  uavmsg::command_ack_t ack{};
  ack.header = {"UAV1", 1};
  ack.source = "gcs";
  ack.command_seq = sent[0].command_seq;
  ack.command = "takeoff";
  ack.result = uavmsg::command_ack_t::RESULT_IN_PROGRESS;
  ack.progress_percent = 40;
  bus_.Publish("UAV1/COMMAND_ACK", ack);
  Poll();
  ASSERT_TRUE(model_.commands().sent().back().last_ack);
  EXPECT_EQ(model_.commands().sent().back().last_ack->result, CommandResult::kInProgress);
  EXPECT_EQ(model_.commands().sent().back().last_ack->percent, 40);
  ack.result = 17;  // no such result: refused, counted, the last good answer stays
  bus_.Publish("UAV1/COMMAND_ACK", ack);
  Poll();
  EXPECT_EQ(link_.dropped_messages(), 1);
  EXPECT_NE(link_.last_drop_reason().find("unknown command result"), std::string::npos);
  EXPECT_EQ(model_.commands().sent().back().last_ack->result, CommandResult::kInProgress);
}

TEST_F(LinkTest, HeartbeatTargetAndFileRequestGoOut) {
  bus_.Publish("UAV1/STATE", StateMsg(1, 1.0, 0.0));
  Poll();
  int heartbeats = 0;
  std::vector<uavmsg::track_target_t> targets;
  std::vector<uavmsg::file_request_t> requests;
  bus_.Subscribe<uavmsg::heartbeat_t>("UAV1/GCS_HEARTBEAT", [&](const std::string&, const uavmsg::heartbeat_t& m) {
    heartbeats += m.source_kind == uavmsg::heartbeat_t::SOURCE_GCS && m.source_name == "gcs";
  });
  bus_.Subscribe<uavmsg::track_target_t>("UAV1/TRACK_TARGET", [&](const std::string&, const uavmsg::track_target_t& m) { targets.push_back(m); });
  bus_.Subscribe<uavmsg::file_request_t>("UAV1/FILE_REQUEST", [&](const std::string&, const uavmsg::file_request_t& m) { requests.push_back(m); });
  TrackTarget t;
  t.x = 0.1, t.y = 0.2, t.width = 0.3, t.height = 0.2;
  t.corners = {{{0.1, 0.2}, {0.4, 0.2}, {0.4, 0.4}, {0.1, 0.4}}};
  ASSERT_TRUE(model_.SelectTarget(t, now_));
  uavmsg::file_offer_t fo{};
  fo.header = {"UAV1", 1};
  fo.transfer_id = 4;
  fo.name = "a.png";
  fo.size = 10;
  fo.chunk_bytes = 4096;
  fo.chunks = 1;
  fo.sha256 = Sha256::HexOf("0123456789", 10);
  bus_.Publish("UAV1/FILE_OFFER", fo);
  Poll();
  const auto dir = std::filesystem::temp_directory_path() / "uav_test_gcs_link_dl";
  ASSERT_TRUE(model_.StartDownload(dir.string(), now_));
  model_.Tick(now_);
  now_ += GcsLink::kHeartbeatPeriod;
  Poll();
  bus_.Handle(0);
  EXPECT_GE(heartbeats, 1);
  ASSERT_EQ(targets.size(), 1u);
  EXPECT_DOUBLE_EQ(targets[0].width, 0.3);
  EXPECT_EQ(targets[0].method, int8_t{uavmsg::track_target_t::METHOD_DRAG});
  ASSERT_FALSE(requests.empty());
  EXPECT_EQ(requests[0].transfer_id, 4);
  // The chunk comes back: the file is saved once its SHA-256 matched.
  uavmsg::file_chunk_t ch{};
  ch.header = {"UAV1", 2};
  ch.transfer_id = 4;
  ch.index = 0;
  const std::string data = "0123456789";
  ch.data.assign(data.begin(), data.end());
  ch.size = 10;
  ch.crc32 = static_cast<int32_t>(Crc32(data.data(), data.size()));
  bus_.Publish("UAV1/FILE_CHUNK", ch);
  Poll();
  model_.Tick(now_);
  EXPECT_TRUE(std::filesystem::exists(dir / "a.png"));
  std::filesystem::remove_all(dir);
}

TEST_F(LinkTest, MissionUploadGoesOutAndItsAcknowledgementComesBack) {
  bus_.Publish("UAV1/STATE", StateMsg(1, 1.0, 0.0));
  Poll();
  SurveyPlanner& planner = model_.missions().planner();
  planner.AddVertex({0, 0});
  planner.AddVertex({60, 0});
  planner.AddVertex({60, 60});
  planner.AddVertex({0, 60});
  ASSERT_TRUE(model_.UploadMission(now_)) << model_.missions().error();
  std::vector<uavmsg::mission_upload_t> chunks;
  bus_.Subscribe<uavmsg::mission_upload_t>("UAV1/MISSION_UPLOAD", [&](const std::string&, const uavmsg::mission_upload_t& m) { chunks.push_back(m); });
  waypoints::MissionAssembler assembler;
  for (int i = 0; i < 50 && !model_.vehicles().at("UAV1").mission; ++i) {
    model_.Tick(now_);
    Poll();
    bus_.Handle(0);
    for (const auto& c : std::exchange(chunks, {})) {
      auto ack = assembler.Receive(waypoints::FromMessage(c), [](const waypoints::Mission&) { return std::string(); });
      uavmsg::mission_ack_t m = waypoints::ToMessage(ack);
      m.header = {"UAV1", i + 1};
      m.source = "gcs";
      bus_.Publish("UAV1/MISSION_ACK", m);
    }
  }
  ASSERT_TRUE(model_.vehicles().at("UAV1").mission);
  EXPECT_GT(model_.vehicles().at("UAV1").mission->items.size(), 5u);
}

uavmsg::power_lines_t WiresMsg(int64_t seq, double nearest_m) {
  PowerLines p;
  p.utime = seq;
  p.camera = "stereo_left";
  p.nearest_m = nearest_m;
  PowerLine ranged;
  ranged.image_uv = {{0.1, 0.8}, {0.5, 0.5}, {0.9, 0.2}};
  ranged.p_N = {{20, -5, -9}, {20, 0, -8.5}, {20, 5, -9}};
  ranged.range_m = nearest_m;
  ranged.range_sigma_m = 0.4;
  PowerLine unranged;
  unranged.image_uv = {{0.0, 0.3}, {1.0, 0.35}};
  p.wires = {ranged, unranged};
  uavmsg::power_lines_t m = ToMessage(p);
  m.header = {"UAV1", seq};
  return m;
}

// Power lines decode into the model; a wire nearer than the warning distance raises the warning
// once, it clears beyond the margin, and stale reports clear it too, saying so.
TEST_F(LinkTest, PowerLinesWarnWhenAWireComesNearAndClearWithAMargin) {
  model_.wires().params().warn_distance_m = 15.0;
  auto publish = [&](int64_t seq, double nearest) {
    bus_.Publish("UAV1/POWER_LINES", WiresMsg(seq, nearest));
    Poll();
  };
  auto warnings = [&] {
    int n = 0;
    for (const auto& l : model_.log().lines()) n += l.text.find("power line ") == 0 && l.severity == Severity::kWarning;
    return n;
  };
  publish(1, 20.0);
  const VehicleModel& v = model_.vehicles().at("UAV1");
  const std::optional<PowerLines>& lines = v.reports.Get<PowerLines>().newest;
  ASSERT_TRUE(lines);
  ASSERT_EQ(lines->wires.size(), 2u);
  EXPECT_TRUE(lines->wires[0].ranged());
  EXPECT_FALSE(lines->wires[1].ranged());
  EXPECT_NEAR(lines->wires[0].p_N[1].z(), -8.5, 1e-5);
  EXPECT_NEAR(lines->wires[0].image_uv[2].x(), 0.9, 1e-6);
  EXPECT_EQ(lines->camera, "stereo_left");
  EXPECT_FALSE(v.wire_warning);
  EXPECT_EQ(v.wire_map.size(), 1u);  // the ranged wire kept for the map
  publish(2, 12.0);
  EXPECT_TRUE(v.wire_warning);
  publish(3, 11.0);
  publish(4, 16.0);  // inside the clearing margin (15 m x 1.2): still warning, no new message
  EXPECT_TRUE(v.wire_warning);
  EXPECT_EQ(warnings(), 1);
  publish(5, 19.0);
  EXPECT_FALSE(v.wire_warning);
  EXPECT_EQ(model_.log().lines().back().text, "power lines clear: nearest 19.0 m");
  publish(6, 9.0);
  EXPECT_EQ(warnings(), 2);
  model_.Tick(now_ + 3.0);  // no report for 3 s
  EXPECT_FALSE(v.wire_warning);
  EXPECT_NE(model_.log().lines().back().text.find("reports stopped"), std::string::npos);
  EXPECT_EQ(link_.dropped_messages(), 0);
}

TEST_F(LinkTest, MalformedPowerLinesAreDroppedWithTheReason) {
  auto nan_point = WiresMsg(1, 10.0);
  nan_point.wires[0].down_m[1] = NAN;
  bus_.Publish("UAV1/POWER_LINES", nan_point);
  Poll();
  EXPECT_EQ(link_.dropped_messages(), 1);
  EXPECT_NE(link_.last_drop_reason().find("wire 0: point 1 is not finite"), std::string::npos) << link_.last_drop_reason();
  auto range_without_points = WiresMsg(3, 10.0);
  range_without_points.wires[1].range_m = 4.0;
  bus_.Publish("UAV1/POWER_LINES", range_without_points);
  Poll();
  EXPECT_EQ(link_.dropped_messages(), 2);
  EXPECT_NE(link_.last_drop_reason().find("a range needs points"), std::string::npos);
  EXPECT_TRUE(model_.vehicles().empty() || !model_.vehicles().at("UAV1").reports.Get<PowerLines>().newest);
}

uavmsg::obstacles_t ObstaclesMsg(int64_t seq, bool healthy) {
  Obstacles o;
  o.utime = seq;
  o.camera = "stereo_left";
  o.healthy = healthy;
  o.reason = healthy ? "" : "stereo: empty image";
  o.range_gate_m = 6.8;
  if (healthy) {
    Obstacle b;
    b.p_NE = {6.0, -1.5};
    b.top_down_m = -1.8;
    b.bottom_down_m = 0.0;
    b.radius_m = 0.25;
    b.safety_radius_m = 0.75;
    b.range_m = 3.1;
    b.cov_NE << 0.02, 0.001, 0.001, 0.0004;
    b.image_box = {0.1, 0.3, 0.3, 0.9};
    o.obstacles = {b};
    o.nearest_m = 3.1;
  }
  uavmsg::obstacles_t m = ToMessage(o);
  m.header = {"UAV1", seq};
  return m;
}

// Obstacles and the point cloud decode into the model; an unhealthy stereo channel is said once,
// its recovery too; reports older than the staleness are not offered to the panels; malformed
// ones are dropped naming the field.
TEST_F(LinkTest, ObstaclesAndPointCloudReachTheModelAndStaleOnesAreNotDrawn) {
  bus_.Publish("UAV1/OBSTACLES", ObstaclesMsg(1, true));
  PointCloud cloud;
  cloud.utime = 1;
  cloud.origin_N = {3, 0, -1.5};
  cloud.p_N = {{6.0f, -1.5f, -1.0f}, {6.1f, -1.4f, -0.5f}, {200.0f, 0.0f, 0.0f}};
  uavmsg::point_cloud_t cm = ToMessage(cloud);
  cm.header = {"UAV1", 2};
  bus_.Publish("UAV1/POINT_CLOUD", cm);
  Poll();
  const VehicleModel& v = model_.vehicles().at("UAV1");
  const Obstacles* o = v.reports.Fresh<Obstacles>(now_, model_.obstacles().params().stale_after_s);
  ASSERT_NE(o, nullptr);
  ASSERT_EQ(o->obstacles.size(), 1u);
  EXPECT_NEAR(o->obstacles[0].p_NE.y(), -1.5, 1e-6);
  EXPECT_NEAR(o->obstacles[0].cov_NE(0, 1), 0.001, 1e-7);
  EXPECT_NEAR(o->obstacles[0].image_box[3], 0.9, 1e-6);
  const PointCloud* c = v.reports.Fresh<PointCloud>(now_, model_.obstacles().params().cloud_stale_after_s);
  ASSERT_NE(c, nullptr);
  ASSERT_EQ(c->p_N.size(), 3u);
  EXPECT_NEAR(c->p_N[1].z(), -0.5, 0.006);  // centimetre resolution
  EXPECT_NEAR(c->p_N[2].x(), 200.0, 0.006);
  EXPECT_EQ(v.reports.Fresh<Obstacles>(now_ + 3.0, model_.obstacles().params().stale_after_s), nullptr);
  bus_.Publish("UAV1/OBSTACLES", ObstaclesMsg(3, false));
  bus_.Publish("UAV1/OBSTACLES", ObstaclesMsg(4, false));
  Poll();
  EXPECT_TRUE(v.stereo_unhealthy);
  EXPECT_TRUE(v.reports.Fresh<Obstacles>(now_, model_.obstacles().params().stale_after_s)->obstacles.empty());
  int said = 0;
  for (const auto& l : model_.log().lines()) said += l.text == "stereo obstacles unavailable: stereo: empty image";
  EXPECT_EQ(said, 1);
  bus_.Publish("UAV1/OBSTACLES", ObstaclesMsg(5, true));
  Poll();
  EXPECT_FALSE(v.stereo_unhealthy);
  EXPECT_EQ(model_.log().lines().back().text, "stereo obstacles available again");
  // Malformed: a non-finite radius, an unhealthy report with obstacles, a cloud count mismatch.
  auto bad = ObstaclesMsg(6, true);
  bad.obstacles[0].radius_m = NAN;
  bus_.Publish("UAV1/OBSTACLES", bad);
  Poll();
  EXPECT_NE(link_.last_drop_reason().find("obstacle 0: a value is not finite"), std::string::npos) << link_.last_drop_reason();
  bad = ObstaclesMsg(7, true);
  bad.healthy = false;
  bus_.Publish("UAV1/OBSTACLES", bad);
  Poll();
  EXPECT_NE(link_.last_drop_reason().find("unhealthy report carries obstacles"), std::string::npos);
  EXPECT_EQ(link_.dropped_messages(), 2);
  cm.num_points = 2;  // LCM would send only two; decoding checks the arrays against the count
  try {
    FromMessage(cm);
    ADD_FAILURE() << "a count mismatch was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("point arrays do not match"), std::string::npos) << e.what();
  }
}

uavmsg::mono_depth_t DepthMsg(int64_t seq, const std::string& camera, bool healthy) {
  DepthGrid g;
  g.utime = seq * 100000;
  g.camera = camera;
  g.rows = 3;
  g.cols = 4;
  g.obstacle_depth_m = 10;
  g.healthy = healthy;
  g.reason = healthy ? "" : "no navigation sample for this frame";
  g.cells.resize(12);
  if (healthy) {
    for (int c = 0; c < 12; ++c) g.cells[c] = {CellState::kFree, 20.0 + c, 0.3, 10, 0.9, ""};
    g.cells[5] = {CellState::kObstacle, 7.5, 0.1, 12, 0.9, ""};
    g.cells[11] = {CellState::kUnknown, 0, 0, 1, 0, "1 converged features (3 needed)"};
  } else {
    for (auto& c : g.cells) c.reason = g.reason;
  }
  uavmsg::mono_depth_t m = ToMessage(g);
  m.header = {"UAV1", seq};
  return m;
}

// Depth from motion: the grid reaches the model, every cell is a plottable DEPTH signal (0 while
// unknown), the grid is offered for drawing only over the video of its own camera and while
// fresh, and the channel turning unavailable and back is said once each.
TEST_F(LinkTest, DepthGridReachesTheModelThePlotsAndTheVideoOfItsCamera) {
  uavmsg::video_frame_t vf{};
  vf.header = {"UAV1", 1};
  vf.camera = "downward";
  vf.width = 32, vf.height = 24, vf.source_width = 640, vf.source_height = 480;
  vf.jpeg = Jpeg(32, 24);
  vf.size = static_cast<int32_t>(vf.jpeg.size());
  bus_.Publish("UAV1/VIDEO", vf);
  bus_.Publish("UAV1/MONO_DEPTH", DepthMsg(1, "downward", true));
  Poll();
  const VehicleModel& v = model_.vehicles().at("UAV1");
  const DepthGrid* g = v.DepthGridOver(v.video, now_, model_.obstacles().params());
  ASSERT_NE(g, nullptr) << link_.last_drop_reason();
  EXPECT_EQ(g->at(1, 1).state, CellState::kObstacle);
  EXPECT_EQ(g->at(2, 3).reason, "1 converged features (3 needed)");
  EXPECT_NEAR(*v.Latest(*FindSignal("DEPTH.r1c1")), 7.5, 1e-6);
  EXPECT_NEAR(*v.Latest(*FindSignal("DEPTH.r0c2")), 22.0, 1e-6);
  EXPECT_EQ(*v.Latest(*FindSignal("DEPTH.r2c3")), 0.0);  // unknown
  const std::vector<std::string> known = {"depth.known", ">=", "11"}, obstacles = {"depth.obstacles", "==", "1"};
  EXPECT_TRUE(EvaluateCondition(known, model_, now_).holds);
  EXPECT_TRUE(EvaluateCondition(obstacles, model_, now_).holds);
  EXPECT_EQ(v.DepthGridOver(v.video, now_ + 3.0, model_.obstacles().params()), nullptr);  // stale
  // A grid from another camera is not drawn over this one's video.
  bus_.Publish("UAV1/MONO_DEPTH", DepthMsg(2, "gimbal", true));
  Poll();
  EXPECT_EQ(v.DepthGridOver(v.video, now_, model_.obstacles().params()), nullptr);
  EXPECT_FALSE(EvaluateCondition(obstacles, model_, now_).holds);
  bus_.Publish("UAV1/MONO_DEPTH", DepthMsg(3, "downward", false));
  bus_.Publish("UAV1/MONO_DEPTH", DepthMsg(4, "downward", false));
  Poll();
  int said = 0;
  for (const auto& l : model_.log().lines()) said += l.text == "depth from motion unavailable: no navigation sample for this frame";
  EXPECT_EQ(said, 1);
  EXPECT_EQ(v.DepthGridOver(v.video, now_, model_.obstacles().params())->at(0, 0).state, CellState::kUnknown);
  bus_.Publish("UAV1/MONO_DEPTH", DepthMsg(5, "downward", true));
  Poll();
  EXPECT_EQ(model_.log().lines().back().text, "depth from motion available again");
  // A malformed grid is dropped naming the cell.
  auto bad = DepthMsg(6, "downward", true);
  bad.depth_m[4] = NAN;
  bus_.Publish("UAV1/MONO_DEPTH", bad);
  Poll();
  EXPECT_NE(link_.last_drop_reason().find("cell 4: depth or sigma is not a finite"), std::string::npos) << link_.last_drop_reason();
}

// The vehicle's sensing health reaches the model typed, round-trips through its message, feeds
// the SENSING signals scripts and plots read, and a malformed report is dropped naming why.
TEST_F(LinkTest, SensingHealthReachesTheModelAndItsSignals) {
  SensingReport sent;
  sent.utime = 5'000'000;
  sent.control_period_p50_ms = 20.0;
  sent.control_period_p99_ms = 21.5;
  sent.control_period_max_ms = 34.0;
  SensingWorker stereo;
  stereo.name = "STEREO";
  stereo.rig = "stereo_left";
  stereo.camera_rate_hz = 15;
  stereo.configured_rate_hz = 15;
  stereo.rate_hz = 7.5;
  stereo.latency_p50_ms = 60;
  stereo.latency_p99_ms = 60;
  stereo.compute_p50_ms = 98.6;
  stereo.results = 75;
  stereo.dropped = 75;
  stereo.healthy = false;
  stereo.reason = "behind: 7.5 of 15.0 Hz, 75 frames dropped";
  SensingWorker cam = stereo;
  cam.name = "CAM";
  cam.rig = "downward";
  cam.healthy = true;
  cam.reason.clear();
  cam.dropped = 0;
  sent.workers = {stereo, cam};
  uavmsg::sensing_t m = ToMessage(sent);
  m.header = {"UAV1", 1};
  bus_.Publish("UAV1/SENSING", m);
  Poll();
  const VehicleModel& v = model_.vehicles().at("UAV1");
  const std::optional<SensingReport>& sensing = v.reports.Get<SensingReport>().newest;
  ASSERT_TRUE(sensing) << link_.last_drop_reason();
  ASSERT_EQ(sensing->workers.size(), 2u);
  EXPECT_EQ(sensing->workers[0].reason, stereo.reason);
  EXPECT_NEAR(sensing->workers[0].compute_p50_ms, 98.6, 1e-4);
  EXPECT_EQ(sensing->workers[1].rig, "downward");
  EXPECT_EQ(*v.Latest(*FindSignal("SENSING.workers")), 2.0);
  EXPECT_EQ(*v.Latest(*FindSignal("SENSING.unhealthy")), 1.0);
  EXPECT_EQ(*v.Latest(*FindSignal("SENSING.dropped")), 75.0);
  EXPECT_NEAR(*v.Latest(*FindSignal("SENSING.ctl_p99")), 21.5, 1e-4);
  const std::vector<std::string> unhealthy = {"SENSING.unhealthy", "==", "1"};
  EXPECT_TRUE(EvaluateCondition(unhealthy, model_, now_).holds);
  auto bad = m;
  bad.workers[1].healthy = false;  // unhealthy without a reason
  bus_.Publish("UAV1/SENSING", bad);
  Poll();
  EXPECT_NE(link_.last_drop_reason().find("worker CAM unhealthy without a reason"), std::string::npos) << link_.last_drop_reason();
  bad = m;
  bad.workers[0].latency_p99_ms = NAN;
  bus_.Publish("UAV1/SENSING", bad);
  Poll();
  EXPECT_NE(link_.last_drop_reason().find("latency_p99_ms of worker STEREO"), std::string::npos) << link_.last_drop_reason();
  EXPECT_EQ(model_.vehicles().at("UAV1").reports.Get<SensingReport>().newest->workers[1].healthy, true);  // the good report stays
}

TEST_F(LinkTest, MismatchedVehicleIdsAndGarbageAreDroppedAndCounted) {
  bus_.Publish("UAV2/STATE", StateMsg(1, 1.0, 0.0));  // header says UAV1
  auto bad_task = StateMsg(2, 1.0, 0.0);
  bad_task.task = 42;
  bus_.Publish("UAV1/STATE", bad_task);
  Poll();
  EXPECT_EQ(link_.dropped_messages(), 2);
  EXPECT_NE(link_.last_drop_reason().find("task"), std::string::npos);
  const char garbage[] = "not an LCM message";
  EXPECT_FALSE(link_.Dispatch("UAV1/STATE", garbage, sizeof garbage, now_));
  EXPECT_EQ(link_.dropped_messages(), 3);
  // A tracker state the enum does not name: refused before the cast (found by fuzzing).
  uavmsg::track_status_t ts{};
  ts.header = {"UAV1", 1};
  ts.state = 7;
  bus_.Publish("UAV1/TRACK_STATUS", ts);
  Poll();
  EXPECT_EQ(link_.dropped_messages(), 4);
  EXPECT_NE(link_.last_drop_reason().find("unknown tracker state 7"), std::string::npos) << link_.last_drop_reason();
  EXPECT_TRUE(model_.vehicles().empty() || !model_.vehicles().at("UAV1").state);
}

TEST_F(LinkTest, AReplayingModelSendsNothingOnTheBus) {
  bus_.Publish("UAV1/STATE", StateMsg(1, 1.0, 0.0));
  Poll();
  int heard = 0;
  bus_.SubscribeRaw("UAV1/(COMMAND|GCS_HEARTBEAT|TRACK_TARGET|FILE_REQUEST|MISSION_UPLOAD)",
                    [&](const std::string&, const lcm::ReceiveBuffer&) { ++heard; });
  model_.SetReplay(true);
  EXPECT_FALSE(model_.SubmitCommand("land", now_));
  EXPECT_NE(model_.commands().error().find("nothing is sent"), std::string::npos);
  TrackTarget t;
  t.width = t.height = 0.2;
  EXPECT_TRUE(model_.SelectTarget(t, now_));  // queued by the concern, dropped by the replay
  for (int i = 0; i < 200; ++i) {  // 4 s: heartbeats would be due
    model_.Tick(now_);
    Poll();
    bus_.Handle(0);
  }
  EXPECT_EQ(heard, 0);
}

// ---- Replay of recorded event logs.

// Writes a log of a short flight: STATE at 50 Hz for `seconds`, a heartbeat per second, a tile
// every 0.2 s, and the GCS's commands in between (which the replay must only read).
std::string WriteLog(const std::string& name, double seconds) {
  const std::string path = (std::filesystem::temp_directory_path() / name).string();
  lcm::LogFile log(path, "w");
  int64_t n = 0;
  auto write = [&](const std::string& channel, const auto& msg, int64_t wall_us) {
    std::vector<uint8_t> buf(msg.getEncodedSize());
    msg.encode(buf.data(), 0, static_cast<int>(buf.size()));
    lcm::LogEvent e;
    e.eventnum = n++;
    e.timestamp = wall_us;
    e.channel = channel;
    e.datalen = static_cast<int32_t>(buf.size());
    e.data = buf.data();
    log.writeEvent(&e);
  };
  const int states = static_cast<int>(seconds * 50);
  for (int i = 0; i < states; ++i) {
    const double t = 1000.0 + i * 0.02;
    const int64_t wall = 5'000'000 + i * 2000;  // the simulator ran at 10x
    write("UAV1/STATE", StateMsg(i + 1, t, 10.0 * std::sin(i * 0.01)), wall);
    if (i % 50 == 0) {
      uavmsg::heartbeat_t hb{};
      hb.utime = static_cast<int64_t>(t * 1e6);
      hb.header = {"UAV1", i / 50 + 1};
      hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
      write("UAV1/HEARTBEAT", hb, wall);
      uavmsg::command_t c{};
      c.header = {"UAV1", i / 50 + 1};
      c.source = "gcs-live";
      c.text = "hover";
      write("UAV1/COMMAND", c, wall);
      uavmsg::command_ack_t ack{};
      ack.header = {"UAV1", i / 50 + 1};
      ack.source = "gcs-live";
      ack.command = "hover";
      ack.result = uavmsg::command_ack_t::RESULT_COMPLETED;
      write("UAV1/COMMAND_ACK", ack, wall);
    }
    if (i % 10 == 5) write("UAV1/MAP_TILE", TileMsg(i / 10 + 1, i / 10), wall);
  }
  return path;
}

struct Replayed {
  std::unique_ptr<GcsModel> model;
  std::unique_ptr<GcsLink> link;
  GcsLink& Reset() {
    link.reset();
    model = std::make_unique<GcsModel>("gcs", 1);
    model->SetReplay(true);
    link = std::make_unique<GcsLink>(nullptr, *model, std::nullopt);
    return *link;
  }
};

TEST(LogReplay, ReproducesTheFlightSampleForSampleOnTheVehicleClock) {
  const std::string path = WriteLog("uav_test_replay.lcmlog", 20.0);
  // What the live GCS saw: the same messages, decoded by the link as they came.
  Replayed live;
  live.Reset();
  live.model->SetReplay(false);
  {
    lcm::LogFile in(path, "r");
    for (const lcm::LogEvent* e = in.readNextEvent(); e; e = in.readNextEvent())
      live.link->Dispatch(e->channel, e->data, e->datalen, e->timestamp * 1e-6);
  }
  Replayed r;
  LogReplay replay(path, [&]() -> GcsLink& { return r.Reset(); });
  EXPECT_TRUE(replay.damage().empty());
  EXPECT_NEAR(replay.duration(), 19.98, 1e-6);  // vehicle time, not the 10x wall time
  replay.SetSpeed(10.0);
  EXPECT_FALSE(replay.SetSpeed(20.0));
  replay.Advance(1.0);  // 10 s of flight
  EXPECT_NEAR(replay.position(), 10.0, 1e-9);
  EXPECT_NEAR(*r.model->vehicles().at("UAV1").Latest(Sig("STATE.alt")), 10.0 * std::sin(500 * 0.01), 1e-9);
  replay.Pause();
  replay.Advance(5.0);
  EXPECT_NEAR(replay.position(), 10.0, 1e-9);
  replay.Play();
  replay.Advance(5.0);
  ASSERT_TRUE(replay.finished());
  const SignalSeries* a = live.model->vehicles().at("UAV1").History(Sig("STATE.alt"));
  const SignalSeries* b = r.model->vehicles().at("UAV1").History(Sig("STATE.alt"));
  ASSERT_TRUE(a && b);
  ASSERT_EQ(a->size(), 1000u);
  ASSERT_EQ(b->size(), a->size());
  for (std::size_t i = 0; i < a->size(); ++i) {
    ASSERT_EQ(a->TimeAt(i), b->TimeAt(i)) << i;
    ASSERT_EQ(a->ValueAt(i), b->ValueAt(i)) << i;
  }
  EXPECT_EQ(r.model->vehicles().at("UAV1").live_map.tiles.size(), 100u);
  EXPECT_EQ(r.model->vehicles().at("UAV1").live_map.received, live.model->vehicles().at("UAV1").live_map.received);
  // Seeking back starts a fresh model and replays up to the point.
  GcsModel* before = r.model.get();
  replay.Seek(2.0);
  EXPECT_NE(r.model.get(), before);
  EXPECT_EQ(r.model->vehicles().at("UAV1").History(Sig("STATE.alt"))->size(), 101u);  // t = 0 .. 2.00 s
  EXPECT_EQ(r.model->vehicles().at("UAV1").live_map.tiles.size(), 10u);
  // The live GCS's acknowledgements are in the messages, naming whom they answered.
  bool ack_shown = false;
  for (const auto& l : r.model->log().lines()) ack_shown |= l.text == "hover: completed [to gcs-live]";
  EXPECT_TRUE(ack_shown);
  // A replay refuses commands, saying why.
  EXPECT_FALSE(r.model->SubmitCommand("hover", 1.0));
  EXPECT_NE(r.model->commands().error().find("replaying"), std::string::npos);
  std::filesystem::remove(path);
}

TEST(LogReplay, TruncatedAndDamagedLogsReplayUpToTheDamageAndSayWhere) {
  const std::string path = WriteLog("uav_test_replay_damaged.lcmlog", 4.0);
  const auto size = std::filesystem::file_size(path);
  Replayed whole;
  const std::size_t all = LogReplay(path, [&]() -> GcsLink& { return whole.Reset(); }).events();

  const std::string cut = path + ".cut";
  std::filesystem::copy_file(path, cut, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::resize_file(cut, size * 6 / 10);
  Replayed r1;
  LogReplay truncated(cut, [&]() -> GcsLink& { return r1.Reset(); });
  EXPECT_LT(truncated.events(), all);
  EXPECT_GT(truncated.events(), all / 2);
  EXPECT_NE(truncated.damage().find("truncated or damaged"), std::string::npos) << truncated.damage();
  truncated.Seek(1e9);
  EXPECT_TRUE(truncated.finished());
  EXPECT_GT(r1.model->vehicles().at("UAV1").History(Sig("STATE.alt"))->size(), 50u);

  // Garbage written over the middle: the events before it replay, and the replay says where.
  const std::string bad = path + ".bad";
  std::filesystem::copy_file(path, bad, std::filesystem::copy_options::overwrite_existing);
  {
    std::fstream f(bad, std::ios::in | std::ios::out | std::ios::binary);
    f.seekp(static_cast<std::streamoff>(size / 2));
    const std::string junk(300, '\x5a');
    f.write(junk.data(), static_cast<std::streamsize>(junk.size()));
  }
  Replayed r2;
  LogReplay damaged(bad, [&]() -> GcsLink& { return r2.Reset(); });
  EXPECT_LT(damaged.events(), all);
  EXPECT_NE(damaged.damage().find("byte "), std::string::npos);
  damaged.Seek(1e9);
  EXPECT_GT(r2.model->vehicles().at("UAV1").History(Sig("STATE.alt"))->size(), 50u);

  Replayed r3;
  EXPECT_THROW(LogReplay("/nonexistent/events.lcmlog", [&]() -> GcsLink& { return r3.Reset(); }), std::runtime_error);
  for (const auto& p : {path, cut, bad}) std::filesystem::remove(p);
}

// Every report of VehicleReports has a decoder in the link (so the fuzz target, which draws
// its topics from GcsLink::Topics(), covers it) and reaches the model as that report.
TEST(ReportSeam, EveryReportIsDecodedByTheLinkAndReachesTheModel) {
  GcsModel model("gcs", 1);
  GcsLink link(nullptr, model, std::nullopt);
  const std::vector<Topic> topics = GcsLink::Topics();
  int64_t seq = 0;
  ForEachType(VehicleReports{}, [&](auto* type) {
    using T = std::remove_pointer_t<decltype(type)>;
    const Topic topic = Report<T>::kTopic;
    EXPECT_NE(std::find(topics.begin(), topics.end(), topic), topics.end()) << TopicName(topic);
    auto m = ToMessage(ExampleReport<T>());
    m.header.vehicle_id = "UAV1";
    m.header.seq = ++seq;
    std::vector<uint8_t> bytes(static_cast<std::size_t>(m.getEncodedSize()));
    m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
    EXPECT_TRUE(link.Dispatch(Channel("UAV1", topic), bytes.data(), static_cast<int>(bytes.size()), 1.0))
        << TopicName(topic) << ": " << link.last_drop_reason();
  });
  EXPECT_EQ(link.dropped_messages(), 0);
  // Each is kept as the vehicle's newest of its type, and its signals are sampled.
  const VehicleModel& v = model.vehicles().at("UAV1");
  ForEachType(VehicleReports{}, [&](auto* type) {
    using T = std::remove_pointer_t<decltype(type)>;
    const Received<T>& r = v.reports.Get<T>();
    EXPECT_TRUE(r.newest) << TopicName(Report<T>::kTopic);
    EXPECT_EQ(r.at, 1.0) << TopicName(Report<T>::kTopic);
    EXPECT_EQ(r.newest->utime, ExampleReport<T>().utime) << TopicName(Report<T>::kTopic);
    const SignalGroupId g = ReportGroup<T>();
    EXPECT_EQ(GroupName(g), ReportSignals<T>::kGroup);
    EXPECT_EQ(GroupSignals(g).size(), ReportSignals<T>::Table().size());
    if (!ReportSignals<T>::Table().empty()) {
      EXPECT_EQ(v.group(g).received, 1) << GroupName(g);
      ASSERT_EQ(v.group(g).latest.size(), ReportSignals<T>::Table().size());
      EXPECT_EQ(v.group(g).latest[0], ReportSignals<T>::Table()[0].read(ExampleReport<T>())) << GroupName(g);
    }
  });
}

}  // namespace
}  // namespace uav::gcs
