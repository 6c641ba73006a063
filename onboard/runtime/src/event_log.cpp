#include "uav/runtime/event_log.hpp"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

namespace uav::runtime {

EventLog::EventLog(const std::string& dir, int64_t start_utime)
    : path_(dir + "/events_" + std::to_string(start_utime) + ".lcmlog") {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  file_ = std::make_unique<lcm::LogFile>(path_, "w");
  if (!file_->good()) throw std::runtime_error("cannot write the event log '" + path_ + "'");
}

EventLog::~EventLog() { Flush(); }

void EventLog::Write(const std::string& channel, const void* data, int size, int64_t utime) {
  lcm::LogEvent e;
  e.eventnum = events_++;
  e.timestamp = utime;
  e.channel = channel;
  e.datalen = size;
  e.data = const_cast<void*>(data);
  file_->writeEvent(&e);
}

void EventLog::Flush() {
  if (file_ && file_->getFilePtr()) std::fflush(file_->getFilePtr());
}

}  // namespace uav::runtime
