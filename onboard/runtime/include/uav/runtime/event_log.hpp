#pragma once
// DLG's LCM event log: every message on the vehicle's bus (received and its own, which LCM
// loops back) in the LCM log format, so lcm-logplayer can replay a flight and lcm-spy or the GCS
// can inspect it. Flushed on every CMM tick (20 ms), so a crash or kill -9 loses at most that.
#include <cstdint>
#include <memory>
#include <string>

namespace lcm {
class LogFile;
}

namespace uav::runtime {

class EventLog {
 public:
  // Creates DIR/events_<utime>.lcmlog. Throws std::runtime_error naming the path.
  EventLog(const std::string& dir, int64_t start_utime);
  ~EventLog();
  void Write(const std::string& channel, const void* data, int size, int64_t utime);
  void Flush();
  const std::string& path() const { return path_; }
  int64_t events() const { return events_; }

 private:
  std::string path_;
  std::unique_ptr<lcm::LogFile> file_;
  int64_t events_ = 0;
};

}  // namespace uav::runtime
