// The message tables derived from mavlink_messages.def: wire order, CRC_EXTRA and lengths for
// messages whose numbers the specification publishes (the full table is checked against npm's
// mavlink-mappings by tests/mavlink/tables.js), round trips through frames with truncated
// extensions, and the signing rules of a receiver (replay, stale, wrong key, unsigned).
#include <gtest/gtest.h>

#include <map>

#include "uav/shared/mavlink_messages.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/signing.hpp"

namespace uav::mavlink {
namespace {

TEST(MavlinkMessages, LayoutsFollowTheSpecificationsRules) {
  // CRC_EXTRA and lengths as published in common.xml's generated headers.
  struct Known {
    uint32_t id;
    uint8_t crc_extra;
    std::size_t length, base_length;
  };
  for (const Known& k : {Known{0, 50, 9, 9}, Known{1, 124, 43, 31}, Known{22, 220, 25, 25}, Known{24, 24, 52, 30},
                         Known{33, 104, 28, 28}, Known{73, 38, 38, 37}, Known{76, 152, 33, 33}, Known{77, 143, 10, 3},
                         Known{148, 178, 78, 60}, Known{253, 83, 54, 51}}) {
    const MessageLayout* l = FindLayout(k.id);
    ASSERT_NE(l, nullptr) << k.id;
    EXPECT_EQ(l->crc_extra, k.crc_extra) << l->name;
    EXPECT_EQ(l->length, k.length) << l->name;
    EXPECT_EQ(l->base_length, k.base_length) << l->name;
  }
  // HEARTBEAT: custom_mode (4 bytes) moves first; the 1-byte fields keep their order.
  const MessageLayout& hb = *FindLayout(Heartbeat::kId);
  EXPECT_EQ(hb.fields[0].name, "custom_mode");
  EXPECT_EQ(hb.fields[1].name, "type");
  EXPECT_EQ(hb.fields[5].name, "mavlink_version");
  EXPECT_EQ(FindLayout(99999), nullptr);
}

TEST(MavlinkMessages, AMessageRoundTripsThroughAFrameWithItsExtensionsTruncated) {
  MissionItemInt item;
  item.target_system = 1, item.target_component = 1, item.seq = 12, item.frame = 3, item.command = 16;
  item.autocontinue = 1, item.param1 = 2.5f, item.x = 473977420, item.y = 85455940, item.z = 30.f;
  Frame f;
  f.sysid = 255, f.compid = 190, f.msgid = MissionItemInt::kId;
  f.payload = Pack(item);
  const std::vector<uint8_t> bytes = Encode(f, FindLayout(MissionItemInt::kId)->crc_extra);
  EXPECT_EQ(bytes[1], 37) << "mission_type 0 (the last byte) is not sent";
  Parser parser(Lookup());
  const std::vector<Frame> frames = parser.Push(bytes.data(), bytes.size());
  ASSERT_EQ(frames.size(), 1u);
  const MissionItemInt back = Unpack<MissionItemInt>(frames[0]);
  EXPECT_EQ(back.seq, 12);
  EXPECT_EQ(back.command, 16);
  EXPECT_EQ(back.x, 473977420);
  EXPECT_EQ(back.y, 85455940);
  EXPECT_FLOAT_EQ(back.param1, 2.5f);
  EXPECT_EQ(back.mission_type, 0);
  EXPECT_THROW(Unpack<Heartbeat>(frames[0]), std::invalid_argument);

  Statustext t;
  SetText(t.text, std::string(60, 'x'));
  EXPECT_EQ(Text(t.text), std::string(50, 'x')) << "50 characters and no NUL is a full STATUSTEXT";
}

TEST(MavlinkMessages, AReceiverRefusesReplayedStaleForeignAndUnsignedFrames) {
  const SecretKey key = SigningKey::FromPassphrase("operator passphrase").bytes;
  const SecretKey other = SigningKey::FromPassphrase("someone else").bytes;
  const uint64_t now = 600'000'000'000;  // [10 us]
  auto frame = [](const SecretKey* k, uint64_t timestamp, uint8_t sysid = 255) {
    Frame f;
    f.sysid = sysid, f.compid = 190, f.msgid = Heartbeat::kId;
    Heartbeat hb;
    hb.type = 6;
    f.payload = Pack(hb);
    const std::vector<uint8_t> bytes = Encode(f, FindLayout(Heartbeat::kId)->crc_extra, k, 2, timestamp);
    Parser p(Lookup());
    return p.Push(bytes.data(), bytes.size()).at(0);
  };
  SignedStreams streams(key, false);
  const Frame first = frame(&key, now - 100);
  EXPECT_EQ(streams.Check(first, now), SignedStreams::Verdict::kAccepted);
  EXPECT_EQ(streams.Check(first, now), SignedStreams::Verdict::kReplay) << "the same frame again";
  EXPECT_EQ(streams.Check(frame(&key, now - 50), now), SignedStreams::Verdict::kAccepted);
  EXPECT_EQ(streams.Check(frame(&key, now - 60), now), SignedStreams::Verdict::kReplay) << "older than the last";
  EXPECT_EQ(streams.Check(frame(&key, now - 2 * SignedStreams::kNewStreamWindow, 7), now),
            SignedStreams::Verdict::kStale) << "a new stream two minutes behind";
  EXPECT_EQ(streams.Check(frame(&key, now - SignedStreams::kNewStreamWindow / 2, 8), now),
            SignedStreams::Verdict::kAccepted) << "a new stream half a minute behind";
  EXPECT_EQ(streams.Check(frame(&other, now + 10), now), SignedStreams::Verdict::kBadSignature);
  EXPECT_EQ(streams.Check(frame(nullptr, 0), now), SignedStreams::Verdict::kUnsigned);
  SignedStreams insecure(key, true);
  EXPECT_EQ(insecure.Check(frame(nullptr, 0), now), SignedStreams::Verdict::kAccepted);
  // What this side sends is strictly increasing, even with a clock that stands still.
  const uint64_t a = streams.NextTimestamp(now), b = streams.NextTimestamp(now);
  EXPECT_GT(b, a);
  EXPECT_GE(a, now);
}

TEST(MavlinkMessages, EveryVehicleParameterHasAStableUniqueIdOf16CharactersAtMost) {
  std::map<std::string, std::string> by_id;
  for (const ParameterSpec& p : VehicleParameterSchema().specs) {
    const std::string id = ParamIdOf(p.name);
    EXPECT_LE(id.size(), 16u) << p.name;
    if (p.name.size() <= 16) {
      EXPECT_EQ(id, p.name);
    }
    EXPECT_TRUE(by_id.emplace(id, p.name).second) << p.name << " and " << by_id[id] << " share " << id;
  }
  // Written down: a GCS's saved parameter file names it so.
  EXPECT_EQ(ParamIdOf("gyro_cruise_roll_rate_gain"), ParamIdOf("gyro_cruise_roll_rate_gain"));
  EXPECT_EQ(ParamIdOf("gyro_cruise_roll_rate_gain").substr(0, 12), "gyro_cruise_");
}

}  // namespace
}  // namespace uav::mavlink
