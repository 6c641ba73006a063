#include "uav/wire/messages.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "uavmsg/sensing_t.hpp"

namespace uav {

SensingReport FromMessage(const uavmsg::sensing_t& m) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("sensing_t: " + what); };
  auto figure = [&](float v, const char* name) {
    if (!std::isfinite(v) || v < 0) fail(std::string(name) + " is not a finite non-negative number");
    return static_cast<double>(v);
  };
  SensingReport r;
  r.utime = m.utime;
  r.measured_latency = m.measured_latency;
  r.control_period_p50_ms = figure(m.control_period_p50_ms, "control_period_p50_ms");
  r.control_period_p99_ms = figure(m.control_period_p99_ms, "control_period_p99_ms");
  r.control_period_max_ms = figure(m.control_period_max_ms, "control_period_max_ms");
  if (m.num_workers < 0 || m.num_workers > uavmsg::sensing_t::MAX_WORKERS ||
      m.workers.size() != static_cast<std::size_t>(m.num_workers))
    fail("num_workers " + std::to_string(m.num_workers) + " out of range");
  for (const uavmsg::sensing_worker_t& w : m.workers) {
    SensingWorker s;
    if (w.name.empty()) fail("a worker without a name");
    s.name = w.name;
    s.rig = w.rig;
    const std::string of = " of worker " + w.name;
    s.camera_rate_hz = figure(w.camera_rate_hz, ("camera_rate_hz" + of).c_str());
    s.configured_rate_hz = figure(w.configured_rate_hz, ("configured_rate_hz" + of).c_str());
    if (s.configured_rate_hz > s.camera_rate_hz + 1e-3) fail("configured_rate_hz above camera_rate_hz" + of);
    s.rate_hz = figure(w.rate_hz, ("rate_hz" + of).c_str());
    s.latency_p50_ms = figure(w.latency_p50_ms, ("latency_p50_ms" + of).c_str());
    s.latency_p99_ms = figure(w.latency_p99_ms, ("latency_p99_ms" + of).c_str());
    s.compute_p50_ms = figure(w.compute_p50_ms, ("compute_p50_ms" + of).c_str());
    if (w.results < 0 || w.dropped < 0) fail("negative count" + of);
    s.results = w.results;
    s.dropped = w.dropped;
    s.healthy = w.healthy;
    s.reason = w.reason;
    if (!s.healthy && s.reason.empty()) fail("worker " + w.name + " unhealthy without a reason");
    r.workers.push_back(std::move(s));
  }
  return r;
}

uavmsg::sensing_t ToMessage(const SensingReport& r) {
  uavmsg::sensing_t m{};
  m.utime = r.utime;
  m.measured_latency = r.measured_latency;
  m.control_period_p50_ms = static_cast<float>(r.control_period_p50_ms);
  m.control_period_p99_ms = static_cast<float>(r.control_period_p99_ms);
  m.control_period_max_ms = static_cast<float>(r.control_period_max_ms);
  for (const SensingWorker& s : r.workers) {
    if (m.workers.size() >= static_cast<std::size_t>(uavmsg::sensing_t::MAX_WORKERS)) break;
    uavmsg::sensing_worker_t w{};
    w.name = s.name;
    w.rig = s.rig;
    w.camera_rate_hz = static_cast<float>(s.camera_rate_hz);
    w.configured_rate_hz = static_cast<float>(s.configured_rate_hz);
    w.rate_hz = static_cast<float>(s.rate_hz);
    w.latency_p50_ms = static_cast<float>(s.latency_p50_ms);
    w.latency_p99_ms = static_cast<float>(s.latency_p99_ms);
    w.compute_p50_ms = static_cast<float>(s.compute_p50_ms);
    w.results = s.results;
    w.dropped = s.dropped;
    w.healthy = s.healthy;
    w.reason = s.reason;
    m.workers.push_back(std::move(w));
  }
  m.num_workers = static_cast<int16_t>(m.workers.size());
  return m;
}

}  // namespace uav
