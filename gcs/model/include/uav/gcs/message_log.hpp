#pragma once
// The Messages panel's log: the vehicles' status texts and the GCS's own notes, newest last.
#include <cstddef>
#include <deque>
#include <string>

#include "uav/shared/vehicle_enums.hpp"

namespace uav::gcs {

struct LogLine {
  double t;  // GCS clock
  std::string vehicle_id;
  std::string text;
  Severity severity;
};

class MessageLog {
 public:
  static constexpr std::size_t kMaxLines = 500;
  void Add(double now, const std::string& vehicle, const std::string& text, Severity severity) {
    lines_.push_back({now, vehicle, text, severity});
    ++added_;
    while (lines_.size() > kMaxLines) lines_.pop_front();
  }
  const std::deque<LogLine>& lines() const { return lines_; }
  std::size_t added() const { return added_; }  // lines ever added (the oldest are dropped past kMaxLines)

 private:
  std::deque<LogLine> lines_;
  std::size_t added_ = 0;
};

}  // namespace uav::gcs
