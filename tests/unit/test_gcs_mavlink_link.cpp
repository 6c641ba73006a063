// The GCS with both links: our vehicle on the bus (memq://) and an ArduCopter on MAVLink (a UDP
// peer playing the vehicle with our codec) in one vehicle list; each command goes out on its
// vehicle's link only, in its dialect (Guided before a take-off), and the autopilot's answer comes
// back as the command's result; an upload puts ArduPilot's home at item 0.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <string>
#include <vector>

#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/mavlink_link.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "unit/free_port.hpp"
#include "uav/wire/bus.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/heartbeat_t.hpp"

namespace uav::gcs {
namespace {

using namespace uav::mavlink;

using test::FreePort;

// The vehicle's side: sends frames of system 1 to the GCS's port, parses what comes back.
struct Vehicle {
  int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK, 0);
  sockaddr_in gcs{};
  Parser parser{Lookup()};
  uint8_t seq = 0;
  explicit Vehicle(int gcs_port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    gcs = a;
    gcs.sin_port = htons(static_cast<uint16_t>(gcs_port));
  }
  ~Vehicle() { ::close(fd); }
  template <class M>
  void Send(const M& m) {
    Frame f;
    f.seq = seq++, f.sysid = 1, f.compid = 1, f.msgid = M::kId;
    f.payload = Pack(m);
    const auto b = Encode(f, FindLayout(M::kId)->crc_extra);
    ::sendto(fd, b.data(), b.size(), 0, reinterpret_cast<sockaddr*>(&gcs), sizeof gcs);
  }
  std::vector<Frame> Received() {
    std::vector<Frame> out;
    uint8_t buf[2048];
    for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0;)
      for (Frame& f : parser.Push(buf, static_cast<std::size_t>(n))) out.push_back(std::move(f));
    return out;
  }
  // The first frame of message M among `frames`, decoded.
  template <class M>
  static std::optional<M> Find(const std::vector<Frame>& frames) {
    for (const Frame& f : frames)
      if (f.msgid == M::kId) return Unpack<M>(f);
    return std::nullopt;
  }
};

TEST(GcsMavlinkLinkTest, BothKindsOfVehicleInOneListEachCommandOnItsOwnLink) {
  Bus bus("memq://");
  GcsModel model("gcs", 100);
  GcsLink lcm(&bus, model, std::nullopt);
  std::vector<uavmsg::command_t> on_bus;
  bus.Subscribe<uavmsg::command_t>("[^/]+/COMMAND", [&](const std::string&, const uavmsg::command_t& m) { on_bus.push_back(m); });
  MavlinkLinkParams p;
  const int port = FreePort();
  p.endpoint = "udpin:127.0.0.1:" + std::to_string(port);
  p.video_port = 0;
  MavlinkLink mav(p, model);
  Vehicle copter(port);
  double now = 1.0;
  std::vector<Frame> heard;
  auto pump = [&] {
    for (int i = 0; i < 3; ++i) {
      ::usleep(10'000);
      now += 0.02;
      lcm.Receive(0, now);
      mav.Receive(now);
      model.Tick(now);
      GcsOutgoing out = model.TakeOutgoing();
      mav.Send(out, now);
      lcm.Send(out, now);
      bus.Handle(0);
      for (Frame& f : copter.Received()) heard.push_back(std::move(f));
    }
  };
  uavmsg::heartbeat_t hb{};
  hb.header = {"UAV1", 1};
  hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
  bus.Publish("UAV1/HEARTBEAT", hb);
  Heartbeat h;
  h.type = 2, h.autopilot = kAutopilotArduPilot, h.custom_mode = 5;  // ArduCopter, Loiter
  copter.Send(h);
  HomePosition home;
  home.latitude = 12966000, home.longitude = 1037764000, home.altitude = 15000;
  copter.Send(home);
  pump();
  ASSERT_EQ(model.vehicles().size(), 2u);
  ASSERT_TRUE(model.vehicles().count("arducopter-1"));
  ASSERT_TRUE(model.vehicles().at("arducopter-1").mavlink);
  EXPECT_EQ(model.vehicles().at("arducopter-1").mavlink->autopilot, "ArduCopter");
  EXPECT_EQ(model.vehicles().at("arducopter-1").mavlink->mode, "Loiter");
  EXPECT_FALSE(model.vehicles().at("UAV1").mavlink);
  EXPECT_TRUE(Vehicle::Find<ParamRequestList>(heard)) << "the parameters are asked for on discovery";

  // A take-off to the ArduCopter: Guided first, then NAV_TAKEOFF above home; nothing on the bus.
  model.SelectVehicle("arducopter-1");
  heard.clear();
  ASSERT_TRUE(model.SubmitCommand("takeoff 10", now));
  pump();
  const auto mode = Vehicle::Find<CommandLong>(heard);
  ASSERT_TRUE(mode);
  EXPECT_EQ(mode->command, 176);
  EXPECT_FLOAT_EQ(mode->param2, 4.f);
  EXPECT_TRUE(on_bus.empty());
  mavlink::CommandAck ack;
  ack.command = 176, ack.result = 0, ack.target_system = 255;
  copter.Send(ack);
  heard.clear();
  pump();
  const auto takeoff = Vehicle::Find<CommandLong>(heard);
  ASSERT_TRUE(takeoff);
  EXPECT_EQ(takeoff->command, 22);
  EXPECT_FLOAT_EQ(takeoff->param7, 10.f);
  ack.command = 22, ack.result = 4;  // FAILED, as Copter answers when not armed
  copter.Send(ack);
  pump();
  const SentCommand& sent = model.commands().sent().back();
  ASSERT_TRUE(sent.last_ack);
  EXPECT_EQ(sent.last_ack->result, CommandResult::kFailed);
  EXPECT_NE(sent.last_ack->reason.find("NAV_TAKEOFF"), std::string::npos);

  // A command to our vehicle goes on the bus, none to the ArduCopter.
  model.SelectVehicle("UAV1");
  heard.clear();
  ASSERT_TRUE(model.SubmitCommand("arm", now));
  pump();
  ASSERT_EQ(on_bus.size(), 1u);
  EXPECT_EQ(on_bus[0].text, "arm");
  EXPECT_FALSE(Vehicle::Find<CommandLong>(heard));

  // An upload to the ArduCopter: its home as item 0, the mission's items after it.
  model.SelectVehicle("arducopter-1");
  auto& planner = model.missions().planner();
  planner.SetOrigin({1.2966, 103.7764, 15.0});
  for (const Eigen::Vector2d& ne : {Eigen::Vector2d(5, -30), Eigen::Vector2d(5, 30), Eigen::Vector2d(45, 30), Eigen::Vector2d(45, -30)})
    planner.AddVertex(ne);
  heard.clear();
  ASSERT_TRUE(model.UploadMission(now)) << model.missions().error();
  pump();
  const auto count = Vehicle::Find<MissionCount>(heard);
  ASSERT_TRUE(count);
  const std::size_t mission_items = model.vehicles().at("arducopter-1").upload->total_items();
  EXPECT_EQ(count->count, mission_items + 1) << "home first";
  MissionRequestInt rq;
  rq.target_system = 255;
  copter.Send(rq);
  heard.clear();
  pump();
  const auto item0 = Vehicle::Find<MissionItemInt>(heard);
  ASSERT_TRUE(item0);
  EXPECT_EQ(item0->seq, 0);
  EXPECT_EQ(item0->x, 12966000);
  EXPECT_EQ(item0->y, 1037764000);
}

}  // namespace
}  // namespace uav::gcs
