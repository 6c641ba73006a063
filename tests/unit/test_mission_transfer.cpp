// Mission upload protocol through a lossy channel: chunks and acknowledgements are dropped,
// duplicated and reordered; the vehicle ends with exactly the mission the GCS sent, or both sides
// say why not.
#include <random>

#include <gtest/gtest.h>

#include "uav/waypoints/mission_messages.hpp"

namespace uav::waypoints {
namespace {

const GeodeticPoint kHome{1.2966, 103.7764, 15.0};

Mission BigMission(int waypoints) {
  Mission m;
  m.home = kHome;
  m.items.push_back({mav_cmd::kNavTakeoff, mav_frame::kGlobalRelativeAlt, {0, 0, 0, NAN}, kHome.latitude_deg, kHome.longitude_deg, 10});
  for (int i = 0; i < waypoints; ++i)
    m.items.push_back({mav_cmd::kNavWaypoint, mav_frame::kGlobalRelativeAlt, {0, 0, 0, NAN},
                       kHome.latitude_deg + 1e-5 * i, kHome.longitude_deg + 2e-5 * (i % 7), 10.0 + i % 5});
  m.items.push_back({mav_cmd::kNavReturnToLaunch, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0});
  return m;
}

// Messages in flight, delivered in random order with loss and duplication; each passes through
// its LCM message type and back, as on the bus.
template <class T>
class LossyChannel {
 public:
  LossyChannel(double loss, double dup, std::mt19937* rng) : loss_(loss), dup_(dup), rng_(rng) {}
  void Send(const T& m) {
    std::uniform_real_distribution<double> u(0, 1);
    if (u(*rng_) < loss_) return;
    queue_.push_back(m);
    if (u(*rng_) < dup_) queue_.push_back(m);
  }
  std::vector<T> Deliver() {
    std::shuffle(queue_.begin(), queue_.end(), *rng_);
    std::vector<T> out;
    out.swap(queue_);
    return out;
  }

 private:
  double loss_, dup_;
  std::mt19937* rng_;
  std::vector<T> queue_;
};

struct Outcome {
  MissionUploader::State state;
  std::string reason;
  std::optional<Mission> stored;
  double seconds;
};

Outcome Upload(const Mission& m, double loss, double dup, unsigned seed,
               const std::function<std::string(const Mission&)>& check = nullptr) {
  std::mt19937 rng(seed);
  LossyChannel<uavmsg::mission_upload_t> up(loss, dup, &rng);
  LossyChannel<uavmsg::mission_ack_t> down(loss, dup, &rng);
  MissionAssembler vehicle;
  std::optional<Mission> stored;
  auto accept = [&](const Mission& got) {
    const std::string why = check ? check(got) : "";
    if (why.empty()) stored = got;
    return why;
  };
  MissionUploader gcs(m, 42);
  double t = 0;
  for (; t < 120 && gcs.state() == MissionUploader::State::kSending; t += 0.05) {
    for (const auto& c : gcs.Tick(t)) up.Send(ToMessage(c));
    for (const auto& msg : up.Deliver()) down.Send(ToMessage(vehicle.Receive(FromMessage(msg), accept)));
    for (const auto& a : down.Deliver()) gcs.OnAck(FromMessage(a), t);
  }
  return {gcs.state(), gcs.reason(), stored, t};
}

class LossyUpload : public testing::TestWithParam<double> {};

TEST_P(LossyUpload, ArrivesIdenticalEveryTime) {
  const Mission m = BigMission(150);  // 152 items: 13 chunks
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const Outcome o = Upload(m, GetParam(), GetParam(), seed);
    ASSERT_EQ(o.state, MissionUploader::State::kAccepted) << "seed " << seed << ": " << o.reason;
    EXPECT_LT(o.seconds, 30.0);
    ASSERT_TRUE(o.stored);
    EXPECT_EQ(MissionDigest(*o.stored), MissionDigest(m));
    ASSERT_EQ(o.stored->items.size(), m.items.size());
    for (std::size_t i = 0; i < m.items.size(); ++i) EXPECT_TRUE(o.stored->items[i] == m.items[i]);
  }
}

INSTANTIATE_TEST_SUITE_P(LossAndDuplication, LossyUpload, testing::Values(0.0, 0.01, 0.05, 0.10));

TEST(MissionTransfer, AHopelessLinkFailsCleanly) {
  // 30 % loss each way: some uploads run out of tries. Then the GCS says so, and the vehicle
  // holds either nothing or the whole mission (when only the final answer was lost).
  const Mission m = BigMission(150);
  int accepted = 0, failed = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const Outcome o = Upload(m, 0.3, 0.3, seed);
    if (o.stored) {
      EXPECT_EQ(MissionDigest(*o.stored), MissionDigest(m));
    }
    if (o.state == MissionUploader::State::kAccepted) {
      ++accepted;
      EXPECT_TRUE(o.stored);
    } else {
      ++failed;
      EXPECT_EQ(o.state, MissionUploader::State::kFailed);
      EXPECT_NE(o.reason.find("no answer"), std::string::npos) << o.reason;
    }
  }
  EXPECT_GT(accepted, 0);
  std::printf("30 %% loss: %d of 20 uploads accepted, %d failed cleanly\n", accepted, failed);
}

