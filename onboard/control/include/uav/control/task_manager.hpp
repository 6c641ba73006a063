#pragma once
// Flight task manager (thesis 2.3.2): takes validated commands, checks that they make sense in
// the current state, reloads the references when the task changes, and reports progress.
// Plain class on the simulated clock: no threads, no messages.
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uav/shared/operator_messages.hpp"
#include "uav/control/chirp.hpp"
#include "uav/hal/navigation_estimate.hpp"
#include "uav/control/failsafe.hpp"
#include "uav/control/mission_runner.hpp"
#include "uav/control/position_attitude_controller.hpp"
#include "uav/control/target_follower.hpp"
#include "uav/waypoints/geofence.hpp"
#include "uav/shared/command_grammar.hpp"
#include "uav/shared/manual_control.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::control {

using hal::VehicleEstimate;

using Task = uav::Task;
using AckResult = uav::CommandResult;

struct CommandRequest {
  std::string source;  // GCS instance
  int64_t seq = 0;     // command_seq
  Command command;
};

struct TaskParams {
  double reached_radius, reached_speed, land_speed, land_slow_alt, landed_alt, landed_time;
  double speed_max_xy, speed_max_up, speed_max_down;
  double path_accel, path_leash, return_alt, stall_time;
  double fence_radius, fence_alt;  // targets beyond the geofence are refused
  FollowParams follow;
  double stick_yaw_rate = 0.785;    // [rad/s] sticks: yaw rate at full deflection
  double stick_timeout = 0.5;       // [s] sticks silent this long: hold
  double disarm_preflight = 10.0;   // [s] armed on the ground this long without a takeoff: disarm (0: never)
  double disarm_land = 0.0;         // [s] after a touchdown the rotors idle this long, then disarm
  static TaskParams FromParameters(const ParameterSet& p);
};

// Where "track N" and "mission" get their steps (compiled in the vehicle's home frame). The app
// reads stored paths from disk and keeps the last accepted upload; tests give their own.
class MissionSource {
 public:
  virtual ~MissionSource() = default;
  // Steps to fly, or nullopt with `error` naming why not (no such path, invalid file, ...).
  virtual std::optional<std::vector<waypoints::MissionStep>> StoredPath(int n, std::string* error) = 0;
  virtual std::optional<std::vector<waypoints::MissionStep>> UploadedMission(std::string* error) = 0;
  // Missions accepted so far: a resume continues only the mission it interrupted.
  virtual int64_t upload_count() = 0;
  // The geofence and rally points uploaded with the last accepted mission (empty: none).
  virtual waypoints::Geofence UploadedGeofence() = 0;
};

class TaskManager {
 public:
  TaskManager(const TaskParams& params, MissionSource* missions = nullptr);
  // New settings (a parameter changed over the link): limits apply at once, a follow's or a
  // path's own settings from its next start.
  // New parameters; a path being flown keeps to the new speed limits at once.
  void SetParams(const TaskParams& params);
  const TaskParams& params() const { return p_; }
  // A tail-sitter on its wing (nullopt: hovering): goto's target counts as reached within the
  // acceptance radius at any speed, and paths are flown through their corners at cruise speed.
  void SetWingBorne(std::optional<WingBorne> wing);
  // The vehicle cannot descend yet (a tail-sitter still on its wing, or braking from its back
  // transition toward the landing point): a landing's touchdown detection waits, so a vehicle
  // holding its height is not taken for one the ground has stopped.
  void DeferDescent(bool deferred) { descent_deferred_ = deferred; }
  // The uploaded geofence (targets in an exclusion zone or outside every inclusion zone are
  // refused) and rally points (a return goes to the nearest).
  void SetGeofence(waypoints::Geofence fence) { fence_ = std::move(fence); }

  // Handles one command; appends its ACCEPTED/REJECTED (and, for instant ones, COMPLETED)
  // reports to `reports`. A rejected command changes nothing.
  void Submit(const CommandRequest& req, const VehicleEstimate& est, double t,
              std::vector<CommandAck>* reports);

