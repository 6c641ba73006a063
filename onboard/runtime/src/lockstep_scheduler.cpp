#include "uav/runtime/lockstep_scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <stdexcept>

#include <pthread.h>

namespace uav::runtime {

struct LockstepScheduler::Worker {
  std::string name;
  int stage;
  int64_t period_us;
  int64_t phase_us;
  std::function<void(int64_t)> work;
  std::thread thread;
  uint64_t go_generation = 0;    // incremented by the driver to release the worker
  std::atomic<uint64_t> done_generation{0};  // set by the worker when it has finished that release
  int64_t utime = 0;
  // Its own wake-up: releasing a stage wakes only the workers that are due, not every thread
  // (a shared condition variable woke all six threads four times per period).
  std::condition_variable go;
  // Wall-clock periods between releases, in 0.1 ms bins up to 200 ms (under stats_mutex_).
  std::chrono::steady_clock::time_point last_release{};
  std::vector<uint32_t> period_bins = std::vector<uint32_t>(2001, 0);
  double period_max_ms = 0.0;
};

struct LockstepScheduler::Vision {
  std::string name;
  VisionTiming timing;
  VisionJob job;
  std::thread thread;
  std::condition_variable wake;
  bool go = false;                 // a frame handed to the thread (under mutex_)
  std::atomic<bool> done{false};   // its work has returned (set under mutex_)
  double compute_ms = 0.0;         // of the work that just returned (written before done) ...
  double capture_ms = 0.0;         // ... and of it, its camera's capture
  // The clock thread's.
  int64_t visible_utime = 0;       // fixed latency: when the result is due
  // Under stats_mutex_ (written by the clock thread, read by VisionHealth).
  bool in_flight = false;
  bool late = false;               // the clock gave up waiting for it: stalled
  int64_t capture_utime = 0;
  int64_t first_offer_utime = -1;
  int decimation = 1;              // frames offered: every decimation-th of the camera's
  int64_t frames_due = 0;          // the camera's frames so far
  int64_t results = 0, dropped = 0;
  std::deque<int64_t> result_utimes;  // the last 2 s
  std::deque<double> latency_ms, compute_ms_recent, capture_ms_recent;  // the last 64
};

double& CaptureMsOfThisThread() {
  thread_local double capture_ms = 0.0;
  return capture_ms;
}
double TakeCaptureMs() {
  const double taken = CaptureMsOfThisThread();
  CaptureMsOfThisThread() = 0.0;
  return taken;
}

namespace {
// Rates are counted over the last 2 s, or the last 5 frames asked for where that is longer (a
// rate lowered to 1 Hz counted over 2 s would read 0.5, 1 or 1.5 by chance of phase).
constexpr int64_t kRateWindowUs = 2'000'000, kKeepResultsUs = 20'000'000;
constexpr std::size_t kRecent = 64;

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(std::ceil(q * v.size())) - (q > 0 ? 1 : 0))];
}
}  // namespace

LockstepScheduler::LockstepScheduler(const Options& options)
    : options_(options), now_(options.start_utime) {
  if (options.step_us <= 0) throw std::invalid_argument("scheduler step must be positive");
}

LockstepScheduler::~LockstepScheduler() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    shutting_down_ = true;
  }
  for (auto& w : workers_) w->go.notify_all();
  for (auto& v : vision_) v->wake.notify_all();
  for (auto& w : workers_)
    if (w->thread.joinable()) w->thread.join();
  for (auto& v : vision_) {
    if (!v->thread.joinable()) continue;
    // A worker still inside its work after Run's last wait has hung: it cannot be joined, and
    // the process is ending. It is left to the exit (its state is never freed).
    if (v->in_flight && !v->done.load(std::memory_order_acquire)) {
      v->thread.detach();
      v.release();  // NOLINT: deliberately leaked, the hung thread still refers to it
      continue;
    }
    v->thread.join();
  }
}

