#pragma once
// A perception worker off the control path. As on a real vehicle, control, the INS and the
// servos never wait for vision: at each frame the clock's thread hands the worker its exposure
// time and what it needs from the blackboard (Begin, cheap), the worker captures and computes on
// its own thread (Work), and what it writes reaches the blackboard only when its result becomes
// visible, at capture time plus its latency (LockstepScheduler::AddVisionWorker). Until then the
// rest of the vehicle acts on the previous, older result, stamped with its capture time.
#include <chrono>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "uav/runtime/blackboard.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::runtime {

// The wall time this thread spent in cameras' Capture since it was last taken [ms]: rendering in
// the simulator, decoding a recording, grabbing from a device. The scheduler takes it after each
// frame's work (TakeCaptureMs), and the sensing report gives it apart from the whole work.
double& CaptureMsOfThisThread();
double TakeCaptureMs();
// Runs `capture` (a camera's Capture) and counts its wall time as this thread's capture time.
template <class Capture>
auto TimedCapture(Capture&& capture) {
  const auto started = std::chrono::steady_clock::now();
  auto frame = capture();
  CaptureMsOfThisThread() += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started).count();
  return frame;
}

// What a worker writes during Work, applied to the blackboard in order when the result is due.
// Each write captures what it writes by value: it runs after the work that made it has returned.
class Outbox {
 public:
  void Post(std::function<void(Blackboard&)> write) { writes_.push_back(std::move(write)); }
  void PushStatus(Severity severity, std::string text) {
    Post([severity, text = std::move(text)](Blackboard& b) { b.PushStatus(severity, text); });
  }
  void ApplyTo(Blackboard& board) {
    for (auto& write : writes_) write(board);
    writes_.clear();
  }

 private:
  std::vector<std::function<void(Blackboard&)>> writes_;
};

class VisionWorker {
 public:
  explicit VisionWorker(Blackboard& board) : board_(board) {}
  virtual ~VisionWorker() = default;
  VisionWorker(const VisionWorker&) = delete;
  VisionWorker& operator=(const VisionWorker&) = delete;

  // On the clock's thread at each frame: the parameters first, when they have changed over the
  // link (the one place a worker re-reads them: ApplyParameters), then Begin.
  void BeginFrame(int64_t utime) {
    if (const auto params = board_.ParametersNewerThan(&params_version_)) ApplyParameters(*params);
    Begin(utime);
  }
  // Takes the settings that may change in flight (ParamApply::kInFlight) from `params`, on the
  // clock's thread between frames. By default the worker has none.
  virtual void ApplyParameters(const ParameterSet& params) {}
  // The parameters' version it last took (0: those it was built with).
  int64_t params_version() const { return params_version_; }

  // On the clock's thread at the exposure `utime`: takes from the blackboard what the work needs
  // (the estimate then, the requests and inputs waiting). Must be cheap: control waits for it.
  // By default: the exposure's time and the blackboard then.
  virtual void Begin(int64_t utime) {
    utime_ = utime;
    at_begin_ = board_.Snapshot();
  }
  // On the worker's own thread: the camera's images and the algorithm. Writes go to `out`.
  virtual void Work(Outbox& out) = 0;

  // Begin, Work and apply at once, with no latency: for tests and tools that own the clock.
  void Tick(int64_t utime) {
    BeginFrame(utime);
    Outbox out;
    Work(out);
    out.ApplyTo(board_);
  }
  Blackboard& board() { return board_; }

 protected:
  Blackboard& board_;
  int64_t utime_ = 0;        // of the frame Begin took
  BlackboardData at_begin_;  // the blackboard then

 private:
  int64_t params_version_ = 0;
};

}  // namespace uav::runtime
