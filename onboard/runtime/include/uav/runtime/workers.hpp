#pragma once
// The thread bodies of thesis Table 2.1. Each is a thin shell: read the blackboard, call the
// algorithm class, write the blackboard. The scheduler owns the threads.
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/flight_log.hpp"
#include "uav/runtime/parameter_server.hpp"
#include "uav/control/pre_arm.hpp"
#include "uav/avoid/safety_layer.hpp"
#include "uav/control/position_attitude_controller.hpp"
#include "uav/control/tailsitter_controller.hpp"
#include "uav/control/task_manager.hpp"
#include "uav/hal/vehicle_backend.hpp"
#include "uav/hal/vehicle_params.hpp"
#include "uav/nav/ins.hpp"
#include "uav/nav/position_history.hpp"
#include "uav/nav/vo_imu_filter.hpp"
#include "uav/shared/state_news.hpp"

namespace uav::runtime {

// IMU: reads the sensors and the RC receiver, runs the INS, publishes the estimate.
class ImuWorker {
 public:
  ImuWorker(hal::VehicleBackend& backend, Blackboard& board, const nav::InsParams& ins_params,
            const GeodeticPoint& home, const control::LandDetectorParams& land = {})
      : backend_(backend), board_(board), ins_(ins_params, home), land_(land) {}
  void Tick(int64_t utime);
  const nav::Ins& ins() const { return ins_; }
  int64_t params_version() const { return params_version_; }

 private:
  hal::VehicleBackend& backend_;
  Blackboard& board_;
  nav::Ins ins_;
  // Ground contact and crashes: the INS's zero-velocity updates hold only while it is truly at
  // rest, and after a crash it aligns anew once the vehicle stands upright and still.
  control::LandDetector land_;
  int64_t params_version_ = 0;  // the parameters the land detector last took (0: those it was built with)
  int64_t vision_height_utime_ = 0;  // the last vision height handed to the INS
  int64_t vision_position_utime_ = 0;  // the last VO position handed to the filters
  int vision_segment_ = -1;            // the VO+IMU filter's odometry segment
  nav::VoImuFilter vo_filter_;         // thesis 5.7: the VO+IMU track beside the INS
  nav::PositionHistory vo_filter_track_;  // its positions, for odometry that arrives late
  int64_t last_utime_ = -1;
};

// CTL: task manager, obstacle avoidance's safety layer and position/attitude controller.
class ControlWorker {
 public:
  ControlWorker(const control::TaskParams& task_params,
                const control::ControllerParams& controller_params,
                const control::FailsafeParams& failsafe_params, double period_s, Blackboard& board,
                control::MissionSource* missions = nullptr, const avoid::AvoidanceParams& avoidance = {},
                const control::PreArmParams& pre_arm = {});
  void Tick(int64_t utime);
  // Serves the vehicle's parameters over the link: `param NAME VALUE` commands change them where
  // their ParamApply allows, and the table goes out every 5 s and after each change. Without it
  // a `param` command is refused.
  void ServeParameters(const ParameterSet& params);
  // U-Lion (vehicle_type 1): its controller flies the tasks in place of the quadrotor's, takes
  // `transition fw|mc`, flies goto and paths on the wing (legs by L1 guidance, a loiter circle
  // where it holds), and transitions back to hover on its own before landing and on any failsafe.
  void UseTailSitter(const control::TailSitterControlParams& params);
  // Where the simulator's faults go ("gps 0"): the simulator applies the command and returns ""
  // or why it cannot. Called on this thread; without one, fault commands are refused.
  using FaultInjector = std::function<std::string(const Command& command)>;
  void SetFaultInjector(FaultInjector inject) { inject_fault_ = std::move(inject); }

 private:
  // A `param` command: set, apply to every setting it reaches, answer with the value now used.
  void SetParameter(const control::CommandRequest& req, const BlackboardData& d, int64_t utime,
                    std::vector<CommandAck>* reports);
  void PublishParameters(int64_t utime);
  void InjectFault(const control::CommandRequest& req, std::vector<CommandAck>* reports);

