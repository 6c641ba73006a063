#pragma once
// The simulated vehicle flown by the onboard runtime, assembled once: the simulator, the threads
// IMU, CTL and SVO of thesis Table 2.1 and the sensing (the vision workers and AVD) on the
// scene's rendered cameras, on one lockstep scheduler, with the simulator's own duties each
// physics step (the truth the cameras render from, the true clearance for the flight log, the
// faults the operator injects: "gps 0"). uav-onboard adds its link and log threads; the
// avoidance benchmark and the scenario flights drive it from their own loop.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/flight_log.hpp"
#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/sensing.hpp"
#include "uav/runtime/workers.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/simulated_vehicle.hpp"
#include "uav/simflight/sim_rig.hpp"

namespace uav::world {
class Scene;
}

namespace uav::runtime {
class MissionStore;
}

namespace uav::simflight {

class SimFlight {
 public:
  static constexpr int64_t kStepUs = 2000;     // physics at 500 Hz
  static constexpr int64_t kPeriodUs = 20000;  // threads at 50 Hz (thesis 2.3.2)

  struct Options {
    GeodeticPoint home;
    int64_t start_utime = 0;
    double speed = 0.0;                   // sim seconds per wall second; <= 0 as fast as possible
    double duration_s = 0.0;              // 0: until Stop
    const world::Scene* scene = nullptr;  // null: no cameras (and no sensing)
    std::string log_dir;                  // survey captures and the avoidance map ("" : none written)
    runtime::MissionStore* missions = nullptr;     // where uploaded missions are kept (null: none)
  };
  // Throws std::invalid_argument naming a bad parameter or scene.
  SimFlight(const ParameterSet& params, const Options& options);
  ~SimFlight();

  // Runs until the duration has passed or Stop; `each_period(utime)` runs on the clock's thread
  // after the physics of each control period (the caller's operator and measurements).
  void Run(const std::function<void(int64_t utime)>& each_period = {});
  void Stop() { scheduler_.Stop(); }

  // The X650 or U-Lion, as the vehicle file's vehicle_type says.
  sim::SimulatedVehicle& vehicle() { return *vehicle_; }
  runtime::Blackboard& board() { return board_; }
  runtime::ControlWorker& control() { return ctl_; }
  const runtime::ImuWorker& imu() const { return imu_; }
  runtime::LockstepScheduler& scheduler() { return scheduler_; }
  runtime::Sensing* sensing() { return sensing_.get(); }
  SimRig* rig() { return rig_.get(); }  // null without a scene with cameras
  // The simulator's columns for the flight log: clearance_m, the distance from the body centre
  // to the nearest true surface other than the ground [m] (nan in a world without one; the
  // flight stack never reads it).
  std::vector<runtime::LogColumn> LogColumns() const;
  const world::Scene* scene() const { return options_.scene; }
  Eigen::Isometry3d TruthPose() const;

 private:
  Options options_;
  std::unique_ptr<sim::SimulatedVehicle> vehicle_;
  runtime::Blackboard board_;
  runtime::ImuWorker imu_;
  runtime::ControlWorker ctl_;
  runtime::ServoWorker svo_;
  std::unique_ptr<SimRig> rig_;
  std::unique_ptr<runtime::Sensing> sensing_;
  runtime::LockstepScheduler scheduler_;
  bool sky_view_ = true;
  bool gps_enabled_ = true;
  std::atomic<bool> gps_wanted_{true};  // the operator's "gps 0|1" (CTL's thread sets it)
  std::atomic<double> clearance_m_{-1.0};
};

}  // namespace uav::simflight