  struct Output {
    bool armed = false;
    bool airborne = false;       // false: rotors at idle (armed) or stopped (disarmed)
    bool reset_controller = false;
    Task task = Task::kIdle;
    Setpoint setpoint;
    // Where the task is taking the vehicle (goto's target, a path's leg end, the follow point),
    // for obstacle avoidance; nullopt for tasks that do not travel (takeoff, land, hover).
    std::optional<Eigen::Vector3d> goal_N;
    int mission_item = -1;                      // item being flown by track/mission, else -1
    std::optional<double> capture_interval_s;   // survey camera on (by time) ...
    std::optional<double> capture_distance_m;   // ... or by distance
    ServoChannel chirp_channel = ServoChannel::kNone;  // system identification: add chirp_value
    double chirp_value = 0.0;                          // to this servo channel (Eq. 2.14)
    std::string note;  // said once to the operator: why the vehicle disarmed on its own
    bool touched_down = false;  // on the ground after a landing's touchdown, until the next takeoff
  };
  // Carries out what the failsafes require (call before Update each step): an action stricter
  // than the one being flown takes over at once (an active command fails with the reason);
  // nothing is downgraded when a failsafe clears. While one is required, commands that would do
  // less are refused. `return_at_altitude`: a return flies home at the altitude it is at, not
  // the return altitude (obstacle perception lost: the space above was never seen).
  void EnforceFailsafe(FailsafeAction required, const std::string& reason, const VehicleEstimate& est,
                       double t, std::vector<CommandAck>* reports, bool return_at_altitude = false);
  FailsafeAction enforced() const { return enforced_; }

  // The vehicle has crashed (land_detector.hpp): the motors stop, the task fails saying why, and
  // it stays disarmed (arming waits for the crash to be over: a pre-arm check). Nothing when the
  // motors are already off.
  void OnCrash(const std::string& reason, std::vector<CommandAck>* reports);

  // The operator's newest sticks, stamped with the vehicle clock when they arrived (call before
  // Update each step): the `sticks` task flies them.
  void ObserveSticks(const std::optional<ManualSticks>& sticks) { sticks_ = sticks; }
  // What the `sticks` task does now: flying, or holding and why ("" while flying or in another
  // task); the control thread tells the operator when it changes.
  const std::string& sticks_holding() const { return sticks_holding_; }
  // The tracker's newest target (call before Submit and Update each step): follow flies on it.
  void ObserveTarget(const TrackedTarget& target) { target_ = target; }
  // The pre-arm checks' failures ("gps: no 3-D fix ...; battery: ..."; "" when all pass), from
  // the control thread's newest evaluation (call before Submit): arm is refused while any fails.
  void ObservePreArm(std::string failing) { pre_arm_failing_ = std::move(failing); }
  // Where obstacle avoidance stops short of a goto's goal that lies nearer an obstacle than the
  // vehicle's clearance, and why (nullopt: the goal itself can be reached). Reached there, the
  // goto completes, saying why it stopped short (call after each avoidance step).
  void ObserveStandIn(const std::optional<Eigen::Vector3d>& p_N, std::string why) {
    stand_in_N_ = p_N, stand_in_why_ = std::move(why);
  }

  // One step at the control rate: advances the active task, appends progress reports.
  Output Update(const VehicleEstimate& est, double t, std::vector<CommandAck>* reports);

  Task task() const { return task_; }
  // Tells the owner of the active command how its task is going (avoiding, blocked, no path):
  // an IN_PROGRESS report with the progress so far and `reason`.
  void ReportProgressNote(const std::string& reason, std::vector<CommandAck>* reports) const;
  bool armed() const { return armed_; }