void LockstepScheduler::AddVisionWorker(const std::string& name, const VisionTiming& timing, VisionJob job) {
  if (timing.period_us <= 0 || timing.period_us % options_.step_us != 0)
    throw std::invalid_argument("vision worker '" + name + "': period must be a positive multiple of the step");
  if (timing.phase_us < 0 || timing.phase_us >= timing.period_us || timing.phase_us % options_.step_us != 0)
    throw std::invalid_argument("vision worker '" + name + "': phase must be a multiple of the step below the period");
  if (timing.latency_us < 0 || timing.stall_us <= 0)
    throw std::invalid_argument("vision worker '" + name + "': latency must be >= 0 and the stall time positive");
  auto v = std::make_unique<Vision>();
  v->name = name;
  v->timing = timing;
  v->job = std::move(job);
  Vision* raw = v.get();
  v->thread = std::thread([this, raw] {
    pthread_setname_np(pthread_self(), raw->name.substr(0, 15).c_str());
    for (;;) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        raw->wake.wait(lock, [&] { return shutting_down_ || raw->go; });
        if (shutting_down_) return;
        raw->go = false;
      }
      const auto started = std::chrono::steady_clock::now();
      TakeCaptureMs();
      raw->job.work();
      raw->compute_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
      raw->capture_ms = TakeCaptureMs();
      {
        std::lock_guard<std::mutex> lock(mutex_);
        raw->done.store(true, std::memory_order_release);
      }
      vision_done_.notify_all();
    }
  });
  vision_.push_back(std::move(v));
}

void LockstepScheduler::PublishDue(Vision& v, int64_t utime) {
  bool late;
  {
    std::lock_guard<std::mutex> stats(stats_mutex_);
    if (!v.in_flight) return;
    late = v.late;
  }
  const bool fixed = v.timing.latency_us > 0 && !late;
  if (fixed) {
    if (utime < v.visible_utime) return;
    if (!v.done.load(std::memory_order_acquire)) {
      // Due and not done: the simulated clock waits (that is what keeps a run repeatable), but
      // not for ever: a worker that hangs must not take the vehicle with it.
      std::unique_lock<std::mutex> lock(mutex_);
      if (!vision_done_.wait_for(lock, std::chrono::microseconds(options_.late_wait_wall_us),
                                 [&] { return v.done.load(std::memory_order_acquire); })) {
        lock.unlock();
        std::lock_guard<std::mutex> stats(stats_mutex_);
        v.late = true;
        return;
      }
    }
  } else if (!v.done.load(std::memory_order_acquire)) {
    return;
  }
  v.job.publish();
  v.done.store(false, std::memory_order_relaxed);
  std::lock_guard<std::mutex> stats(stats_mutex_);
  const double latency_ms = ((fixed ? v.visible_utime : utime) - v.capture_utime) * 1e-3;
  v.latency_ms.push_back(latency_ms);
  v.compute_ms_recent.push_back(v.compute_ms);
  v.capture_ms_recent.push_back(v.capture_ms);
  if (v.latency_ms.size() > kRecent) v.latency_ms.pop_front();
  if (v.compute_ms_recent.size() > kRecent) v.compute_ms_recent.pop_front();
  if (v.capture_ms_recent.size() > kRecent) v.capture_ms_recent.pop_front();
  v.result_utimes.push_back(utime);
  ++v.results;
  v.in_flight = false;
  v.late = false;
}

void LockstepScheduler::OfferFrame(Vision& v, int64_t utime) {
  {
    std::lock_guard<std::mutex> stats(stats_mutex_);
    if (v.first_offer_utime < 0) v.first_offer_utime = utime;
    if (v.frames_due++ % v.decimation != 0) return;  // not asked for: the rate was lowered on purpose
    if (v.in_flight) {
      v.dropped += v.timing.drops_frames;
      return;
    }
  }
  v.job.begin(utime);
  v.visible_utime = utime + v.timing.latency_us;
  {
    std::lock_guard<std::mutex> stats(stats_mutex_);
    v.in_flight = true;
    v.capture_utime = utime;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    v.go = true;
  }
  v.wake.notify_one();
}

void LockstepScheduler::SetDecimation(const std::string& name, int decimation) {
  if (decimation < 1) throw std::invalid_argument("vision worker '" + name + "': decimation must be at least 1");
  std::lock_guard<std::mutex> stats(stats_mutex_);
  for (auto& v : vision_)
    if (v->name == name) {
      v->decimation = decimation;
      v->frames_due = 0;  // the next frame is taken
      return;
    }
  throw std::invalid_argument("no vision worker '" + name + "'");
}

