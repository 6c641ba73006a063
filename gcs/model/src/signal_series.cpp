#include "uav/gcs/signal_series.hpp"

#include <algorithm>

namespace uav::gcs {

void SignalSeries::Push(double t, double value) {
  const float v = static_cast<float>(value);
  std::size_t pos;
  if (t_.size() < capacity_) {
    pos = t_.size();
    t_.push_back(t);
    v_.push_back(v);
  } else {
    pos = head_;
    t_[pos] = t;
    v_[pos] = v;
    head_ = (head_ + 1) % capacity_;
  }
  const std::size_t b = pos / kBlock;
  if (b >= block_min_.size()) {
    block_min_.push_back(v);
    block_max_.push_back(v);
  } else if (pos + 1 == t_.size() && t_.size() < capacity_) {
    // Still filling: the block only grows.
    block_min_[b] = std::min(block_min_[b], v);
    block_max_[b] = std::max(block_max_[b], v);
  } else {
    // A stored sample was overwritten: recompute its block (32 reads per push).
    const std::size_t a = b * kBlock, e = std::min(a + kBlock, v_.size());
    float lo = v_[a], hi = v_[a];
    for (std::size_t k = a + 1; k < e; ++k) lo = std::min(lo, v_[k]), hi = std::max(hi, v_[k]);
    block_min_[b] = lo;
    block_max_[b] = hi;
  }
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

std::size_t SignalSeries::LowerBoundFrom(double t, std::size_t from) const {
  const std::size_t n = size();
  if (from >= n || TimeAt(from) >= t) return from;
  // TimeAt(lo) < t; find hi with TimeAt(hi) >= t (or n) by doubling steps, then bisect.
  std::size_t lo = from, step = 1, hi = from + 1;
  while (hi < n && TimeAt(hi) < t) {
    lo = hi;
    step *= 2;
    hi = std::min(n, lo + step);
  }
  ++lo;
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (TimeAt(mid) < t) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

std::size_t SignalSeries::UpperBound(double t) const {
  std::size_t lo = 0, hi = size();
  while (lo < hi) {
    const std::size_t mid = (lo + hi) / 2;
    if (TimeAt(mid) <= t) lo = mid + 1;
    else hi = mid;
  }
  return lo;
}

void SignalSeries::StoredMinMax(std::size_t a, std::size_t b, float* lo, float* hi) const {
  while (a < b && a % kBlock != 0) *lo = std::min(*lo, v_[a]), *hi = std::max(*hi, v_[a]), ++a;
  while (a + kBlock <= b) {
    *lo = std::min(*lo, block_min_[a / kBlock]);
    *hi = std::max(*hi, block_max_[a / kBlock]);
    a += kBlock;
  }
  while (a < b) *lo = std::min(*lo, v_[a]), *hi = std::max(*hi, v_[a]), ++a;
}

void SignalSeries::MinMax(std::size_t i, std::size_t j, float* lo, float* hi) const {
  *lo = v_[Index(i)];
  *hi = *lo;
  const std::size_t a = Index(i), b = Index(j - 1) + 1;
  if (a < b) {
    StoredMinMax(a, b, lo, hi);
  } else {  // wraps around the end of the storage
    StoredMinMax(a, v_.size(), lo, hi);
    StoredMinMax(0, b, lo, hi);
  }
}

}  // namespace uav::gcs
