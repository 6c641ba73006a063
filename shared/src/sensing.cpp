#include "uav/shared/sensing.hpp"

#include <algorithm>

namespace uav {

// Sensing: how many vision workers run and how many are unhealthy, their drops, and the control
// loop's wall-clock period (vision must never stretch it).
const std::vector<Signal<SensingReport>>& ReportSignals<SensingReport>::Table() {
  using F = SignalFormat;
  using R = SensingReport;
  static const std::vector<Signal<R>> k = {
      {{"workers", "workers", "1", "vision workers running", F::kInteger}, [](const R& r) { return double(r.workers.size()); }},
      {{"unhealthy", "unhealthy", "1", "behind or stalled", F::kInteger}, [](const R& r) {
         return double(std::count_if(r.workers.begin(), r.workers.end(), [](const SensingWorker& w) { return !w.healthy; }));
       }},
      {{"dropped", "dropped", "1", "frames dropped, all workers", F::kInteger}, [](const R& r) {
         double n = 0;
         for (const SensingWorker& w : r.workers) n += w.dropped;
         return n;
       }},
      {{"ctl_p50", "control_period_p50_ms", "ms", "nominal 20", F::kMilliseconds}, [](const R& r) { return r.control_period_p50_ms; }},
      {{"ctl_p99", "control_period_p99_ms", "ms", "", F::kMilliseconds}, [](const R& r) { return r.control_period_p99_ms; }},
      {{"ctl_max", "control_period_max_ms", "ms", "", F::kMilliseconds}, [](const R& r) { return r.control_period_max_ms; }},
  };
  return k;
}

}  // namespace uav