TEST(MissionTransfer, TheVehicleRefusalReachesTheGcsWithItsReason) {
  const Outcome o = Upload(BigMission(10), 0.05, 0.05, 7, [](const Mission&) { return std::string("speed too high"); });
  EXPECT_EQ(o.state, MissionUploader::State::kRejected);
  EXPECT_EQ(o.reason, "speed too high");
  EXPECT_FALSE(o.stored);
}

TEST(MissionTransfer, CorruptedContentIsRejectedByTheDigest) {
  const Mission m = BigMission(20);
  auto chunks = SplitMission(m, 5);
  chunks[1].items[3].latitude_deg += 1e-6;  // what a duplicated LCM fragment could do
  MissionAssembler vehicle;
  bool stored = false;
  MissionUploadAck ack;
  for (const auto& c : chunks) ack = vehicle.Receive(c, [&](const Mission&) { stored = true; return std::string(); });
  EXPECT_EQ(ack.result, MissionUploadAck::Result::kRejected);
  EXPECT_NE(ack.reason.find("digest"), std::string::npos);
  EXPECT_FALSE(stored);
}

TEST(MissionTransfer, ANewUploadReplacesAHalfReceivedOne) {
  const Mission a = BigMission(30), b = BigMission(40);
  MissionAssembler vehicle;
  std::optional<Mission> stored;
  auto accept = [&](const Mission& got) { stored = got; return std::string(); };
  const auto ca = SplitMission(a, 1), cb = SplitMission(b, 2);
  vehicle.Receive(ca[0], accept);
  vehicle.Receive(ca[1], accept);
  MissionUploadAck ack;
  for (const auto& c : cb) ack = vehicle.Receive(c, accept);
  EXPECT_EQ(ack.result, MissionUploadAck::Result::kAccepted);
  ASSERT_TRUE(stored);
  EXPECT_EQ(MissionDigest(*stored), MissionDigest(b));
  // A late chunk of the old upload does not disturb anything.
  const auto late = vehicle.Receive(ca[2], accept);
  EXPECT_EQ(late.received_items, 0);
  EXPECT_EQ(MissionDigest(*stored), MissionDigest(b));
}

TEST(MissionTransfer, GivesUpWhenTheVehicleIsSilent) {
  MissionUploader gcs(BigMission(5), 1);
  int sent = 0;
  for (double t = 0; t < 30; t += 0.05) sent += static_cast<int>(gcs.Tick(t).size());
  EXPECT_EQ(gcs.state(), MissionUploader::State::kFailed);
  EXPECT_EQ(sent, MissionUploader::kMaxTries);
  EXPECT_NE(gcs.reason().find("no answer"), std::string::npos);
}

TEST(MissionTransfer, MalformedChunkMessageIsRefused) {
  uavmsg::mission_upload_t m = ToMessage(SplitMission(BigMission(20), 1)[0]);
  m.num_items = 13;
  EXPECT_THROW(FromMessage(m), std::invalid_argument);
}

}  // namespace
}  // namespace uav::waypoints
