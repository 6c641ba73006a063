#pragma once
// The simulated vehicle flown by the onboard stack, assembled once: the simulator, the threads
// IMU, CTL and SVO of thesis Table 2.1 and the scene's sensing (the vision workers and AVD) on
// one lockstep scheduler, with the simulator's own duties each physics step (the truth the
// cameras render from, the true clearance for the flight log, the GPS fault). uav-onboard adds
// its link and log threads; the avoidance benchmark and the scenario flights drive it from
// their own loop.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "uav/app/blackboard.hpp"
#include "uav/app/lockstep_scheduler.hpp"
#include "uav/app/sensing.hpp"
#include "uav/app/workers.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/simulated_vehicle.hpp"

namespace uav::world {
class Scene;
}

namespace uav::app {

class MissionStore;

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
    MissionStore* missions = nullptr;     // where uploaded missions are kept (null: none)
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
  Blackboard& board() { return board_; }
  ControlWorker& control() { return ctl_; }
  LockstepScheduler& scheduler() { return scheduler_; }
  Sensing* sensing() { return sensing_.get(); }
  const world::Scene* scene() const { return options_.scene; }
  Eigen::Isometry3d TruthPose() const;

 private:
  Options options_;
  std::unique_ptr<sim::SimulatedVehicle> vehicle_;
  Blackboard board_;
  ImuWorker imu_;
  ControlWorker ctl_;
  ServoWorker svo_;
  std::unique_ptr<Sensing> sensing_;
  LockstepScheduler scheduler_;
  bool sky_view_ = true;
  bool gps_enabled_ = true;
};

}  // namespace uav::app
