#include "uav/waypoints/mission_transfer.hpp"

#include <cstring>

namespace uav::waypoints {
namespace {

class Fnv1a {
 public:
  void Add(const void* data, std::size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (std::size_t i = 0; i < n; ++i) h_ = (h_ ^ p[i]) * 1099511628211ULL;
  }
  void Add(double v) { Add(&v, sizeof v); }
  void Add(int64_t v) { Add(&v, sizeof v); }
  uint64_t value() const { return h_; }

 private:
  uint64_t h_ = 1469598103934665603ULL;
};

}  // namespace

uint64_t MissionDigest(const Mission& m) {
  Fnv1a h;
  h.Add(m.home.latitude_deg), h.Add(m.home.longitude_deg), h.Add(m.home.altitude_m);
  h.Add(m.cruise_speed_m_s);
  h.Add(static_cast<int64_t>(m.items.size()));
  for (const auto& it : m.items) {
    h.Add(static_cast<int64_t>(it.command)), h.Add(static_cast<int64_t>(it.frame));
    for (double p : it.param) h.Add(p);
    h.Add(it.latitude_deg), h.Add(it.longitude_deg), h.Add(it.altitude_m);
    h.Add(static_cast<int64_t>(it.autocontinue));
  }
  return h.value();
}

std::vector<MissionChunk> SplitMission(const Mission& m, int64_t upload_id) {
  std::vector<MissionChunk> out;
  const uint64_t digest = MissionDigest(m);
  const int total = static_cast<int>(m.items.size());
  for (int first = 0; first < total; first += kItemsPerChunk) {
    MissionChunk c;
    c.upload_id = upload_id;
    c.total_items = total;
    c.first_index = first;
    c.items.assign(m.items.begin() + first, m.items.begin() + std::min(total, first + kItemsPerChunk));
    c.home = m.home;
    c.cruise_speed_m_s = m.cruise_speed_m_s;
    c.digest = digest;
    out.push_back(std::move(c));
  }
  return out;
}

MissionUploadAck MissionAssembler::Receive(const MissionChunk& c,
                                           const std::function<std::string(const Mission&)>& accept) {
  MissionUploadAck ack;
  ack.upload_id = c.upload_id;
  ack.total_items = c.total_items;
  ack.digest = c.digest;
  auto reject = [&](const std::string& why) {
    ack.result = MissionUploadAck::Result::kRejected;
    ack.reason = why;
    upload_id_ = -1;
    finished_ = ack;
    return ack;
  };
  if (finished_ && finished_->upload_id == c.upload_id) return *finished_;  // repeated last chunk
  if (c.upload_id != upload_id_) {
    // A new upload replaces whatever was half-received.
    if (c.first_index != 0) {
      ack.received_items = 0;  // ask for the start
      return ack;
    }
    upload_id_ = c.upload_id;
    mission_ = Mission{};
    mission_.home = c.home;
    mission_.cruise_speed_m_s = c.cruise_speed_m_s;
    total_ = c.total_items;
    finished_.reset();
    if (total_ <= 0 || static_cast<std::size_t>(total_) > kMaxMissionItems)
      return reject("mission has " + std::to_string(total_) + " items (1 to " + std::to_string(kMaxMissionItems) + " allowed)");
  }
  if (c.total_items != total_) return reject("chunks disagree on the item count");
  const int have = static_cast<int>(mission_.items.size());
  if (c.first_index == have && !c.items.empty() && have + static_cast<int>(c.items.size()) <= total_)
    mission_.items.insert(mission_.items.end(), c.items.begin(), c.items.end());
  // Anything else is a duplicate or out of order: answer with what we hold.
  ack.received_items = static_cast<int>(mission_.items.size());
  if (ack.received_items < total_) return ack;
  if (MissionDigest(mission_) != c.digest)
    return reject("mission arrived corrupted (digest mismatch); upload again");
  const std::string why = accept(mission_);
  if (!why.empty()) return reject(why);
  ack.result = MissionUploadAck::Result::kAccepted;
  upload_id_ = -1;
  finished_ = ack;
  return ack;
}

MissionUploader::MissionUploader(const Mission& m, int64_t upload_id)
    : mission_(m), chunks_(SplitMission(m, upload_id)), upload_id_(upload_id),
      total_(static_cast<int>(m.items.size())), digest_(MissionDigest(m)) {}

std::vector<MissionChunk> MissionUploader::Tick(double now) {
  if (state_ != State::kSending || next_ >= chunks_.size()) return {};
  if (now - last_sent_ < kResendTimeout) return {};
  if (tries_ >= kMaxTries) {
    state_ = State::kFailed;
    reason_ = "no answer from the vehicle after " + std::to_string(kMaxTries) + " tries of item " +
              std::to_string(chunks_[next_].first_index);
    return {};
  }
  ++tries_;
  last_sent_ = now;
  return {chunks_[next_]};
}

void MissionUploader::OnAck(const MissionUploadAck& ack, double now) {
  if (state_ != State::kSending || ack.upload_id != upload_id_) return;
  if (ack.result == MissionUploadAck::Result::kRejected) {
    state_ = State::kRejected;
    reason_ = ack.reason;
    return;
  }
  if (ack.result == MissionUploadAck::Result::kAccepted) {
    if (ack.digest != digest_) {
      state_ = State::kFailed;
      reason_ = "vehicle accepted a different mission (digest mismatch)";
      return;
    }
    acked_ = total_;
    state_ = State::kAccepted;
    return;
  }
  acked_ = ack.received_items;
  // Send the chunk that starts where the vehicle is, at once.
  const std::size_t want = static_cast<std::size_t>(ack.received_items / kItemsPerChunk);
  if (want != next_ && want < chunks_.size()) {
    next_ = want;
    tries_ = 0;
    last_sent_ = now - kResendTimeout;
  }
}

}  // namespace uav::waypoints