std::vector<SensingWorker> LockstepScheduler::VisionHealth() const {
  std::lock_guard<std::mutex> stats(stats_mutex_);
  const int64_t now = now_.load();
  std::vector<SensingWorker> out;
  for (const auto& v : vision_) {
    SensingWorker h;
    h.name = v->name;
    h.rig = v->timing.rig;
    h.camera_rate_hz = v->timing.drops_frames ? 1e6 / v->timing.period_us : 0.0;
    h.configured_rate_hz = h.camera_rate_hz / v->decimation;
    const int64_t full_window =
        h.configured_rate_hz > 0
            ? std::clamp(static_cast<int64_t>(5e6 / h.configured_rate_hz), kRateWindowUs, kKeepResultsUs)
            : kRateWindowUs;
    const int64_t window = std::min(full_window, v->first_offer_utime < 0 ? 0 : now - v->first_offer_utime);
    const auto recent = std::count_if(v->result_utimes.begin(), v->result_utimes.end(),
                                      [&](int64_t t) { return t > now - full_window; });
    h.rate_hz = window > 0 ? recent * 1e6 / window : 0.0;
    const std::vector<double> latency(v->latency_ms.begin(), v->latency_ms.end());
    h.latency_p50_ms = Percentile(latency, 0.5);
    h.latency_p99_ms = Percentile(latency, 0.99);
    h.compute_p50_ms = Percentile({v->compute_ms_recent.begin(), v->compute_ms_recent.end()}, 0.5);
    h.capture_p50_ms = Percentile({v->capture_ms_recent.begin(), v->capture_ms_recent.end()}, 0.5);
    h.results = v->results;
    h.dropped = v->dropped;
    char reason[160] = "";
    const double waiting_s = (now - v->capture_utime) * 1e-6;
    if (v->in_flight && (v->late || now - v->capture_utime > v->timing.stall_us)) {
      std::snprintf(reason, sizeof reason, "stalled: no result %.1f s after its frame", waiting_s);
    } else if (h.configured_rate_hz > 0 && window >= full_window && h.rate_hz < 0.8 * h.configured_rate_hz) {
      std::snprintf(reason, sizeof reason, "behind: %.1f of %.1f Hz, %lld frames dropped", h.rate_hz,
                    h.configured_rate_hz, static_cast<long long>(h.dropped));
    }
    h.reason = reason;
    h.healthy = h.reason.empty();
    out.push_back(std::move(h));
  }
  return out;
}

PeriodStats LockstepScheduler::Period(const std::string& worker) const {
  std::lock_guard<std::mutex> stats(stats_mutex_);
  PeriodStats p;
  for (const auto& w : workers_) {
    if (w->name != worker) continue;
    int64_t n = 0;
    for (uint32_t c : w->period_bins) n += c;
    auto quantile = [&](double q) {
      int64_t below = 0;
      for (std::size_t i = 0; i < w->period_bins.size(); ++i)
        if ((below += w->period_bins[i]) >= std::ceil(q * n)) return i * 0.1;
      return w->period_max_ms;
    };
    p.samples = static_cast<int>(n);
    if (n == 0) return p;
    p.p50_ms = quantile(0.5);
    p.p99_ms = quantile(0.99);
    p.max_ms = w->period_max_ms;
  }
  return p;
}

void LockstepScheduler::AddWorker(const std::string& name, int stage, int64_t period_us,
                                  std::function<void(int64_t)> work, int64_t phase_us) {
  if (period_us <= 0 || period_us % options_.step_us != 0)
    throw std::invalid_argument("worker '" + name + "': period must be a positive multiple of the step");
  if (phase_us < 0 || phase_us >= period_us || phase_us % options_.step_us != 0)
    throw std::invalid_argument("worker '" + name + "': phase must be a multiple of the step below the period");
  auto w = std::make_unique<Worker>();
  w->name = name;
  w->stage = stage;
  w->period_us = period_us;
  w->phase_us = phase_us;
  w->work = std::move(work);
  Worker* raw = w.get();
  w->thread = std::thread([this, raw] {
    pthread_setname_np(pthread_self(), raw->name.substr(0, 15).c_str());
    uint64_t seen = 0;
    for (;;) {
      int64_t t;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        raw->go.wait(lock, [&] { return shutting_down_ || raw->go_generation != seen; });
        if (shutting_down_) return;
        seen = raw->go_generation;
        t = raw->utime;
      }
      raw->work(t);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        raw->done_generation = seen;
      }
      cv_.notify_one();  // only the driver waits on cv_
    }
  });
  workers_.push_back(std::move(w));
}

