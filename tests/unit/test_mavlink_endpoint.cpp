// The vehicle's MAVLink endpoint apart from any vehicle: on a memq:// bus, it turns a signed
// COMMAND_LONG into the vehicle's own command (signed on the bus, from "mavlink:<sysid>"), drops
// and counts unsigned, foreign-key and replayed frames, garbage and bus messages that do not
// convert (a truncated datagram is dropped alone: the command after it still arrives), denies a
// reposition to no place, resends a command the bus lost, and names what is wrong with an endpoint
// it cannot open.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "uav/runtime/mavlink_endpoint.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "unit/free_port.hpp"
#include "uav/shared/time.hpp"
#include "uav/wire/bus.hpp"
#include "uav/wire/messages.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"

namespace uav::runtime {
namespace {

using namespace uav::mavlink;

// A UDP socket on a free port of the loopback, as a ground station would have.
struct Peer {
  int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in vehicle{};
  Peer() {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
    timeval tv{0, 200'000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
  }
  ~Peer() { ::close(fd); }
  void Send(const std::vector<uint8_t>& b) {
    ::sendto(fd, b.data(), b.size(), 0, reinterpret_cast<sockaddr*>(&vehicle), sizeof vehicle);
  }
};

using test::FreePort;

std::vector<uint8_t> Arm(const SecretKey* key, uint64_t timestamp) {
  CommandLong c;
  c.target_system = 1, c.target_component = 1, c.command = 400, c.param1 = 1;
  Frame f;
  f.sysid = 255, f.compid = 190, f.msgid = CommandLong::kId;
  f.payload = Pack(c);
  return Encode(f, FindLayout(CommandLong::kId)->crc_extra, key, 1, timestamp);
}

// An endpoint on a memq:// bus, listening on a free UDP port; a ground station's socket aimed at
// it; what the endpoint published on the bus and said.
class Rig {
 public:
  explicit Rig(MavlinkParams p = {}) {
    bus_.Subscribe<uavmsg::command_t>(Channel("UAV1", Topic::kCommand),
                                      [this](const std::string&, const uavmsg::command_t& m) { commands_.push_back(m); });
    const int port = FreePort();
    p.endpoint = "udpin:127.0.0.1:" + std::to_string(port);
    p.video_host.clear();
    endpoint_ = std::make_unique<MavlinkEndpoint>("UAV1", bus_, p, key_,
                                                  [this](Severity, const std::string& t) { said_.push_back(t); });
    gcs_.vehicle.sin_family = AF_INET;
    gcs_.vehicle.sin_port = htons(static_cast<uint16_t>(port));
    gcs_.vehicle.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  }
  // A link tick after `sleep_us` (what the GCS sent has arrived), then the bus.
  void Tick(int sleep_us = 20'000) {
    ::usleep(static_cast<useconds_t>(sleep_us));
    endpoint_->Tick(1'000'000);
    bus_.Handle(0);
  }
  auto Parts() { return std::tie(bus_, key_, commands_, said_, gcs_, *endpoint_); }

