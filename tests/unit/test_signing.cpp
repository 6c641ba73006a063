// Message signing (shared/signing.hpp): HMAC-SHA256 against RFC 4231, key files, and the battery
// of messages a vehicle must not execute: forged (wrong key, any flipped bit in body or tag),
// replayed (later, and across a restart), reordered, stale, truncated, unsigned and misaddressed.
#include <sys/stat.h>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uav/shared/sha256.hpp"
#include "uav/wire/signed_message.hpp"
#include "uavmsg/command_t.hpp"

namespace uav {
namespace {

std::string Hex(const SigningTag& t) { return Sha256::Hex(t); }

TEST(HmacSha256, Rfc4231Vectors) {
  // Test case 1: key = 20 x 0x0b, "Hi There".
  const std::vector<uint8_t> key1(20, 0x0b);
  EXPECT_EQ(Hex(HmacSha256(key1.data(), key1.size(), "Hi There", 8)),
            "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7");
  // Test case 2: key = "Jefe".
  const std::string msg2 = "what do ya want for nothing?";
  EXPECT_EQ(Hex(HmacSha256(reinterpret_cast<const uint8_t*>("Jefe"), 4, msg2.data(), msg2.size())),
            "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843");
  // Test case 6: a key longer than the block (131 x 0xaa) is hashed first.
  const std::vector<uint8_t> key6(131, 0xaa);
  const std::string msg6 = "Test Using Larger Than Block-Size Key - Hash Key First";
  EXPECT_EQ(Hex(HmacSha256(key6.data(), key6.size(), msg6.data(), msg6.size())),
            "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54");
}

class KeyFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/uav_keys_XXXXXX";
    dir_ = mkdtemp(tmpl);
  }
  void TearDown() override { std::system(("rm -rf " + dir_).c_str()); }
  std::string dir_;
};

