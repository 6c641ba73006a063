#pragma once
// The estimate's positions of the last second, by time, for measurements that arrive late.
// Vision results are stamped with their exposure and reach the INS 30-150 ms later (their
// compute time): the innovation is taken against where the estimate was at the exposure and the
// correction applied to the state now. To first order the estimate's error does not change over
// the delay, while the vehicle may have moved half a metre (PX4's EKF2 does the same with its
// delayed fusion horizon).
#include <cstdint>
#include <cstdlib>
#include <deque>
#include <optional>
#include <utility>

#include <Eigen/Core>

namespace uav::nav {

class PositionHistory {
 public:
  explicit PositionHistory(int64_t keep_us = 1'000'000) : keep_us_(keep_us) {}

  void Record(int64_t utime, const Eigen::Vector3d& p_N) {
    if (!entries_.empty() && entries_.back().first > utime) entries_.clear();  // the clock went back
    if (!entries_.empty() && entries_.back().first == utime) entries_.pop_back();
    entries_.emplace_back(utime, p_N);
    while (entries_.front().first < utime - keep_us_) entries_.pop_front();
  }
  // The position recorded nearest `utime`; nullopt when none is within half a control period of it
  // (older than kept, or newer than the newest).
  static constexpr int64_t kMatchUs = 10'000;
  std::optional<Eigen::Vector3d> At(int64_t utime) const {
    std::optional<std::pair<int64_t, Eigen::Vector3d>> best;
    for (const auto& e : entries_)
      if (!best || std::llabs(e.first - utime) < std::llabs(best->first - utime)) best = e;
    if (!best || std::llabs(best->first - utime) > kMatchUs) return std::nullopt;
    return best->second;
  }

 private:
  int64_t keep_us_;
  std::deque<std::pair<int64_t, Eigen::Vector3d>> entries_;
};

}  // namespace uav::nav
