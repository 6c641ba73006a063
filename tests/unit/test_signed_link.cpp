// Signed commands through the relay (lossy_link.hpp): with the right key every command is
// executed exactly once through loss, duplication and reordering (the GCS resends, signed anew,
// until answered); everything a tap on the link recorded, played again afterwards, is refused.
// A copy the tap caught but the relay lost stays acceptable only until a newer message on the
// same link arrives: the GCS's signed 1 Hz heartbeat closes that window.
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uav/wire/messages.hpp"
#include "uav/runtime/command_intake.hpp"
#include "uav/wire/signed_message.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "unit/lossy_link.hpp"

namespace uav {
namespace {

struct RelayCase {
  double loss, duplicate, max_delay_s;
};

class SignedCommandsThroughRelay : public ::testing::TestWithParam<RelayCase> {};

TEST_P(SignedCommandsThroughRelay, EachRunsOnceAndNoRecordedMessageRunsAgain) {
  const RelayCase link = GetParam();
  SigningKey key;
  key.bytes.fill(0x5a);
  constexpr int64_t kStartUs = 1'795'000'000'000'000;
  auto wall_us = [&](double t) { return kStartUs + static_cast<int64_t>(t * 1e6); };
  MessageSigner gcs(key, 0);
  SignatureVerifier vehicle(key, "UAV1", SigningTimestamp(kStartUs));
  runtime::CommandIntake intake("UAV1");
  LossyLink<uavmsg::command_t> up(link.loss, link.duplicate, link.max_delay_s, 7);
  LossyLink<int64_t> down(link.loss, link.duplicate, link.max_delay_s, 8);  // acknowledged command_seq
  LossyLink<uavmsg::heartbeat_t> heartbeats(link.loss, link.duplicate, link.max_delay_s, 9);
  std::vector<uavmsg::command_t> tap;                                      // everything sent, recorded
  const std::vector<std::string> texts = {"arm", "takeoff 10", "goto 10 0 10", "goto 0 10 10", "hover", "land"};
  std::map<int64_t, int> executed;  // command_seq -> times executed
  std::map<int64_t, bool> acked;
  std::map<SignatureVerdict, int> verdicts;
  size_t next = 0;
  double last_sent = -1, last_heartbeat = -1, all_acked = -1;
  for (double t = 0; t < 120 && (all_acked < 0 || t < all_acked + 5); t += 0.02) {
    if (all_acked < 0 && acked.size() == texts.size()) all_acked = t;
    if (t - last_heartbeat >= 1.0) {
      uavmsg::heartbeat_t hb{};
      hb.header.vehicle_id = "UAV1";
      hb.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
      hb.source_name = "gcs-a";
      SignMessage(gcs, wall_us(t), hb);
      heartbeats.Send(hb, t);
      last_heartbeat = t;
    }
    heartbeats.Deliver(t, [&](const uavmsg::heartbeat_t& m) {
      ++verdicts[VerifyMessage(vehicle, m, m.source_name, SigningTimestamp(wall_us(t)))];
    });
    // The GCS: one command at a time, resent every 0.5 s until answered, each copy signed anew.
    if (next < texts.size() && acked.count(static_cast<int64_t>(next + 1))) ++next;
    if (next < texts.size() && (last_sent < 0 || t - last_sent >= 0.5)) {
      uavmsg::command_t m{};
      m.utime = wall_us(t);
      m.header.vehicle_id = "UAV1";
      m.source = "gcs-a";
      m.command_seq = static_cast<int64_t>(next + 1);
      m.text = texts[next];
      SignMessage(gcs, wall_us(t), m);
      up.Send(m, t);
      tap.push_back(m);
      last_sent = t;
    }
    // The vehicle: the gate, then the intake (which answers a resend without running it again).
    up.Deliver(t, [&](const uavmsg::command_t& m) {
      const SignatureVerdict v = VerifyMessage(vehicle, m, m.source, SigningTimestamp(wall_us(t)));
      ++verdicts[v];
      if (v != SignatureVerdict::kAccepted) return;
      const auto r = intake.Receive(m.header.vehicle_id, m.source, m.command_seq, m.text);
      if (r.request) {
        ++executed[m.command_seq];
        intake.Remember({m.source, m.command_seq, r.request->command.Name(), control::AckResult::kCompleted, 100, ""});
      }
      down.Send(m.command_seq, t);
    });
    down.Deliver(t, [&](int64_t seq) { acked[seq] = true; });
  }
  ASSERT_EQ(acked.size(), texts.size()) << "not every command was answered";
  for (size_t i = 1; i <= texts.size(); ++i) EXPECT_EQ(executed[static_cast<int64_t>(i)], 1) << texts[i - 1];
  if (link.duplicate > 0 || link.max_delay_s > 0.5) {
    EXPECT_GT(verdicts[SignatureVerdict::kReplay], 0);
  }
  // An attacker plays the whole recording again, in order and reversed, a minute later.
  const double later = 180;
  int accepted_again = 0;
  for (const auto& m : tap)
    accepted_again += VerifyMessage(vehicle, m, m.source, SigningTimestamp(wall_us(later))) == SignatureVerdict::kAccepted;
  for (auto it = tap.rbegin(); it != tap.rend(); ++it)
    accepted_again += VerifyMessage(vehicle, *it, it->source, SigningTimestamp(wall_us(later))) == SignatureVerdict::kAccepted;
  EXPECT_EQ(accepted_again, 0);
  std::printf("[ relay ] loss %.0f %%, duplicates %.0f %%, delay up to %.1f s: %zu sent, %d accepted (commands and heartbeats), %d replays "
              "refused, recording of %zu refused on replay\n",
              100 * link.loss, 100 * link.duplicate, link.max_delay_s, tap.size(), verdicts[SignatureVerdict::kAccepted],
              verdicts[SignatureVerdict::kReplay], tap.size());
}

INSTANTIATE_TEST_SUITE_P(Links, SignedCommandsThroughRelay,
                         ::testing::Values(RelayCase{0, 0, 0}, RelayCase{0.2, 0.2, 0.3}, RelayCase{0.3, 0.3, 1.2}),
                         [](const auto& info) { return "case" + std::to_string(info.index); });

}  // namespace
}  // namespace uav
