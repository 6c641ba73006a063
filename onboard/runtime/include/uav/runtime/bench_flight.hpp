#pragma once
// The vehicle on the bench: the onboard runtime on recorded or live sensors (a rig file) with
// no actuators. The vision workers run as in flight and the link reports them to the GCS; the
// vehicle's pose comes from the recording's ground truth, from its IMU's attitude and the
// visual odometry's position (the IMU aiding the odometry, as in flight), from the odometry
// alone, or stands at home (RigFile::PoseSource); control is off, and every command that would move the vehicle
// is refused saying so, as is arming (the pre-arm report names the bench). Target selection
// works: the tracker follows a box picked on the recorded or live video. PX4's replay and a
// ROS bag played into the stack are the models.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "uav/nav/imu_attitude.hpp"
#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/rig_file.hpp"
#include "uav/runtime/sensing.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::runtime {

class BenchFlight {
 public:
  static constexpr int64_t kStepUs = 2000;     // the clock's grid (camera periods round to it)
  static constexpr int64_t kPeriodUs = 20000;  // the pose thread and the link at 50 Hz

  struct Options {
    GeodeticPoint home;
    int64_t start_utime = 0;
    double speed = 1.0;       // vehicle seconds per wall second; <= 0 as fast as the workers go
    double duration_s = 0.0;  // 0: to the end of the recording (live: until Stop)
    std::string log_dir;      // survey captures, maps and the odometry's poses ("" : none written)
  };
  // Throws std::invalid_argument naming a bad parameter or rig.
  BenchFlight(const ParameterSet& params, const RigFile& rig, const Options& options);

  // Runs until the duration has passed or Stop; the sensing's health is watched on the clock's thread.
  void Run() {
    scheduler_.Run([this](int64_t) { sensing_->Monitor(scheduler_.now(), scheduler_); });
  }
  void Stop() { scheduler_.Stop(); }
  Blackboard& board() { return board_; }
  LockstepScheduler& scheduler() { return scheduler_; }
  Sensing& sensing() { return *sensing_; }
  // "pose from the recorded ground truth" (what the operator is told at start).
  std::string PoseDescription() const;
  static constexpr const char* kControlOff = "bench mode: control is off (recorded or live sensors, no actuators)";

 private:
  void Tick(int64_t utime);  // the POSE thread

  const RigFile& rig_;
  Options options_;
  Blackboard board_;
  std::unique_ptr<Sensing> sensing_;
  LockstepScheduler scheduler_;
  std::optional<Eigen::Isometry3d> last_T_NB_;
  int64_t last_utime_ = -1;
  int64_t last_prearm_utime_ = -1;
  int64_t vision_utime_ = -1;
  Eigen::Vector3d p_N_vision_ = Eigen::Vector3d::Zero();
  nav::ImuAttitude imu_attitude_;  // the recorded IMU's attitude (pose "imu")
  std::size_t imu_next_ = 0;       // the next recorded IMU sample to give it
};

}  // namespace uav::runtime
