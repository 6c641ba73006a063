#pragma once
// History of one telemetry signal: a ring buffer of (time, value) that keeps the newest
// `capacity` samples (default 30 minutes at 50 Hz), with the min and max of every block of 32
// stored samples so that a plot column's range costs a few block reads, not a scan.
#include <cstddef>
#include <vector>

namespace uav::gcs {

class SignalSeries {
 public:
  static constexpr std::size_t kDefaultCapacity = 30 * 60 * 50;
  explicit SignalSeries(std::size_t capacity = kDefaultCapacity) : capacity_(capacity) {}

  void Push(double t, double value);
  std::size_t size() const { return t_.size() < capacity_ ? t_.size() : capacity_; }
  bool empty() const { return t_.empty(); }
  // i = 0 is the oldest sample kept.
  double TimeAt(std::size_t i) const { return t_[Index(i)]; }
  double ValueAt(std::size_t i) const { return v_[Index(i)]; }
  double LastTime() const { return TimeAt(size() - 1); }
  double LastValue() const { return ValueAt(size() - 1); }
  // First sample index with time >= t, and with time > t (binary search; times non-decreasing).
  std::size_t LowerBound(double t) const;
  std::size_t UpperBound(double t) const;
  // LowerBound(t) for t at or after sample `from`'s time: gallops forward from it, so walking a
  // window column by column costs O(log step) per column, not O(log n).
  std::size_t LowerBoundFrom(double t, std::size_t from) const;
  // Min and max value of samples [i, j) (i < j <= size()).
  void MinMax(std::size_t i, std::size_t j, float* lo, float* hi) const;

 private:
  static constexpr std::size_t kBlock = 32;
  std::size_t Index(std::size_t i) const {
    if (t_.size() < capacity_) return i;
    const std::size_t k = head_ + i;
    return k < capacity_ ? k : k - capacity_;
  }
  // Min/max over stored positions [a, b) (no wrap).
  void StoredMinMax(std::size_t a, std::size_t b, float* lo, float* hi) const;
  std::size_t capacity_;
  std::size_t head_ = 0;  // oldest element once full
  std::vector<double> t_;
  std::vector<float> v_;
  std::vector<float> block_min_, block_max_;  // per kBlock stored positions
};

}  // namespace uav::gcs