  // The task's setpoint through the safety layer; tells the operator when its state changes.
  control::Setpoint Avoid(const control::TaskManager::Output& out, const BlackboardData& d, int64_t utime,
                          std::vector<CommandAck>* reports);

  // The pre-arm checks on the ground, given to the task manager and, once a second, to the link.
  void CheckPreArm(const BlackboardData& d, int64_t utime);

  // U-Lion: a command only a tail-sitter takes or refuses (transition; chirp, sticks and follow
  // need a hover). True when it was handled here.
  bool TailSitterCommand(const control::CommandRequest& req, const BlackboardData& d, std::vector<CommandAck>* reports);
  // U-Lion: one control step of the task's setpoint; the inputs and the status to the blackboard.
  airframe::TailSitterInputs FlyTailSitter(const control::TaskManager::Output& out, const control::Setpoint& setpoint,
                                      const BlackboardData& d, std::vector<CommandAck>* reports);
  // U-Lion on its wing: how the task manager flies paths and holds (from the turn radius).
  control::WingBorne WingBorne() const;
  struct TailSitterControl {
    explicit TailSitterControl(const control::TailSitterControlParams& params) : controller(params) {}
    control::TailSitterController controller;
    std::optional<Eigen::Vector3d> leg_from_N, leg_to_N;  // the leg flown on the wing
    std::optional<CommandAck> transition;  // the transition command being carried out
    bool transition_to_wing = false;
    control::TailSitterMode last_mode = control::TailSitterMode::kHover;
    std::string last_event;
    double hover_heading = 0.0;  // where the belly faces in hover [rad]
    bool approaching = false;    // a landing circling down on the wing
  };
  std::optional<TailSitterControl> tailsitter_;

  control::TaskManager tasks_;
  control::MissionSource* missions_;
  int64_t geofence_upload_ = 0;  // the upload whose geofence is in force
  control::PositionAttitudeController controller_;
  std::optional<ParameterServer> parameters_;
  FaultInjector inject_fault_;
  int64_t last_parameters_report_ = -1;
  control::PreArmParams pre_arm_params_;
  int64_t last_pre_arm_report_ = -1;
  control::FailsafeParams failsafe_params_;
  control::FailsafeMonitor failsafes_;
  avoid::SafetyLayer safety_;
  // The avoidance state as the operator hears it: a state flapping faster than this is said once it settles.
  static constexpr double kAvoidNewsSettle_s = 2.0;
  StateNews avoid_news_{kAvoidNewsSettle_s};
  std::string last_sticks_said_;
  control::Setpoint last_valid_setpoint_;
  std::string last_setpoint_error_;
  double period_s_;
  Blackboard& board_;
  control::Task last_task_ = control::Task::kIdle;
  bool last_armed_ = false;
  bool last_capturing_ = false;
};

// SVO: servo channels to the outputs: through the mixer to the rotors in direct mode, straight
// to the gyro with the gyro in the loop (thesis Fig. 2.21).
class ServoWorker {
 public:
  ServoWorker(hal::VehicleBackend& backend, Blackboard& board, double rotor_input_idle, hal::AttitudeMode mode)
      : backend_(backend), board_(board), rotor_input_idle_(rotor_input_idle), mode_(mode) {}
  void Tick(int64_t utime);

 private:
  hal::VehicleBackend& backend_;
  Blackboard& board_;
  double rotor_input_idle_;
  hal::AttitudeMode mode_;
};

// DLG: CSV flight log (only when a log directory was given).
// Writes the flight log; at every touchdown it offers the log so far for download (the GCS lists
// it beside the maps), as QGroundControl's log download.
class LogWorker {
 public:
  LogWorker(std::unique_ptr<FlightLog> log, Blackboard& board)
      : log_(std::move(log)), board_(board) {}
  void Tick(int64_t utime);

 private:
  std::unique_ptr<FlightLog> log_;
  Blackboard& board_;
  bool was_airborne_ = false;
  int landings_ = 0;
};

}  // namespace uav::runtime
