// The link's signature gate (shared/signing.hpp has the model).
#include <fstream>
#include <sstream>

#include "link_translators.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::runtime {

namespace {

constexpr int64_t kReportPeriodUs = 1'000'000;  // at most one status text a second per reason

// The newest timestamp accepted before this start, or -1 without a state file yet.
int64_t LoadNewest(const std::string& path) {
  std::ifstream in(path);
  if (!in) return -1;
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::istringstream s(text);
  int64_t v = -1;
  std::string rest;
  if (!(s >> v) || (s >> rest) || v < 0 || v > kSigningTimestampMax)
    throw std::runtime_error("signing state '" + path +
                             "' is damaged (it should hold one timestamp); remove it to start with the clock as floor");
  return v;
}

}  // namespace

std::string SignatureRefusal(SignatureVerdict v, const std::string& sender_key_id, const std::string& own_key_id) {
  std::string text = std::string("signature check: ") + SignatureVerdictName(v);
  if (v != SignatureVerdict::kBadTag || own_key_id.empty()) return text;
  // Key ids are printable hex from a well-behaved sender; anything else is shown as not given.
  const bool named = sender_key_id.size() == own_key_id.size() &&
                     sender_key_id.find_first_not_of("0123456789abcdef") == std::string::npos;
  if (!named) return text + " (the sender names no key; this vehicle holds key " + own_key_id + ")";
  if (sender_key_id != own_key_id)
    return text + ": the keys differ: the sender signs with key " + sender_key_id + ", this vehicle holds key " +
           own_key_id + " (give both the same key file)";
  return text + ": the same key (" + own_key_id + "), so the message was altered or damaged on the way";
}

SignatureGate::SignatureGate(const LinkParams& p, const std::string& vehicle_id, Blackboard& board)
    : state_file_(p.signing_state_file), board_(board) {
  if (!p.signing_key) return;
  // Floor: nothing signed before this start, nor at or before the newest accepted before it.
  int64_t floor = SigningTimestamp(WallTimeMicros());
  if (!state_file_.empty()) floor = std::max(floor, LoadNewest(state_file_));
  verifier_.emplace(*p.signing_key, vehicle_id, floor);
  key_id_ = p.signing_key->Id();
  saved_ = floor;
}

void SignatureGate::Refused(SignatureVerdict v, Topic topic, const std::string& source, const std::string& why) {
  ++rejections_;
  Pending& p = pending_[v];
  ++p.count;
  p.last = std::string(TopicName(topic)) + " from '" + source.substr(0, 64) + "'";
  p.why = why;
  const int64_t now = MonotonicMicros();
  if (p.last_report_us < 0 || now - p.last_report_us >= kReportPeriodUs) {
    board_.PushStatus(Severity::kWarning, "refused " + std::to_string(p.count) + " message" + (p.count > 1 ? "s" : "") +
                                              " (" + p.why + "), the last: " + p.last);
    p.count = 0;
    p.last_report_us = now;
  }
}

void SignatureGate::Tick() {
  const int64_t now = MonotonicMicros();
  for (auto& [v, p] : pending_) {
    if (p.count == 0 || now - p.last_report_us < kReportPeriodUs) continue;
    board_.PushStatus(Severity::kWarning, "refused " + std::to_string(p.count) + " more message" +
                                              (p.count > 1 ? "s" : "") + " (" + p.why + "), the last: " + p.last);
    p.count = 0;
    p.last_report_us = now;
  }
  // At most once a second: a crash loses less than that, and the start time is the floor anyway.
  if (now - last_save_us_ >= kReportPeriodUs) Save();
}

SignatureGate::~SignatureGate() { Save(); }

void SignatureGate::Save() {
  if (!verifier_ || state_file_.empty() || save_failed_) return;
  const int64_t newest = verifier_->newest();
  if (newest <= saved_) return;
  try {
    WriteFileAtomically(state_file_, std::to_string(newest) + "\n");
    saved_ = newest;
    last_save_us_ = MonotonicMicros();
  } catch (const std::exception& e) {
    save_failed_ = true;
    board_.PushStatus(Severity::kWarning, std::string("cannot keep the signing state: ") + e.what() +
                                              " (after a restart, the start time is the only floor)");
  }
}

}  // namespace uav::runtime
