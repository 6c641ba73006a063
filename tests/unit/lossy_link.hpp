#pragma once
// The relay the link tests share: messages in flight with a delivery time; each may be lost,
// duplicated or delayed (so reordered), and the link can be cut.
#include <cstdint>
#include <deque>
#include <random>
#include <utility>

namespace uav {

template <class T>
class LossyLink {
 public:
  LossyLink(double loss, double duplicate, double max_delay_s, uint32_t seed)
      : loss_(loss), duplicate_(duplicate), max_delay_s_(max_delay_s), rng_(seed) {}
  void Send(const T& m, double now) {
    if (cut_) return;
    std::uniform_real_distribution<double> u(0, 1);
    if (u(rng_) < loss_) return;
    queue_.push_back({now + u(rng_) * max_delay_s_, m});
    if (u(rng_) < duplicate_) queue_.push_back({now + u(rng_) * max_delay_s_, m});
  }
  template <class F>
  void Deliver(double now, F&& f) {
    std::deque<std::pair<double, T>> later;
    for (auto& [t, m] : queue_) {
      if (t <= now) f(m);
      else later.emplace_back(t, std::move(m));
    }
    queue_.swap(later);
  }
  void Cut(bool cut) {
    cut_ = cut;
    if (cut) queue_.clear();
  }

 private:
  double loss_, duplicate_, max_delay_s_;
  std::mt19937 rng_;
  std::deque<std::pair<double, T>> queue_;
  bool cut_ = false;
};

}  // namespace uav
