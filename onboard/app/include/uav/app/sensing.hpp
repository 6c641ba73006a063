#pragma once
// The vehicle's sensing: the scene's simulated cameras and the vision workers the vehicle file
// puts on them, each a thread off the control path (vision_worker.hpp), with their latencies
// (the vehicle file's vis_* and *_latency) and their health. main assembles it; the scheduler
// runs it.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "uav/app/blackboard.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/sensing.hpp"

namespace uav::avoid {
class OccupancyMap;
}

namespace uav::world {
class Scene;
}

namespace uav::app {

class LockstepScheduler;

class Sensing {
 public:
  struct Options {
    std::string log_dir;        // "" : no survey captures or maps written
    int64_t start_utime = 0;    // names the capture and map folders
    GeodeticPoint home;
    bool measured_latency = false;  // results visible when done (real time), not at fixed latencies
  };
  // Throws std::invalid_argument naming what is wrong (a scene without cameras, a bad parameter).
  Sensing(const world::Scene& scene, const ParameterSet& params, Blackboard& board, const Options& options);
  ~Sensing();

  // Registers every vision worker with the scheduler (frame periods on its step).
  void AddTo(LockstepScheduler& scheduler, int64_t step_us);
  // The simulator's true pose now, each physics step: the cameras render from it.
  void RecordTruth(int64_t utime, const Eigen::Isometry3d& T_NB);
  // On the clock's thread each step: every 100 ms the workers' health goes to the blackboard,
  // and a worker that falls behind or stalls (or recovers) is announced to the operator; a
  // worker the CPU cannot keep at its camera's rate gets a lower one, on purpose (ChooseRate).
  void Monitor(int64_t utime, LockstepScheduler& scheduler);
  // Obstacle avoidance's 3-D map (null when avoidance is off). Read it only when the scheduler
  // has stopped: the AVD thread writes it.
  const avoid::OccupancyMap* avoidance_map() const;
  // The simulator's fault: stereo rig `rig` (the scene's order) delivers black images from now
  // on (failed) or real ones again. Throws std::out_of_range for a rig the scene has not.
  void SetStereoFailed(int rig, bool failed);
  // "N survey images captured, ..." for the exit line.
  std::string Summary() const;
  // The run's sensing benchmark as JSON: per worker the configured and achieved rates (over the
  // whole run and the last 2 s), latency p50/p99, compute p50, results and drops; the control
  // loop's wall-clock period p50/p99/max; the process's CPU use.
  std::string BenchmarkJson(const LockstepScheduler& scheduler, double speed, double simulated_s, double wall_s) const;

 private:
  void BuildStereo(const world::Scene& scene, const ParameterSet& params);
  void ChooseRate(int64_t utime, SensingWorker& w, LockstepScheduler& scheduler);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::app
