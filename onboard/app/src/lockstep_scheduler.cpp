#include "uav/app/lockstep_scheduler.hpp"

#include <algorithm>
#include <chrono>
#include <map>
#include <stdexcept>

#include <pthread.h>

namespace uav::app {

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
};

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
  for (auto& w : workers_)
    if (w->thread.joinable()) w->thread.join();
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
    for (auto& [stage, members] : stages) {
      due.clear();
      for (Worker* w : members)
        if ((t - t0) % w->period_us == w->phase_us) due.push_back(w);
      if (!due.empty()) RunStage(due, t);
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
}

}  // namespace uav::app
