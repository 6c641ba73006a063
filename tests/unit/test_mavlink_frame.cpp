// MAVLink framing from the specification: the checksum's standard check value, MAVLink 2 and 1
// frames through the parser (truncated zeros padded back, garbage and damaged frames skipped and
// counted, a broken datagram dropped alone), and signing (a tampered frame or another key fails).
#include <gtest/gtest.h>

#include <cstring>

#include "uav/shared/mavlink_frame.hpp"

namespace uav::mavlink {
namespace {

// HEARTBEAT (id 0, 9 bytes, CRC_EXTRA 50) and a made-up 40-byte message for truncation.
std::optional<MessageInfo> Lookup(uint32_t id) {
  if (id == 0) return MessageInfo{50, 9};
  if (id == 70000) return MessageInfo{123, 40};
  return std::nullopt;
}

Frame Heartbeat(int version) {
  Frame f;
  f.version = version;
  f.seq = 7, f.sysid = 1, f.compid = 1, f.msgid = 0;
  f.payload = {0, 0, 0, 0, 2, 12, 0x81, 4, 3};  // custom_mode 0, QUADROTOR, PX4, armed, ACTIVE, v3
  return f;
}

TEST(MavlinkFrame, TheChecksumIsCrc16Mcrf4xx) {
  const char* check = "123456789";
  EXPECT_EQ(Crc16(reinterpret_cast<const uint8_t*>(check), std::strlen(check)), 0x6F91);  // the catalogue's check value
}

TEST(MavlinkFrame, V2AndV1FramesRoundTripThroughTheParser) {
  Parser parser(Lookup);
  const std::vector<uint8_t> v2 = Encode(Heartbeat(2), 50);
  const std::vector<uint8_t> v1 = Encode(Heartbeat(1), 50);
  EXPECT_EQ(v2.size(), 10u + 9u + 2u);
  EXPECT_EQ(v1.size(), 6u + 9u + 2u);
  std::vector<uint8_t> stream = {0x00, 0x42};  // noise before
  stream.insert(stream.end(), v2.begin(), v2.end());
  stream.insert(stream.end(), v1.begin(), v1.end());
  // Byte by byte, as a serial line delivers them.
  std::vector<Frame> frames;
  for (uint8_t b : stream)
    for (Frame& f : parser.Push(&b, 1)) frames.push_back(std::move(f));
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_EQ(frames[0].version, 2);
  EXPECT_EQ(frames[1].version, 1);
  for (const Frame& f : frames) {
    EXPECT_EQ(f.payload, Heartbeat(2).payload);
    EXPECT_EQ(f.seq, 7);
    EXPECT_FALSE(f.signature);
  }
  EXPECT_EQ(parser.counts().skipped_bytes, 2);
}

TEST(MavlinkFrame, V2DropsTrailingZerosAndTheReceiverPadsThemBack) {
  Frame f;
  f.msgid = 70000;  // a 24-bit id
  f.payload.assign(40, 0);
  f.payload[0] = 9, f.payload[3] = 1;
  const std::vector<uint8_t> wire = Encode(f, 123);
  EXPECT_EQ(wire[1], 4) << "40 bytes sent as 4";
  Parser parser(Lookup);
  const std::vector<Frame> got = parser.Push(wire.data(), wire.size());
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].msgid, 70000u);
  EXPECT_EQ(got[0].payload, f.payload);
  // An all-zero payload keeps one byte.
  f.payload.assign(40, 0);
  EXPECT_EQ(Encode(f, 123)[1], 1);
}

