#pragma once
// Simulated clock in lockstep with the onboard threads (thesis Table 2.1). Each worker is a real
// thread; at each tick the workers that are due run stage by stage (IMU before CTL before SVO
// ...), so a run is deterministic however the OS schedules the threads. The clock is paced to
// wall time (times a speed factor) or runs as fast as the threads finish.
//
// Vision workers are off this path: the clock hands each its frame and never waits for the work
// while the result is not yet due. A frame that comes while its worker is busy is dropped and
// counted, as a camera driver does. A result becomes visible at capture time plus a latency:
// fixed (deterministic on a simulated clock: the clock waits for a late result at its due time,
// at most Options::late_wait_wall_us, then carries on and calls the worker stalled) or measured
// (visible at the first tick after the work is done: real time).
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "uav/shared/sensing.hpp"

namespace uav::runtime {

struct VisionTiming {
  int64_t period_us = 0;           // a frame every period (a multiple of the step) ...
  int64_t phase_us = 0;            // ... this long after the start
  int64_t latency_us = 0;          // > 0: visible this long after capture; 0: when done (measured)
  bool drops_frames = true;        // false: its input waits in a queue, a busy tick loses nothing
  int64_t stall_us = 1'000'000;    // no result this long after its frame: stalled (unhealthy)
  std::string rig;                 // the camera or pair, for the health report
};

// The three steps of a vision worker's frame (VisionWorker::Begin / Work / the outbox applied).
struct VisionJob {
  std::function<void(int64_t utime)> begin;  // on the clock's thread at the frame's time
  std::function<void()> work;                // on the worker's thread
  std::function<void()> publish;             // on the clock's thread when the result is due
};

struct PeriodStats {
  double p50_ms = 0.0, p99_ms = 0.0, max_ms = 0.0;
  int samples = 0;
};

class LockstepScheduler {
 public:
  struct Options {
    int64_t start_utime = 0;      // [us] simulated clock at start
    int64_t step_us = 2000;       // [us] physics step; worker periods must be multiples of it
    double speed = 1.0;           // sim seconds per wall second; <= 0 runs as fast as possible
    int64_t duration_us = 0;      // [us] stop after this much simulated time; 0 = until Stop()
    // [us] wall time the clock waits for a fixed-latency result that is due and not done before
    // calling its worker stalled. Long: a loaded machine must not be taken for a hung worker (the
    // simulated vehicle does not move while the clock waits), or runs would not repeat.
    int64_t late_wait_wall_us = 10'000'000;
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

  // Starts a thread named `name` for a vision worker (see the top of this file). Its frames are
  // taken after the tick's stages, so Begin reads the estimate of that tick.
  void AddVisionWorker(const std::string& name, const VisionTiming& timing, VisionJob job);

  // Offers `name` only every `decimation`-th frame of its camera (1: every frame): the vehicle
  // lowers a rate on purpose where the CPU cannot hold it (Sensing::Monitor). Thread-safe.
  void SetDecimation(const std::string& name, int decimation);

  // The vision workers' health now (thread-safe), and the wall-clock period of `worker`'s
  // releases over the run (the control loop's: "CTL").
  std::vector<SensingWorker> VisionHealth() const;
  PeriodStats Period(const std::string& worker) const;

  // How long Run, at its end, waits for the work in flight (a map being finished) to return.
  static constexpr int64_t kExitWaitWallUs = 120'000'000;

  // Drives the clock on the calling thread: per step, due workers then `physics(dt_us)`.
  // Returns when the duration has elapsed or Stop() was called.
  void Run(const std::function<void(int64_t dt_us)>& physics);

  // Thread-safe; may be called from a signal-handling thread.
  void Stop() { stop_.store(true); }
  int64_t now() const { return now_.load(); }

 private:
  struct Worker;
  struct Vision;
  void RunStage(const std::vector<Worker*>& due, int64_t utime);
  void PublishDue(Vision& v, int64_t utime);
  void OfferFrame(Vision& v, int64_t utime);

  Options options_;
  std::atomic<bool> stop_{false};
  std::atomic<int64_t> now_;
  std::mutex mutex_;
  std::condition_variable cv_;
  bool shutting_down_ = false;
  std::vector<std::unique_ptr<Worker>> workers_;
  std::vector<std::unique_ptr<Vision>> vision_;
  mutable std::mutex stats_mutex_;  // the vision workers' figures and the release periods
  std::condition_variable vision_done_;
};

}  // namespace uav::runtime
