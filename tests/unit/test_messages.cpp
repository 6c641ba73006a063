// LCM message round trips: encode/decode, and through the Bus on the in-process memq:// URL.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <vector>

#include "uav/wire/messages.hpp"
#include "uav/wire/bus.hpp"
#include "uav/wire/reports.hpp"
#include "unit/report_examples.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/active_stereo.hpp"
#include "uav/shared/mono_depth.hpp"
#include "uavmsg/active_stereo_t.hpp"
#include "uavmsg/mono_depth_t.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/visual_odometry_t.hpp"

namespace uav {
namespace {

template <class Msg>
Msg RoundTrip(const Msg& in) {
  std::vector<uint8_t> buf(in.getEncodedSize());
  EXPECT_EQ(in.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  Msg out;
  EXPECT_EQ(out.decode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return out;
}

TEST(Messages, VehicleStateRoundTripKeepsEveryField) {
  uavmsg::vehicle_state_t m{};
  m.utime = 1700000000123456;
  m.header = {"UAV1", 42};
  m.x = 1.5; m.y = -2.5; m.z = -10.25;
  m.u = 0.1; m.v = 0.2; m.w = 0.3;
  m.phi = 0.01; m.theta = -0.02; m.psi = 3.1;
  m.p = 0.4; m.q = 0.5; m.r = 0.6;
  m.acx = 0.7; m.acy = 0.8; m.acz = -9.81;
  m.gps_latitude_deg = 1.2966; m.gps_longitude_deg = 103.7764; m.gps_altitude_m = 25.0;
  m.gps_fix = 3; m.gps_satellites = 11;
  for (int i = 0; i < 4; ++i) m.rotor_input[i] = 0.1f * i, m.servo_input[i] = -0.1f * i;
  m.flight_mode = uavmsg::vehicle_state_t::MODE_AUTO;
  m.task = uavmsg::vehicle_state_t::TASK_GOTO;
  m.armed = true; m.landed = false;
  m.battery_voltage_v = 11.9f; m.battery_remaining = 0.75f;
  const auto o = RoundTrip(m);
  EXPECT_EQ(o.utime, m.utime);
  EXPECT_EQ(o.header.vehicle_id, "UAV1");
  EXPECT_EQ(o.header.seq, 42);
  EXPECT_EQ(o.z, -10.25);
  EXPECT_EQ(o.psi, 3.1);
  EXPECT_EQ(o.acz, -9.81);
  EXPECT_EQ(o.gps_longitude_deg, 103.7764);
  EXPECT_EQ(o.rotor_input[3], 0.3f);
  EXPECT_EQ(o.servo_input[2], -0.2f);
  EXPECT_EQ(o.task, +uavmsg::vehicle_state_t::TASK_GOTO);
  EXPECT_TRUE(o.armed);
  EXPECT_EQ(o.battery_remaining, 0.75f);
}

TEST(Messages, CommandAckAndHeartbeatRoundTrip) {
  uavmsg::command_ack_t a{};
  a.utime = 5; a.header = {"UAV2", 7}; a.source = "gcs-a"; a.command_seq = 99;
  a.command = "goto"; a.result = uavmsg::command_ack_t::RESULT_IN_PROGRESS;
  a.progress_percent = 55; a.reason = "";
  const auto ao = RoundTrip(a);
  EXPECT_EQ(ao.command_seq, 99);
  EXPECT_EQ(ao.result, +uavmsg::command_ack_t::RESULT_IN_PROGRESS);
  EXPECT_EQ(ao.progress_percent, 55);

  uavmsg::heartbeat_t h{};
  h.utime = 9; h.header = {"UAV1", 1}; h.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
  h.source_name = "gcs-a"; h.uptime_us = 123;
  const auto ho = RoundTrip(h);
  EXPECT_EQ(ho.source_kind, +uavmsg::heartbeat_t::SOURCE_GCS);
  EXPECT_EQ(ho.source_name, "gcs-a");
}

TEST(Messages, TruncatedBufferIsRejected) {
  uavmsg::command_t c{};
  c.utime = 1; c.header = {"UAV1", 1}; c.source = "gcs"; c.command_seq = 1; c.text = "takeoff 10";
  std::vector<uint8_t> buf(c.getEncodedSize());
  c.encode(buf.data(), 0, static_cast<int>(buf.size()));
  uavmsg::command_t out;
  EXPECT_LT(out.decode(buf.data(), 0, static_cast<int>(buf.size()) - 3), 0);
  buf[0] ^= 0xFF;  // corrupt the type fingerprint
  EXPECT_LT(out.decode(buf.data(), 0, static_cast<int>(buf.size())), 0);
}

// A message spoiled by `spoil` must be refused by FromMessage with `why` in the error.
template <class Message>
void ExpectRefused(Message bad, const std::function<void(Message&)>& spoil, const std::string& why) {
  spoil(bad);
  try {
    FromMessage(bad);
    ADD_FAILURE() << "accepted: " << why;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
  }
}

TEST(Messages, ActiveStereoRoundTripsThroughBytesAndBadReportsAreRefusedByName) {
  ActiveStereoReport r;
  r.utime = 42;
  r.camera = "stereo_left";
  r.healthy = true;
  r.height_m = 1.52;
  r.height_sigma_m = 0.003;
  r.left_dots = 220, r.right_dots = 218, r.ambiguous = 4;
  r.clusters = {{Eigen::Vector3d(0.1, 0.0, 1.5), 1.52, 0.004, 150, true}, {Eigen::Vector3d(0.4, 0.2, 0.8), 0.77, 0.01, 40, false}};
  r.dots = {{0.2, 0.3, 1.51, 0}, {0.7, 0.6, 0.77, 1}};
  uavmsg::active_stereo_t m = ToMessage(r);
  std::vector<uint8_t> bytes(m.getEncodedSize());
  ASSERT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  uavmsg::active_stereo_t back;
  ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const ActiveStereoReport d = FromMessage(back);
  EXPECT_NEAR(d.height_m, 1.52, 1e-6);
  ASSERT_EQ(d.dots.size(), 2u);
  EXPECT_EQ(d.dots[1].cluster, 1);
  ASSERT_EQ(d.clusters.size(), 2u);
  EXPECT_TRUE(d.clusters[0].ground);
  EXPECT_FALSE(d.clusters[1].ground);
  EXPECT_NEAR(d.clusters[1].centre_B.z(), 0.8, 1e-6);
  auto refused = [&](const std::function<void(uavmsg::active_stereo_t&)>& spoil, const std::string& why) {
    ExpectRefused(ToMessage(r), spoil, why);
  };
  refused([](auto& b) { b.u.pop_back(); }, "point arrays do not have num_points entries");
  refused([](auto& b) { b.cluster[0] = 5; }, "point 0: cluster 5 does not exist");
  refused([](auto& b) { b.down_m[1] = NAN; }, "point 1: a value is not finite");
  refused([](auto& b) { b.height_m = NAN; }, "height or its sigma is not finite");
  refused([](auto& b) { b.healthy = false; }, "unhealthy report carries a height or points");
  refused([](auto& b) { b.height_m = 0; }, "healthy without a positive height");
  refused([](auto& b) { b.cluster_spread_m[0] = -1; }, "cluster 0: a value is not finite or is negative");
}

TEST(Messages, MonoDepthRoundTripsThroughBytesAndBadGridsAreRefusedByName) {
  DepthGrid g;
  g.utime = 1234567;
  g.camera = "downward";
  g.rows = 3;
  g.cols = 4;
  g.healthy = true;
  g.obstacle_depth_m = 10;
  g.tracked = 200;
  g.measured = 180;
  g.cells.resize(12);
  g.cells[0] = {CellState::kObstacle, 7.5, 0.1, 12, 0.9, ""};
  g.cells[1] = {CellState::kFree, 19.8, 0.3, 20, 1.0, ""};
  g.cells[2].reason = "2 converged features (3 needed)";
  uavmsg::mono_depth_t m = ToMessage(g);
  std::vector<uint8_t> bytes(m.getEncodedSize());
  ASSERT_EQ(m.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  uavmsg::mono_depth_t back;
  ASSERT_EQ(back.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const DepthGrid d = FromMessage(back);
  EXPECT_EQ(d.camera, "downward");
  EXPECT_EQ(d.at(0, 0).state, CellState::kObstacle);
  EXPECT_FLOAT_EQ(d.at(0, 1).depth_m, 19.8f);
  EXPECT_EQ(d.at(0, 2).reason, "2 converged features (3 needed)");
  EXPECT_EQ(d.tracked, 200);
  auto refused = [&](const std::function<void(uavmsg::mono_depth_t&)>& spoil, const std::string& why) {
    ExpectRefused(ToMessage(g), spoil, why);
  };
  refused([](auto& b) { b.rows = 2; }, "grid 2x4 with num_cells 12");
  refused([](auto& b) { b.depth_m.pop_back(); }, "cell arrays do not have num_cells entries");
  refused([](auto& b) { b.depth_m[1] = NAN; }, "cell 1: depth or sigma is not a finite non-negative number");
  refused([](auto& b) { b.state[3] = 7; }, "cell 3: state 7 is not 0..2");
  refused([](auto& b) { b.depth_m[0] = 0; }, "cell 0: known without a depth");
  refused([](auto& b) { b.healthy = false; }, "cell 0: known in an unhealthy report");
}

TEST(Messages, VisualOdometryCarriesTheLearntDisparityOffsetAndRefusesABadOne) {
  VisualOdometryReport r = ExampleReport<VisualOdometryReport>();
  r.disparity_offset_px = -0.3;
  r.disparity_offset_sigma_px = 0.02;
  const VisualOdometryReport d = FromMessage(ToMessage(r));
  EXPECT_FLOAT_EQ(d.disparity_offset_px, -0.3f);
  EXPECT_FLOAT_EQ(d.disparity_offset_sigma_px, 0.02f);
  auto refused = [&](const std::function<void(uavmsg::visual_odometry_t&)>& spoil, const std::string& why) {
    ExpectRefused(ToMessage(r), spoil, why);
  };
  const std::string why = "disparity offset or its sigma is not a finite number (sigma non-negative)";
  refused([](auto& m) { m.disparity_offset_px = NAN; }, why);
  refused([](auto& m) { m.disparity_offset_sigma_px = -0.1f; }, why);
}

TEST(Messages, AvoidanceRoundTripsToTheCentimetreAndBadReportsAreRefusedByName) {
  AvoidanceReport r;
  r.utime = 7;
  r.state = AvoidState::kAvoiding;
  r.goal_N = {50, 0, -5};
  r.path_N = {{1, 2, -5}, {10, 4, -5}, {50, 0, -5}};
  r.seen_free_m = 8.5;
  r.planning_ms = 7.5;
  r.map_cells = 123456;
  r.origin_N = {1, 2, -5};
  r.occupied_N = {{3.0f, 2.0f, -5.0f}, {12.345f, -4.2f, -0.2f}, {500.0f, 0.0f, 0.0f}};  // the last too far to send
  const AvoidanceReport d = FromMessage(ToMessage(r));
  EXPECT_EQ(d.state, AvoidState::kAvoiding);
  ASSERT_EQ(d.path_N.size(), 3u);
  EXPECT_NEAR(d.path_N[1].y(), 4.0, 1e-6);
  ASSERT_EQ(d.occupied_N.size(), 2u);
  EXPECT_NEAR(d.occupied_N[1].x(), 12.345, 0.006);
  EXPECT_NEAR(d.PathLength(), r.PathLength(), 1e-4);
  EXPECT_NEAR((d.Committed().back() - Eigen::Vector3d(1, 2, -5)).norm(), 8.5, 1e-4);
  auto refused = [&](const std::function<void(uavmsg::avoidance_t&)>& spoil, const std::string& why) {
    ExpectRefused(ToMessage(r), spoil, why);
  };
  refused([](auto& m) { m.state = 3; }, "state 3 is not one the planner sends");
  refused([](auto& m) { m.path_east_m.pop_back(); }, "path arrays do not match num_path");
  refused([](auto& m) { m.path_north_m[1] = NAN; }, "path point 1 is not finite");
  refused([](auto& m) { m.num_cells = uavmsg::avoidance_t::MAX_CELLS + 1; }, "num_cells 12001 outside 0..12000");
  refused([](auto& m) { m.cell_m = 0; }, "cell_m is not in 0.05..2 m");
  refused([](auto& m) { m.seen_free_m = -1; }, "seen_free_m is not a finite non-negative length");
}

TEST(Bus, MemqDeliversByChannelPatternAndCountsBadMessages) {
  Bus bus("memq://");
  std::vector<std::string> got;
  bus.Subscribe<uavmsg::status_text_t>(".*/STATUS_TEXT",
                                       [&](const std::string& ch, const uavmsg::status_text_t& m) {
                                         got.push_back(ch + ":" + m.text);
                                       });
  uavmsg::status_text_t s{};
  s.header = {"UAV1", 1}; s.text = "hello";
  bus.Publish(Channel("UAV1", Topic::kStatusText), s);
  s.header = {"UAV2", 1}; s.text = "world";
  bus.Publish(Channel("UAV2", Topic::kStatusText), s);
  uavmsg::heartbeat_t wrong_type{};
  wrong_type.header = {"UAV3", 1};
  bus.Publish(Channel("UAV3", Topic::kStatusText), wrong_type);
  bus.Handle(0);
  EXPECT_EQ(got, (std::vector<std::string>{"UAV1/STATUS_TEXT:hello", "UAV2/STATUS_TEXT:world"}));
  EXPECT_EQ(bus.DecodeErrors(), 1);
}

TEST(Bus, BadUrlThrowsNamingIt) {
  try {
    Bus bus("nonsense://x");
    FAIL() << "expected an exception";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("nonsense://x"), std::string::npos);
  }
}

TEST(Channels, NamesAndIds) {
  EXPECT_EQ(Channel("UAV1", Topic::kState), "UAV1/STATE");
  EXPECT_EQ(Channel("X", Topic::kGcsHeartbeat), "X/GCS_HEARTBEAT");
  EXPECT_TRUE(IsValidVehicleId("UAV_1-b"));
  EXPECT_FALSE(IsValidVehicleId(""));
  EXPECT_FALSE(IsValidVehicleId("UAV/1"));
  EXPECT_FALSE(IsValidVehicleId(std::string(33, 'a')));
  EXPECT_TRUE(IsValidVehicleId(std::string(32, 'a')));
}

// Every vehicle report round-trips through the seam: struct -> message -> bytes -> message ->
// struct, and the struct encodes to the same bytes again. The types are VehicleReports
// itself, so a report added to the list is tested here without a line more.
template <class List>
struct GtestTypes;
template <class... Ts>
struct GtestTypes<TypeList<Ts...>> {
  using type = ::testing::Types<Ts...>;
};

template <class T>
class ReportSeam : public ::testing::Test {};
TYPED_TEST_SUITE(ReportSeam, GtestTypes<VehicleReports>::type);

template <class Msg>
std::vector<uint8_t> Bytes(const Msg& m) {
  std::vector<uint8_t> b(static_cast<std::size_t>(m.getEncodedSize()));
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

TYPED_TEST(ReportSeam, RoundTripsThroughItsMessage) {
  using T = TypeParam;
  using Msg = typename Report<T>::Message;
  const T sent = ExampleReport<T>();
  const std::vector<uint8_t> bytes = Bytes(ToMessage(sent));
  Msg decoded;
  ASSERT_EQ(decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  const T received = FromMessage(decoded);
  EXPECT_EQ(received.utime, sent.utime);
  EXPECT_EQ(Bytes(ToMessage(received)), bytes);
  // Its channel is its own: no two reports share a topic.
  int same_topic = 0;
  ForEachType(VehicleReports{}, [&](auto* other) {
    same_topic += Report<std::remove_pointer_t<decltype(other)>>::kTopic == Report<T>::kTopic;
  });
  EXPECT_EQ(same_topic, 1);
}

}  // namespace
}  // namespace uav
