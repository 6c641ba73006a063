#pragma once
// The vehicle's sensing: the vision workers on the rig's cameras (sensor_rig.hpp: simulated,
// recorded or live), each a thread off the control path (vision_worker.hpp), with their latencies
// (the vehicle file's vis_* and *_latency) and their health. main assembles it; the scheduler
// runs it.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/sensor_rig.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/sensing.hpp"

namespace uav::avoid {
class OccupancyMap;
}

namespace uav::runtime {

class LockstepScheduler;

class Sensing {
 public:
  struct Options {
    std::string log_dir;        // "" : no survey captures or maps written
    int64_t start_utime = 0;    // names the capture and map folders
    GeodeticPoint home;
    bool measured_latency = false;  // results visible when done (real time), not at fixed latencies
    bool imu = true;                // an IMU aids the odometry's rotation (not on a bench of cameras alone)
  };
  // Throws std::invalid_argument naming what is wrong (a rig without cameras, a bad parameter).
  // The rig's cameras must outlive the sensing.
  Sensing(const SensorRig& rig, const ParameterSet& params, Blackboard& board, const Options& options);
  ~Sensing();

  // Registers every vision worker with the scheduler (frame periods on its step).
  void AddTo(LockstepScheduler& scheduler, int64_t step_us);
  // On the clock's thread each step: every 100 ms the workers' health goes to the blackboard,
  // and a worker that falls behind or stalls (or recovers) is announced to the operator; a
  // worker the CPU cannot keep at its camera's rate gets a lower one, on purpose (ChooseRate).
  void Monitor(int64_t utime, LockstepScheduler& scheduler);
  // Obstacle avoidance's 3-D map (null when avoidance is off). Read it only when the scheduler
  // has stopped: the AVD thread writes it.
  const avoid::OccupancyMap* avoidance_map() const;
  // The parameters' version each vision worker last took, by worker name (the parameter-reader
  // test: a change over the link reaches every worker).
  std::map<std::string, int64_t> ParameterVersions() const;
  // obs_margin as the obstacle worker and the avoidance planner hold it now (-1 without them).
  double ObstacleMargin() const;
  double PlannerMargin() const;
  // "N survey images captured, ..." for the exit line.
  std::string Summary() const;
  // The run's sensing benchmark as JSON: per worker the configured and achieved rates (over the
  // whole run and the last 2 s), latency p50/p99, compute p50, results and drops; the control
  // loop's wall-clock period p50/p99/max; the process's CPU use.
  std::string BenchmarkJson(const LockstepScheduler& scheduler, double speed, double simulated_s, double wall_s) const;

 private:
  void BuildStereo(const ParameterSet& params);
  void ChooseRate(int64_t utime, SensingWorker& w, LockstepScheduler& scheduler);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::runtime