TEST_F(KeyFiles, GeneratedKeysArePrivateRandomAndLoadBack) {
  const std::string path = dir_ + "/a.key";
  const SigningKey a = SigningKey::Generate(path);
  struct stat st {};
  ASSERT_EQ(stat(path.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 0777, 0600u);
  EXPECT_EQ(st.st_size, 32);
  EXPECT_EQ(SigningKey::LoadFile(path).bytes, a.bytes);
  EXPECT_NE(SigningKey::Generate(dir_ + "/b.key").bytes, a.bytes);
  EXPECT_EQ(a.Id().size(), 16u);
  // Never over an existing key: the vehicle and its GCSs would no longer share it.
  try {
    SigningKey::Generate(path);
    FAIL() << "overwrote a key";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
}

TEST_F(KeyFiles, ReadableByOthersWrongSizeOrMissingIsRefusedSayingWhy) {
  const std::string path = dir_ + "/k.key";
  SigningKey::Generate(path);
  auto refusal = [](const std::string& p) {
    try {
      SigningKey::LoadFile(p);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  chmod(path.c_str(), 0644);
  EXPECT_NE(refusal(path).find("mode 0644"), std::string::npos) << refusal(path);
  chmod(path.c_str(), 0620);
  EXPECT_NE(refusal(path).find("mode 0620"), std::string::npos);
  chmod(path.c_str(), 0400);
  EXPECT_EQ(refusal(path), "");  // read-only for its owner is fine
  for (size_t size : {0, 31, 33, 64}) {
    const std::string p = dir_ + "/size" + std::to_string(size);
    std::ofstream(p) << std::string(size, 'x');
    chmod(p.c_str(), 0600);
    EXPECT_NE(refusal(p).find("exactly 32 bytes"), std::string::npos) << size << ": " << refusal(p);
  }
  EXPECT_NE(refusal(dir_ + "/none").find("cannot open signing key"), std::string::npos);
  EXPECT_NE(refusal(dir_).find("not a regular file"), std::string::npos) << refusal(dir_);
}

// A GCS (signer) and a vehicle (verifier) on a simulated wall clock.
class Signing : public ::testing::Test {
 protected:
  static constexpr int64_t kStartUs = 1'795'000'000'000'000;  // the vehicle's start, Unix microseconds
  void SetUp() override {
    key_.bytes.fill(0x11);
    other_key_.bytes.fill(0x22);
  }
  uavmsg::command_t Command(const std::string& text, int64_t at_us, const SigningKey& key, int link = 0,
                            const std::string& to = "UAV1", const std::string& source = "gcs-a") {
    MessageSigner signer(key, link);
    return Command(signer, text, at_us, to, source);
  }
  uavmsg::command_t Command(MessageSigner& signer, const std::string& text, int64_t at_us, const std::string& to = "UAV1",
                            const std::string& source = "gcs-a") {
    uavmsg::command_t m{};
    m.utime = at_us;
    m.header.vehicle_id = to;
    m.header.seq = ++seq_;
    m.source = source;
    m.command_seq = seq_;
    m.text = text;
    SignMessage(signer, at_us, m);
    return m;
  }
  SignatureVerifier Vehicle(int64_t floor = SigningTimestamp(kStartUs)) { return SignatureVerifier(key_, "UAV1", floor); }
  static SignatureVerdict Check(SignatureVerifier& v, const uavmsg::command_t& m, int64_t now_us) {
    return VerifyMessage(v, m, m.source, SigningTimestamp(now_us));
  }
  static std::vector<uint8_t> Encode(const uavmsg::command_t& m) {
    std::vector<uint8_t> b(m.getEncodedSize());
    m.encode(b.data(), 0, static_cast<int>(b.size()));
    return b;
  }
  SigningKey key_, other_key_;
  int64_t seq_ = 0;
};

TEST_F(Signing, RightKeyIsAcceptedAndTimestampsAreMavlinkUnits) {
  auto v = Vehicle();
  const auto m = Command("arm", kStartUs + 1'000'000, key_);
  EXPECT_EQ(int(m.signature.version), int(uavmsg::signature_t::VERSION_HMAC_SHA256));
  EXPECT_EQ(m.signature.timestamp, (kStartUs + 1'000'000 - 1420070400LL * 1000000) / 10);  // 10 us since 2015
  EXPECT_LE(m.signature.timestamp, kSigningTimestampMax);
  EXPECT_EQ(Check(v, m, kStartUs + 1'000'100), SignatureVerdict::kAccepted);
}

TEST_F(Signing, WrongKeyIsABadTag) {
  auto v = Vehicle();
  EXPECT_EQ(Check(v, Command("arm", kStartUs + 1'000'000, other_key_), kStartUs + 1'000'000), SignatureVerdict::kBadTag);
}

TEST_F(Signing, EveryFlippedBitOfBodyOrTagIsRefused) {
  const auto m = Command("goto 10 20 30", kStartUs + 2'000'000, key_);
  const std::vector<uint8_t> bytes = Encode(m);
  int decoded = 0, tag_bits = 0, non_canonical = 0;
  for (size_t bit = 0; bit < bytes.size() * 8; ++bit) {
    std::vector<uint8_t> b = bytes;
    b[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
    uavmsg::command_t f;
    if (f.decode(b.data(), 0, static_cast<int>(b.size())) < 0) continue;  // dropped by the bus
    // The bus drops what our encoder would not write (a string's terminating byte changed):
    // signatures are over the encoding, so it must be the datagram (Bus::Canonical).
    if (Encode(f) != b) {
      ++non_canonical;
      continue;
    }
    ++decoded;
    auto v = Vehicle();  // fresh: the verdict is about the bits, not an earlier acceptance
    const SignatureVerdict verdict = Check(v, f, kStartUs + 2'000'000);
    EXPECT_NE(verdict, SignatureVerdict::kAccepted) << "bit " << bit << " flipped and still accepted";
    if (bit / 8 >= bytes.size() - 32) {
      ++tag_bits;
      EXPECT_EQ(verdict, SignatureVerdict::kBadTag) << "tag bit " << bit;
    }
  }
  EXPECT_GT(decoded, static_cast<int>(bytes.size() * 8) / 2);  // most flips decode: the tag must catch them
  EXPECT_EQ(tag_bits, 256);
  EXPECT_GE(non_canonical, 3 * 8);  // at least the zero after "UAV1", "gcs-a" and "goto 10 20 30"
}

TEST_F(Signing, EveryTruncationFailsToDecode) {
  const std::vector<uint8_t> bytes = Encode(Command("takeoff 10", kStartUs + 1'000'000, key_));
  for (size_t n = 0; n < bytes.size(); ++n) {
    uavmsg::command_t f;
    EXPECT_LT(f.decode(bytes.data(), 0, static_cast<int>(n)), 0) << n << " of " << bytes.size() << " bytes decoded";
  }
}

TEST_F(Signing, ReplayedAndReorderedMessagesAreRefused) {
  auto v = Vehicle();
  MessageSigner gcs(key_, 0);
  const auto first = Command(gcs, "arm", kStartUs + 1'000'000);
  const auto second = Command(gcs, "takeoff 10", kStartUs + 1'000'000);  // same microsecond: still later
  EXPECT_GT(second.signature.timestamp, first.signature.timestamp);
  EXPECT_EQ(Check(v, second, kStartUs + 1'000'000), SignatureVerdict::kAccepted);
  EXPECT_EQ(Check(v, first, kStartUs + 1'000'000), SignatureVerdict::kReplay);  // reordered
  EXPECT_EQ(Check(v, second, kStartUs + 30'000'000), SignatureVerdict::kReplay);  // the same, later
  EXPECT_EQ(Check(v, Command(gcs, "land", kStartUs + 31'000'000), kStartUs + 31'000'000), SignatureVerdict::kAccepted);
}

TEST_F(Signing, ANewLinkOlderThanTheWindowIsStale) {
  auto v = Vehicle();
  const int64_t now = kStartUs + 600'000'000;  // ten minutes after the start
  EXPECT_EQ(Check(v, Command("arm", now - 61'000'000, key_), now), SignatureVerdict::kStale);
  EXPECT_EQ(Check(v, Command("arm", now - 59'000'000, key_, 1), now), SignatureVerdict::kAccepted);
  // Links are independent: another GCS may be a little behind the first.
  EXPECT_EQ(Check(v, Command("arm", now - 30'000'000, key_, 0, "UAV1", "gcs-b"), now), SignatureVerdict::kAccepted);
}

TEST_F(Signing, AMessageRecordedBeforeARestartIsRefusedAfterIt) {
  const auto recorded = Command("arm", kStartUs + 5'000'000, key_);
  auto before = Vehicle();
  ASSERT_EQ(Check(before, recorded, kStartUs + 5'000'000), SignatureVerdict::kAccepted);
  // Restarted two seconds later with the state file: the newest accepted is the floor.
  const int64_t restart = kStartUs + 7'000'000;
  auto after = Vehicle(std::max(SigningTimestamp(restart), before.newest()));
  EXPECT_EQ(Check(after, recorded, restart + 100'000), SignatureVerdict::kStale);
  // Without the state file the start time is the floor; a GCS clock ahead of the vehicle's
  // would slip through that, the state file does not let it.
  const auto ahead = Command("land", kStartUs + 9'000'000, key_, 0, "UAV1", "gcs-ahead");
  auto first_life = Vehicle();
  ASSERT_EQ(Check(first_life, ahead, kStartUs + 6'000'000), SignatureVerdict::kAccepted);
  auto no_state = Vehicle(SigningTimestamp(restart));
  EXPECT_EQ(Check(no_state, ahead, restart), SignatureVerdict::kAccepted);
  auto with_state = Vehicle(std::max(SigningTimestamp(restart), first_life.newest()));
  EXPECT_EQ(Check(with_state, ahead, restart), SignatureVerdict::kStale);
  // The live GCS goes on: its next message is newer than both.
  EXPECT_EQ(Check(with_state, Command("land", kStartUs + 10'000'000, key_), restart), SignatureVerdict::kAccepted);
}

TEST_F(Signing, UnsignedAndMisaddressedAreRefused) {
  auto v = Vehicle();
  auto m = Command("arm", kStartUs + 1'000'000, key_);
  m.signature = uavmsg::signature_t{};
  EXPECT_EQ(Check(v, m, kStartUs + 1'000'000), SignatureVerdict::kUnsigned);
  EXPECT_EQ(Check(v, Command("arm", kStartUs + 1'000'000, key_, 0, "UAV2"), kStartUs + 1'000'000),
            SignatureVerdict::kWrongVehicle);
  // Signed for UAV2, re-addressed to UAV1: the vehicle id is under the tag.
  auto readdressed = Command("arm", kStartUs + 1'000'000, key_, 0, "UAV2");
  readdressed.header.vehicle_id = "UAV1";
  EXPECT_EQ(Check(v, readdressed, kStartUs + 1'000'000), SignatureVerdict::kBadTag);
  // Another source name on the same signature: the source is in the bytes too.
  auto renamed = Command("arm", kStartUs + 1'000'000, key_);
  renamed.source = "gcs-b";
  EXPECT_EQ(Check(v, renamed, kStartUs + 1'000'000), SignatureVerdict::kBadTag);
  EXPECT_STREQ(SignatureVerdictName(SignatureVerdict::kReplay), "replay");
}

}  // namespace
}  // namespace uav
