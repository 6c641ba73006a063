#include "uav/gcs/signal_series.hpp"

namespace uav::gcs {

void SignalSeries::Push(double t, double value) {
  if (t_.size() < capacity_) {
    t_.push_back(t);
    v_.push_back(static_cast<float>(value));
    return;
  }
  t_[head_] = t;
  v_[head_] = static_cast<float>(value);
  head_ = (head_ + 1) % capacity_;
}

std::size_t SignalSeries::LowerBound(double t) const {
  std::size_t lo = 0, hi = size();
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (TimeAt(mid) < t) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

}  // namespace uav::gcs
