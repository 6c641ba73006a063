#pragma once
#include <chrono>
#include <cstdint>

namespace uav {

// Microseconds since the Unix epoch on the wall clock (LCM utime convention).
inline int64_t WallTimeMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Microseconds on a monotonic clock, for ages and rates measured on this machine.
inline int64_t MonotonicMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace uav