TEST(MavlinkFrame, DamagedUnknownAndFlaggedFramesAreSkippedAndCounted) {
  Parser parser(Lookup);
  std::vector<uint8_t> damaged = Encode(Heartbeat(2), 50);
  damaged[12] ^= 0x01;
  std::vector<uint8_t> wrong_extra = Encode(Heartbeat(2), 51);  // another definition of the message
  Frame unknown = Heartbeat(2);
  unknown.msgid = 999;
  Frame flagged = Heartbeat(2);
  flagged.incompat_flags = 0x02;  // a flag this parser does not know
  std::vector<uint8_t> stream = damaged;
  for (const auto& more : {wrong_extra, Encode(unknown, 0), Encode(flagged, 50), Encode(Heartbeat(2), 50)})
    stream.insert(stream.end(), more.begin(), more.end());
  const std::vector<Frame> got = parser.Push(stream.data(), stream.size());
  ASSERT_EQ(got.size(), 1u) << "only the good heartbeat";
  EXPECT_GE(parser.counts().bad_checksum, 2);
  EXPECT_EQ(parser.counts().unknown_message, 1);
  EXPECT_EQ(parser.counts().bad_flags, 1);
}

// UDP: a truncated frame, or garbage that starts like a long frame, ends with its datagram. As a
// stream (Push) the heartbeat of the next datagram is swallowed into the bogus frame; datagram by
// datagram (PushDatagram) it is kept.
TEST(MavlinkFrame, ABrokenDatagramNeverSwallowsTheNextOne) {
  const std::vector<uint8_t> truncated = {0xfd, 0x09, 0x00, 0x00, 0x01, 0xff};  // a header claiming 9 bytes
  const std::vector<uint8_t> bogus = {0xfd, 0xf0, 0x02, 0x00, 0x01, 0xff, 0x01, 0x00, 0x00, 0x00};  // 240 bytes, a flag
  const std::vector<uint8_t> good = Encode(Heartbeat(2), 50);
  for (const auto& broken : {truncated, bogus}) {
    Parser stream(Lookup);
    stream.Push(broken.data(), broken.size());
    std::size_t streamed = 0;
    for (int i = 0; i < 5; ++i) streamed += stream.Push(good.data(), good.size()).size();
    EXPECT_LT(streamed, 5u) << "as a stream, a good frame is lost";
    Parser datagrams(Lookup);
    EXPECT_TRUE(datagrams.PushDatagram(broken.data(), broken.size()).empty());
    EXPECT_EQ(datagrams.counts().skipped_bytes, static_cast<int64_t>(broken.size()));
    std::size_t kept = 0;
    for (int i = 0; i < 5; ++i) kept += datagrams.PushDatagram(good.data(), good.size()).size();
    EXPECT_EQ(kept, 5u) << "datagram by datagram, every good frame";
  }
}

TEST(MavlinkFrame, ASignedFrameVerifiesWithItsKeyOnly) {
  SecretKey key{};
  for (int i = 0; i < 32; ++i) key[i] = static_cast<uint8_t>(i * 7 + 1);
  const uint64_t timestamp = 0x0000123456789AULL;
  const std::vector<uint8_t> wire = Encode(Heartbeat(2), 50, &key, 3, timestamp);
  EXPECT_EQ(wire.size(), 10u + 9u + 2u + 13u);
  EXPECT_TRUE(wire[2] & kIncompatSigned);
  Parser parser(Lookup);
  const std::vector<Frame> got = parser.Push(wire.data(), wire.size());
  ASSERT_EQ(got.size(), 1u);
  ASSERT_TRUE(got[0].signature);
  EXPECT_EQ(got[0].signature->link_id, 3);
  EXPECT_EQ(got[0].signature->timestamp, timestamp);
  EXPECT_TRUE(Verify(key, got[0].raw));
  SecretKey other = key;
  other[0] ^= 1;
  EXPECT_FALSE(Verify(other, got[0].raw));
  std::vector<uint8_t> tampered = got[0].raw;
  tampered[10 + 4] ^= 0x01;  // the payload (the checksum would catch it too; the signature must)
  EXPECT_FALSE(Verify(key, tampered));
  std::vector<uint8_t> later = got[0].raw;
  later[wire.size() - 12] ^= 0x01;  // the timestamp changed: the signature no longer matches
  EXPECT_FALSE(Verify(key, later));
  Frame f = Heartbeat(2);
  EXPECT_THROW(Encode(f, 50, &key, 0, 1ULL << 48), std::invalid_argument);
  f.version = 1;
  f.msgid = 300;
  EXPECT_THROW(Encode(f, 50), std::invalid_argument);
}

}  // namespace
}  // namespace uav::mavlink