 private:
  Bus bus_{"memq://"};
  SigningKey key_ = SigningKey::FromPassphrase("the crew's passphrase");
  std::vector<uavmsg::command_t> commands_;
  std::vector<std::string> said_;
  Peer gcs_;
  std::unique_ptr<MavlinkEndpoint> endpoint_;
};

TEST(MavlinkEndpointTest, ASignedCommandBecomesTheVehiclesOwnAndEverythingElseIsDroppedAndCounted) {
  Rig rig;
  auto [bus, key, commands, said, gcs, endpoint] = rig.Parts();
  const SigningKey other = SigningKey::FromPassphrase("not the crew's");
  auto tick = [&] { rig.Tick(); };
  const uint64_t now = static_cast<uint64_t>(SigningTimestamp(WallTimeMicros()));
  const std::vector<uint8_t> arm = Arm(&key.bytes, now);
  gcs.Send(arm);
  tick();
  ASSERT_EQ(commands.size(), 1u);
  EXPECT_EQ(commands[0].text, "arm");
  EXPECT_EQ(commands[0].source, "mavlink:1");
  EXPECT_NE(commands[0].signature.version, 0) << "signed with the vehicle's key, as our GCS signs";

  gcs.Send(arm);                          // the same frame again
  gcs.Send(Arm(nullptr, 0));              // unsigned
  gcs.Send(Arm(&other.bytes, now + 10));  // another key
  gcs.Send({'n', 'o', 'i', 's', 'e'});
  std::vector<uint8_t> damaged = Arm(&key.bytes, now + 20);
  damaged[15] ^= 0x40;
  gcs.Send(damaged);
  gcs.Send({0xfd, 0xf0, 0x00, 0x00, 0x01, 0xff});  // a truncated frame claiming 240 bytes
  tick();
  EXPECT_EQ(commands.size(), 1u) << "none of them reached the vehicle";
  const MavlinkEndpoint::Counts c = endpoint.counts();
  EXPECT_EQ(c.replayed, 1);
  EXPECT_EQ(c.unsigned_frames, 1);
  EXPECT_EQ(c.bad_signature, 1);
  EXPECT_GE(c.skipped_bytes, 5 + 6);
  EXPECT_EQ(c.bad_checksum, 1);
  std::string all;
  for (const std::string& s : said) all += s + "\n";
  EXPECT_NE(all.find("MAVLink frame refused: replayed"), std::string::npos) << all;
  EXPECT_NE(all.find("MAVLink frame refused: unsigned"), std::string::npos) << all;
  EXPECT_NE(all.find("MAVLink frame refused: bad signature"), std::string::npos) << all;

  // A reposition to latitude 200 degrees: refused (DENIED), nothing sent to the vehicle, and the
  // endpoint goes on.
  // First a state that does not convert (anyone can publish on the bus): counted, nothing stops.
  uavmsg::vehicle_state_t broken{};
  broken.header.vehicle_id = "UAV1";
  broken.task = 99;
  bus.Publish(Channel("UAV1", Topic::kState), broken);
  bus.Handle(0);
  EXPECT_EQ(endpoint.counts().bad_bus_messages, 1);
  uavmsg::vehicle_state_t state{};
  state.header.vehicle_id = "UAV1";
  state.home_latitude_deg = 1.2966, state.home_longitude_deg = 103.7764, state.home_altitude_m = 15;
  bus.Publish(Channel("UAV1", Topic::kState), state);
  bus.Handle(0);  // the state reaches the endpoint
  CommandInt reposition;
  reposition.target_system = 1, reposition.target_component = 1, reposition.command = 192, reposition.frame = 6;
  reposition.x = 2'000'000'000, reposition.y = 1'037'764'000, reposition.z = 10;
  Frame rf;
  rf.sysid = 255, rf.compid = 190, rf.msgid = CommandInt::kId;
  rf.payload = Pack(reposition);
  gcs.Send(Encode(rf, FindLayout(CommandInt::kId)->crc_extra, &key.bytes, 1, now + 30));
  tick();
  EXPECT_EQ(commands.size(), 1u);

  // The answers went back to the sender (udpin): a signed PX4 HEARTBEAT, the reposition denied.
  uint8_t buf[2048];
  Parser parser(Lookup());
  bool px4 = false, denied = false;
  for (ssize_t n; (n = ::recv(gcs.fd, buf, sizeof buf, 0)) > 0;)
    for (const Frame& f : parser.Push(buf, static_cast<std::size_t>(n))) {
      if (f.msgid == Heartbeat::kId) px4 = Unpack<Heartbeat>(f).autopilot == 12 && f.signature && Verify(key.bytes, f.raw);
      if (f.msgid == mavlink::CommandAck::kId) {
        const auto ack = Unpack<mavlink::CommandAck>(f);
        denied = denied || (ack.command == 192 && ack.result == 2);
      }
    }
  EXPECT_TRUE(px4) << "a signed PX4 heartbeat";
  EXPECT_TRUE(denied) << "DO_REPOSITION to latitude 200 denied";
}

// The bus loses the command on its way to the flight controller (nobody answers): the endpoint
// publishes it again with the same sequence number (the vehicle's intake never runs a resend
// twice) until an answer comes, and the GCS gets that answer. A command never answered ends in
// MAV_RESULT_FAILED with the reason said, instead of a GCS waiting for ever.
TEST(MavlinkEndpointTest, ACommandTheBusLostIsPublishedAgainAndOneNeverAnsweredFails) {
  MavlinkParams p;
  p.command_resend_s = 0.05;
  p.command_tries = 3;
  Rig rig(p);
  auto [bus, key, commands, said, gcs, endpoint] = rig.Parts();
  auto tick = [&] { rig.Tick(30'000); };
  std::vector<int> acks;  // MAV_RESULT of every COMMAND_ACK of 400, in order
  Parser parser(Lookup());
  auto read_acks = [&] {
    uint8_t buf[2048];
    for (ssize_t n; (n = ::recv(gcs.fd, buf, sizeof buf, MSG_DONTWAIT)) > 0;)
      for (const Frame& f : parser.Push(buf, static_cast<std::size_t>(n)))
        if (f.msgid == mavlink::CommandAck::kId && Unpack<mavlink::CommandAck>(f).command == 400)
          acks.push_back(Unpack<mavlink::CommandAck>(f).result);
  };
  uint64_t now = static_cast<uint64_t>(SigningTimestamp(WallTimeMicros()));
  gcs.Send(Arm(&key.bytes, now));
  for (int i = 0; i < 4; ++i) tick();  // 120 ms: the first publication and at least one more
  ASSERT_GE(commands.size(), 2u);
  for (const auto& c : commands) {
    EXPECT_EQ(c.command_seq, commands[0].command_seq) << "a resend, not a new command";
    EXPECT_EQ(c.text, "arm");
  }
  EXPECT_GT(commands[1].signature.timestamp, commands[0].signature.timestamp) << "signed afresh";
  // The flight controller answers (the resend reached it): the GCS hears the answer, the resends stop.
  uav::CommandAck done{"mavlink:1", commands[0].command_seq, "arm", CommandResult::kCompleted, 100, ""};
  uavmsg::command_ack_t m = ToMessage(done);
  m.header.vehicle_id = "UAV1";
  bus.Publish(Channel("UAV1", Topic::kCommandAck), m);
  bus.Handle(0);
  const std::size_t published = commands.size();
  for (int i = 0; i < 6; ++i) tick();
  EXPECT_EQ(commands.size(), published) << "answered: no more resends";
  read_acks();
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0], 0) << "ACCEPTED";
  EXPECT_EQ(endpoint.counts().commands_unanswered, 0);

  // A second arm nobody ever answers: three publications, then FAILED and the reason.
  commands.clear();
  gcs.Send(Arm(&key.bytes, now + 1000));
  for (int i = 0; i < 10; ++i) tick();
  EXPECT_EQ(commands.size(), 3u);
  read_acks();
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_EQ(acks[1], 4) << "FAILED";
  EXPECT_EQ(endpoint.counts().commands_unanswered, 1);
  std::string all;
  for (const std::string& s : said) all += s + "\n";
  EXPECT_NE(all.find("MAVLink command 'arm': no answer from the flight controller in 0.15 s"), std::string::npos) << all;
}

TEST(MavlinkEndpointTest, AnEndpointItCannotOpenIsNamed) {
  Bus bus("memq://");
  auto open = [&](const std::string& spec) {
    MavlinkParams p;
    p.endpoint = spec;
    try {
      MavlinkEndpoint e("UAV1", bus, p, std::nullopt, [](Severity, const std::string&) {});
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string("opened");
  };
  EXPECT_NE(open("tcp:127.0.0.1:5760").find("expected udp:HOST:PORT"), std::string::npos);
  EXPECT_NE(open("udp:127.0.0.1").find("needs HOST:PORT"), std::string::npos);
  EXPECT_NE(open("udp:127.0.0.1:99999").find("port '99999' is not 1..65535"), std::string::npos);
  EXPECT_NE(open("udp:no.such.host.invalid:14550").find("cannot resolve host"), std::string::npos);
  EXPECT_NE(open("serial:/nonexistent/ttyUSB9:57600").find("cannot open /nonexistent/ttyUSB9"), std::string::npos);
  EXPECT_NE(open("serial:/dev/null:12345").find("baud rate 12345"), std::string::npos);
  EXPECT_NE(open("serial:/dev/null:57600").find("is not a serial device"), std::string::npos);
}

}  // namespace
}  // namespace uav::runtime
