#pragma once
// Simulated clock in lockstep with the onboard threads (thesis Table 2.1). Each worker is a real
// thread; at each tick the workers that are due run stage by stage (IMU before CTL before SVO
// ...), so a run is deterministic however the OS schedules the threads. The clock is paced to
// wall time (times a speed factor) or runs as fast as the threads finish.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace uav::app {

class LockstepScheduler {
 public:
  struct Options {
    int64_t start_utime = 0;      // [us] simulated clock at start
    int64_t step_us = 2000;       // [us] physics step; worker periods must be multiples of it
    double speed = 1.0;           // sim seconds per wall second; <= 0 runs as fast as possible
    int64_t duration_us = 0;      // [us] stop after this much simulated time; 0 = until Stop()
  };

  explicit LockstepScheduler(const Options& options);
  ~LockstepScheduler();
  LockstepScheduler(const LockstepScheduler&) = delete;
  LockstepScheduler& operator=(const LockstepScheduler&) = delete;

  // Starts a thread named `name` that runs `work(utime)` every `period_us` of simulated time,
  // `phase_us` after the start and every period from there. All workers of stage s finish a
  // tick before any worker of stage s+1 starts it.
  void AddWorker(const std::string& name, int stage, int64_t period_us,
                 std::function<void(int64_t utime)> work, int64_t phase_us = 0);

  // Drives the clock on the calling thread: per step, due workers then `physics(dt_us)`.
  // Returns when the duration has elapsed or Stop() was called.
  void Run(const std::function<void(int64_t dt_us)>& physics);

  // Thread-safe; may be called from a signal-handling thread.
  void Stop() { stop_.store(true); }
  int64_t now() const { return now_.load(); }

 private:
  struct Worker;
  void RunStage(const std::vector<Worker*>& due, int64_t utime);

  Options options_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> now_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool shutting_down_ = false;
  std::vector<std::unique_ptr<Worker>> workers_;
};

}  // namespace uav::app