 private:
  void Finish(AckResult result, const std::string& reason, std::vector<CommandAck>* reports);
  // Motors off at once, wherever the vehicle is (an emergency stop, a crash): the active task
  // fails with `reason`.
  void StopMotors(const std::string& reason, std::vector<CommandAck>* reports);
  void Disarm();
  void Begin(Task task, const CommandRequest& req, const VehicleEstimate& est, double t,
             std::vector<CommandAck>* reports);
  double Progress(const VehicleEstimate& est) const;
  void BeginPath(Task task, std::vector<waypoints::MissionStep> steps, const CommandRequest& req,
                 const VehicleEstimate& est, double t, std::vector<CommandAck>* reports);
  void StartLanding(const VehicleEstimate& est);
  void StartPath(Task task, std::vector<waypoints::MissionStep> steps, const VehicleEstimate& est, double t);
  void Hold(const VehicleEstimate& est);
  // Why p_N is outside the geofence (the circle and ceiling of the vehicle file, the uploaded
  // zones), or "" when it is inside.
  std::string OutsideFence(const Eigen::Vector3d& p_N) const;
  std::string AboveCeiling(const char* what, double altitude_m) const;  // "take-off altitude 130.0 m is above ..."
  // Ends the active command because `by` replaces it: a follow ends as the operator meant it to
  // (completed), anything else as replaced.
  void Supersede(const std::string& by, std::vector<CommandAck>* reports);
  void UpdateFollow(const VehicleEstimate& est, double t, std::vector<CommandAck>* reports);
  // Position-assisted stick flight (PX4's Position mode): the sticks move the reference at up to
  // the speed limits and turn it at up to stick_yaw_rate; released or silent sticks hold it.
  void UpdateSticks(const VehicleEstimate& est, double t, double dt);

  TaskParams p_;
  std::optional<WingBorne> wing_;
  bool descent_deferred_ = false;
  waypoints::Geofence fence_;
  MissionSource* missions_;
  std::unique_ptr<MissionRunner> runner_;  // track, mission and return
  MissionRunner::Output path_;             // its last output
  double last_t_ = 0.0;
  bool armed_ = false;
  double armed_on_ground_since_ = -1.0;  // [s] armed and not yet taken off (auto-disarm)
  double touchdown_t_ = -1.0;            // [s] landed, rotors idling until disarm_land
  bool touched_down_ = false;            // Output::touched_down
  std::string note_;                     // Output::note, said once
  std::string pre_arm_failing_;
  std::optional<Eigen::Vector3d> stand_in_N_;  // see ObserveStandIn
  std::string stand_in_why_;
  bool airborne_ = false;
  FailsafeAction required_ = FailsafeAction::kNone;  // what the failsafes ask for now
  FailsafeAction enforced_ = FailsafeAction::kNone;  // what they made the vehicle do
  std::string failsafe_reason_;
  bool reset_pending_ = false;
  Task task_ = Task::kIdle;
  Setpoint setpoint_;
  // Who owns the current long task, for its progress and completion reports: the operator's
  // command, or the vehicle itself (a failsafe: source kVehicleInitiatedSource, numbered here).
  struct ReportOwner {
    std::string source;
    int64_t seq = 0;
    std::string name;
  };
  void Report(AckResult result, int percent, const std::string& reason, std::vector<CommandAck>* reports) const;
  // `owner` now owns the task: its progress is measured from here and now.
  void Own(ReportOwner owner, const VehicleEstimate& est, double t);
  bool active_report_ = false;
  ReportOwner active_;
  int64_t vehicle_seq_ = 0;
  Eigen::Vector3d start_p_N_ = Eigen::Vector3d::Zero();
  double start_t_ = 0.0;
  double deadline_ = 0.0;
  double closest_to_goal_ = 0;  // [m] a goto's or take-off's nearest approach so far
  static constexpr double kProgressStep_m = 1.0;  // nearer by this is progress (extends the deadline)
  double last_progress_t_ = -1e9;
  int last_percent_ = -1;
  double still_since_ = -1.0;
  // Survey capture carried through a failsafe (interval, distance), see EnforceFailsafe.
  std::optional<std::pair<std::optional<double>, std::optional<double>>> carried_capture_;
  // The chirp being flown (channel kNone: none) and when it started.
  Chirp chirp_;
  double chirp_start_t_ = 0.0;
  TrackedTarget target_;
  std::unique_ptr<TargetFollower> follower_;  // while following
  TargetFollower::State follow_state_ = TargetFollower::State::kFollowing;
  std::optional<ManualSticks> sticks_;
  std::string sticks_holding_;
  // Mission resume: the step of the uploaded mission (upload number resume_upload_) being flown
  // when it stopped; a resumed run's step k is the mission's step k + resume_offset_ (its
  // first steps, which re-establish the settings, count as step resume_first_).
  std::optional<std::size_t> resume_step_;
  int64_t resume_upload_ = -1;
  std::ptrdiff_t resume_offset_ = 0;
  std::size_t resume_first_ = 0;
};

}  // namespace uav::control
