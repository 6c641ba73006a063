#pragma once
// Which messages are spoken (QGroundControl speaks its warnings): every warning and error of the
// log, once, as "UAV1: <text>". A burst is not read out line by line: past kMaxPerTake the rest
// are counted ("UAV1: 4 more warnings"), and a text said in the last kRepeatAfter seconds is not
// said again. The model only decides; the platform's Speaker says it.
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "uav/gcs/message_log.hpp"

namespace uav::gcs {

class SpokenAlerts {
 public:
  static constexpr int kMaxPerTake = 2;
  static constexpr double kRepeatAfter = 30.0;  // [s]
  // The sentences to say for the lines added to `log` since the last call.
  std::vector<std::string> Take(const MessageLog& log, double now);

 private:
  std::size_t seen_ = 0;  // MessageLog::added() at the last call
  std::map<std::string, double> said_at_;
};

}  // namespace uav::gcs