void LockstepScheduler::RunStage(const std::vector<Worker*>& due, int64_t utime) {
  {
    const auto wall = std::chrono::steady_clock::now();
    std::lock_guard<std::mutex> stats(stats_mutex_);
    for (Worker* w : due) {
      if (w->last_release != std::chrono::steady_clock::time_point{}) {
        const double ms = std::chrono::duration<double, std::milli>(wall - w->last_release).count();
        ++w->period_bins[std::min<std::size_t>(w->period_bins.size() - 1, static_cast<std::size_t>(std::lround(ms * 10)))];
        w->period_max_ms = std::max(w->period_max_ms, ms);
      }
      w->last_release = wall;
    }
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (Worker* w : due) {
      w->utime = utime;
      ++w->go_generation;
    }
  }
  for (Worker* w : due) w->go.notify_one();
  // Most stages take tens of microseconds: poll for them briefly before sleeping, which saves
  // the driver a futex sleep and wake-up per stage (most of the cost at hundreds of times real
  // time). go_generation only changes under the mutex on this thread, so reading it is safe.
  auto all_done = [&] {
    return std::all_of(due.begin(), due.end(), [](const Worker* w) {
      return w->done_generation.load(std::memory_order_acquire) == w->go_generation;
    });
  };
  const auto spin_until = std::chrono::steady_clock::now() + std::chrono::microseconds(200);
  while (!all_done() && std::chrono::steady_clock::now() < spin_until) {
#if defined(__x86_64__)
    __builtin_ia32_pause();
#endif
  }
  std::unique_lock<std::mutex> lock(mutex_);
  cv_.wait(lock, all_done);
}

void LockstepScheduler::Run(const std::function<void(int64_t)>& physics) {
  std::map<int, std::vector<Worker*>> stages;
  for (auto& w : workers_) stages[w->stage].push_back(w.get());
  const auto wall_start = std::chrono::steady_clock::now();
  const int64_t t0 = options_.start_utime;
  int64_t t = t0;
  std::vector<Worker*> due;
  while (!stop_.load()) {
    if (options_.duration_us > 0 && t - t0 >= options_.duration_us) break;
    for (auto& v : vision_) PublishDue(*v, t);
    for (auto& [stage, members] : stages) {
      due.clear();
      for (Worker* w : members)
        if ((t - t0) % w->period_us == w->phase_us) due.push_back(w);
      if (!due.empty()) RunStage(due, t);
    }
    for (auto& v : vision_)
      if ((t - t0) % v->timing.period_us == v->timing.phase_us) OfferFrame(*v, t);
    {
      std::lock_guard<std::mutex> stats(stats_mutex_);
      for (auto& v : vision_)
        while (!v->result_utimes.empty() && v->result_utimes.front() <= t - kKeepResultsUs) v->result_utimes.pop_front();
    }
    physics(options_.step_us);
    t += options_.step_us;
    now_.store(t);
    if (options_.speed > 0.0) {
      const auto target = wall_start + std::chrono::microseconds(static_cast<int64_t>(
                                           static_cast<double>(t - t0) / options_.speed));
      std::this_thread::sleep_until(target);
    }
  }
  // Work in flight finishes (a map being written is not cut off); its result is not published.
  // A worker that hangs is not waited for longer than kExitWaitWall: the vehicle must still stop.
  std::unique_lock<std::mutex> lock(mutex_);
  vision_done_.wait_for(lock, std::chrono::microseconds(kExitWaitWallUs), [&] {
    // in_flight is written only on this thread.
    return std::all_of(vision_.begin(), vision_.end(), [](const std::unique_ptr<Vision>& v) {
      return !v->in_flight || v->done.load(std::memory_order_acquire);
    });
  });
}

}  // namespace uav::runtime
