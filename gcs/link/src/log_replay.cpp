#include "uav/gcs/log_replay.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "uav/gcs/gcs_link.hpp"

namespace uav::gcs {
namespace {

// LCM's event framing (lcm eventlog): sync word, event number, timestamp, channel length, data
// length, channel, data.
constexpr int64_t kEventHeaderBytes = 4 + 8 + 8 + 4 + 4;

bool IsStateChannel(const std::string& channel) {
  const std::string suffix = "/STATE";
  return channel.size() > suffix.size() && channel.compare(channel.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// vehicle_state_t.utime: the first field, after LCM's 8-byte type fingerprint, big-endian.
bool ReadUtime(const lcm::LogEvent& e, int64_t* utime) {
  if (e.datalen < 16) return false;
  const auto* b = static_cast<const uint8_t*>(e.data) + 8;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | b[i];
  *utime = static_cast<int64_t>(v);
  return true;
}

}  // namespace

LogReplay::LogReplay(const std::string& path, std::function<GcsLink&()> reset)
    : path_(path), reset_(std::move(reset)), link_(&reset_()) {
  std::error_code ec;
  const auto size = static_cast<int64_t>(std::filesystem::file_size(path, ec));
  if (ec) throw std::runtime_error("cannot read the event log '" + path + "': " + ec.message());
  file_ = std::make_unique<lcm::LogFile>(path, "r");
  if (!file_->good()) throw std::runtime_error("cannot open the event log '" + path + "'");
  std::FILE* f = file_->getFilePtr();
  // Index: each event's offset and its vehicle time (the newest STATE utime at or before it).
  std::vector<double> vehicle_t;
  double newest = -std::numeric_limits<double>::infinity();
  double first_state = std::numeric_limits<double>::quiet_NaN();
  for (;;) {
    const int64_t offset = ftello(f);
    const lcm::LogEvent* e = file_->readNextEvent();
    const int64_t end = ftello(f);
    if (!e) {
      if (offset < size)
        damage_ = "byte " + std::to_string(offset) + " of " + std::to_string(size) + " (after event " +
                  std::to_string(events_.size()) + "): the log is truncated or damaged there; replayed up to it";
      break;
    }
    if (end - offset != kEventHeaderBytes + static_cast<int64_t>(e->channel.size()) + e->datalen) {
      // LCM skipped bytes to find the next sync word: damage. Stop before it.
      damage_ = "byte " + std::to_string(offset) + " of " + std::to_string(size) + " (after event " +
                std::to_string(events_.size()) + "): damaged bytes; replayed up to them";
      break;
    }
    int64_t utime = 0;
    if (IsStateChannel(e->channel) && ReadUtime(*e, &utime) && utime > 0) {
      newest = std::max(newest, utime * 1e-6);
      if (std::isnan(first_state)) first_state = newest;
    }
    events_.push_back({offset, 0.0});
    vehicle_t.push_back(newest);
  }
  if (events_.empty())
    throw std::runtime_error("the event log '" + path + "' holds no readable event" +
                             (damage_.empty() ? "" : ": damaged at " + damage_));
  if (std::isnan(first_state)) first_state = 0.0;  // no vehicle state at all: one instant
  start_ = first_state;
  for (std::size_t i = 0; i < events_.size(); ++i)
    events_[i].t = std::isfinite(vehicle_t[i]) ? vehicle_t[i] - start_ : 0.0;
  duration_ = events_.back().t;
  fseeko(f, events_.front().offset, SEEK_SET);
}

LogReplay::~LogReplay() = default;

bool LogReplay::SetSpeed(double speed) {
  if (!std::isfinite(speed) || speed < kMinSpeed || speed > kMaxSpeed) return false;
  speed_ = speed;
  return true;
}

int LogReplay::Advance(double wall_seconds) {
  const std::size_t before = next_;
  if (!paused_ && wall_seconds > 0) position_ = std::min(duration_, position_ + wall_seconds * speed_);
  DispatchUpTo(position_);
  return static_cast<int>(next_ - before);
}

void LogReplay::Seek(double t) {
  if (!std::isfinite(t)) return;
  t = std::clamp(t, 0.0, duration_);
  if (t < position_ || (next_ > 0 && events_[next_ - 1].t > t)) {
    link_ = &reset_();  // the model holds everything up to now: start it again
    next_ = 0;
    fseeko(file_->getFilePtr(), events_.front().offset, SEEK_SET);
  }
  position_ = t;
  DispatchUpTo(t);
}

void LogReplay::DispatchUpTo(double t) {
  std::FILE* f = file_->getFilePtr();
  while (next_ < events_.size() && events_[next_].t <= t) {
    if (ftello(f) != events_[next_].offset) fseeko(f, events_[next_].offset, SEEK_SET);
    const lcm::LogEvent* e = file_->readNextEvent();
    if (!e) break;  // the index said it was there: the file changed under us
    link_->Dispatch(e->channel, e->data, e->datalen, start_ + events_[next_].t);
    ++next_;
  }
}

}  // namespace uav::gcs
