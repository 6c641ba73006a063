#include "uav/control/task_manager.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace uav::control {

TaskParams TaskParams::FromParameters(const ParameterSet& p) {
  TaskParams t{p.Get("task_reached_radius"), p.Get("task_reached_speed"), p.Get("task_land_speed"),
          p.Get("task_land_slow_alt"),  p.Get("task_landed_alt"),    p.Get("task_landed_time"),
          p.Get("ctl_speed_max_xy"),    p.Get("ctl_speed_max_up"),   p.Get("ctl_speed_max_down"),
          p.Get("task_path_accel"),     p.Get("task_path_leash"),    p.Get("task_return_alt"),
          p.Get("task_stall_time"),     p.Get("fs_fence_radius"),    p.Get("fs_fence_alt"),
          FollowParams::FromParameters(p)};
  t.stick_yaw_rate = p.Get("task_stick_yaw_rate") * M_PI / 180.0;
  t.stick_timeout = p.Get("task_stick_timeout");
  t.disarm_preflight = p.Get("task_disarm_preflight");
  t.disarm_land = p.Get("task_disarm_land");
  return t;
}

std::string TaskManager::AboveCeiling(const char* what, double altitude_m) const {
  char why[160];
  std::snprintf(why, sizeof why, "%s %.1f m is above the vehicle's %.0f m ceiling (fs_fence_alt)", what, altitude_m,
                p_.fence_alt);
  return why;
}

std::string TaskManager::OutsideFence(const Eigen::Vector3d& p_N) const {
  char why[96];
  if (p_N.head<2>().norm() > p_.fence_radius) {
    std::snprintf(why, sizeof why, "%.1f m from home, beyond the %.0f m circle", p_N.head<2>().norm(), p_.fence_radius);
    return why;
  }
  if (-p_N.z() > p_.fence_alt) {
    std::snprintf(why, sizeof why, "%.1f m high, above the %.0f m ceiling", -p_N.z(), p_.fence_alt);
    return why;
  }
  return fence_.Breach(p_N.head<2>());
}

// Holds the current position and heading (hover command, failsafe hold, stalled path).
void TaskManager::Hold(const VehicleEstimate& est) {
  runner_.reset();
  path_ = MissionRunner::Output{};
  setpoint_ = Setpoint{};
  setpoint_.p_N = est.p_N;
  setpoint_.yaw = est.euler.psi;
  task_ = Task::kHover;
  chirp_ = Chirp{};
}

void TaskManager::EnforceFailsafe(FailsafeAction required, const std::string& reason, const VehicleEstimate& est,
                                  double t, std::vector<CommandAck>* reports, bool return_at_altitude) {
  required_ = required;
  failsafe_reason_ = reason;
  if (enforced_ == FailsafeAction::kManual && required != FailsafeAction::kManual) {
    // Pilot hands back: the autopilot holds where the pilot left it (then the stricter rest).
    enforced_ = FailsafeAction::kNone;
    if (airborne_) Hold(est);
    reset_pending_ = true;
  }
  if (required <= enforced_ || !airborne_) return;
  enforced_ = required;
  // A landing under way already does more than a hold: stopping it to hover (low, over the
  // ground where the cameras see least) would only add time in the air.
  if (required == FailsafeAction::kHold && task_ == Task::kLand) return;
  // Onboard work goes on through a failsafe: a survey camera that was on stays on (at the same
  // rate) while the vehicle holds or flies home, until it lands or the operator commands again.
  if (path_.capture_interval_s || path_.capture_distance_m)
    carried_capture_ = {path_.capture_interval_s, path_.capture_distance_m};
  const std::string what = "failsafe_" + std::string(Name(required));
  Finish(AckResult::kFailed, "failsafe " + std::string(Name(required)) + ": " + reason, reports);
  // What the vehicle does now is its own task, reported as itself (thesis 2.3.2: the task
  // manager reports every task): a row of its own in the GCS, closed when it ends.
  Own({std::string(kVehicleInitiatedSource), ++vehicle_seq_, what}, est, t);
  Report(AckResult::kAccepted, 0, reason, reports);
  switch (required) {
    case FailsafeAction::kNone: break;
    case FailsafeAction::kManual:
      Hold(est);
      Finish(AckResult::kCompleted, reason + ": the pilot flies", reports);
      break;
    case FailsafeAction::kHold:
      Hold(est);
      Finish(AckResult::kCompleted, reason + "; holding position", reports);
      break;
    case FailsafeAction::kReturn: {
      std::vector<waypoints::MissionStep> steps(1);
      steps[0].kind = waypoints::MissionStep::Kind::kReturnHome;
      if (return_at_altitude) steps[0].altitude_m = std::max(0.5, -est.p_N.z());
      StartPath(Task::kReturn, std::move(steps), est, t);
      break;
    }
    case FailsafeAction::kLand: StartLanding(est); break;
  }
}

TaskManager::TaskManager(const TaskParams& params, MissionSource* missions)
    : p_(params), missions_(missions) {}

void TaskManager::BeginPath(Task task, std::vector<waypoints::MissionStep> steps,
                            const CommandRequest& req, const VehicleEstimate& est, double t,
                            std::vector<CommandAck>* reports) {
  auto reject = [&](const std::string& why) {
    reports->push_back({req.source, req.seq, req.command.Name(), AckResult::kRejected, 0, why});
  };
  if (!armed_) return reject("not armed: arm first");
  if (!airborne_) {
    // From the ground a path must begin by taking off (a survey mission does).
    auto first = std::find_if(steps.begin(), steps.end(), [](const waypoints::MissionStep& s) {
      return s.kind != waypoints::MissionStep::Kind::kSetSpeed &&
             s.kind != waypoints::MissionStep::Kind::kCaptureStart &&
             s.kind != waypoints::MissionStep::Kind::kCaptureStop;
    });
    if (first == steps.end() || first->kind != waypoints::MissionStep::Kind::kTakeoff)
      return reject("not flying and the path does not start with a take-off: take off first");
    airborne_ = true;
    armed_on_ground_since_ = -1.0;
    touchdown_t_ = -1.0;
    touched_down_ = false;
    reset_pending_ = true;
  }
  // Steps outside the geofence are refused before anything moves.
  for (const auto& s : steps)
    if (s.kind == waypoints::MissionStep::Kind::kWaypoint)
      if (const std::string why = OutsideFence(s.p_N); !why.empty())
        return reject("item " + std::to_string(s.item) + " is outside the geofence: " + why);
  StartPath(task, std::move(steps), est, t);
  Begin(task, req, est, t, reports);
  deadline_ = t + p_.stall_time;  // extended whenever progress is made
}

void TaskManager::SetParams(const TaskParams& params) {
  p_ = params;
  if (runner_) runner_->SetSpeedLimits(p_.speed_max_xy, p_.speed_max_up, p_.speed_max_down);
}

void TaskManager::StartPath(Task task, std::vector<waypoints::MissionStep> steps, const VehicleEstimate& est,
                            double t) {
  MissionRunnerParams rp{p_.reached_radius, p_.reached_speed, p_.speed_max_xy, p_.speed_max_up,
                         p_.speed_max_down, p_.path_accel,    p_.path_leash,   p_.return_alt};
  for (const Eigen::Vector3d& r : fence_.rally_N) rp.rally_N.push_back(r.head<2>());
  runner_ = std::make_unique<MissionRunner>(std::move(steps), rp, est);
  runner_->SetWingBorne(wing_);
  path_ = runner_->Update(est, 0.0);
  setpoint_ = path_.setpoint;
  task_ = task;
  last_percent_ = 0;
  last_progress_t_ = t;
  deadline_ = t + p_.stall_time;
}

void TaskManager::SetWingBorne(std::optional<WingBorne> wing) {
  wing_ = wing;
  if (runner_) runner_->SetWingBorne(wing);
}

void TaskManager::StartLanding(const VehicleEstimate& est) {
  setpoint_.p_N = Eigen::Vector3d(est.p_N.x(), est.p_N.y(), 0.0);
  setpoint_.yaw = est.euler.psi;
  setpoint_.v_ff_N.setZero();
  setpoint_.speed_max_xy.reset();
  setpoint_.descent_rate = p_.land_speed;
  start_p_N_ = est.p_N;
  task_ = Task::kLand;
}

void TaskManager::Report(AckResult result, int percent, const std::string& reason,
                         std::vector<CommandAck>* reports) const {
  // Only the owner of the task in flight hears of it: a command that has ended (completed,
  // replaced, cut short by a failsafe) never gets another report.
  if (active_report_) reports->push_back({active_.source, active_.seq, active_.name, result, percent, reason});
}

void TaskManager::Own(ReportOwner owner, const VehicleEstimate& est, double t) {
  active_ = std::move(owner);
  active_report_ = true;
  start_p_N_ = est.p_N;
  start_t_ = t;
  last_percent_ = 0;
  last_progress_t_ = t;
  still_since_ = -1.0;
}

void TaskManager::Finish(AckResult result, const std::string& reason,
                         std::vector<CommandAck>* reports) {
  Report(result, result == AckResult::kCompleted ? 100 : last_percent_, reason, reports);
  active_report_ = false;
}

void TaskManager::Supersede(const std::string& by, std::vector<CommandAck>* reports) {
  if (task_ == Task::kFollow) {
    Report(AckResult::kCompleted, 100, "stopped by " + by, reports);
    active_report_ = false;
    return;
  }
  Finish(AckResult::kReplaced, "replaced by " + by, reports);
}

void TaskManager::Begin(Task task, const CommandRequest& req, const VehicleEstimate& est, double t,
                        std::vector<CommandAck>* reports) {
  Supersede(req.command.Name(), reports);
  stand_in_N_.reset();  // the last goal's, until avoidance has planned for this one
  chirp_ = Chirp{};
  carried_capture_.reset();
  if (task != Task::kTrack && task != Task::kMission && task != Task::kReturn) runner_.reset();
  task_ = task;
  Own({req.source, req.seq, req.command.Name()}, est, t);
  // Deadline: three times the time the move needs at the speed limits, plus margin.
  const double dist_xy = (setpoint_.p_N - est.p_N).head<2>().norm();
  const double dist_z = std::abs(setpoint_.p_N.z() - est.p_N.z());
  const double need = dist_xy / p_.speed_max_xy + dist_z / std::min(p_.speed_max_up, p_.land_speed);
  deadline_ = t + 3.0 * need + 30.0;
  closest_to_goal_ = (setpoint_.p_N - est.p_N).norm();
  reports->push_back({req.source, req.seq, req.command.Name(), AckResult::kAccepted, 0, ""});
}

void TaskManager::Disarm() {
  armed_ = false;
  armed_on_ground_since_ = -1.0;
  touchdown_t_ = -1.0;
}

void TaskManager::StopMotors(const std::string& reason, std::vector<CommandAck>* reports) {
  if (active_report_) Finish(AckResult::kFailed, reason, reports);
  Disarm();
  airborne_ = false;
  enforced_ = FailsafeAction::kNone;
  task_ = Task::kIdle;
  carried_capture_.reset();
  setpoint_.descent_rate.reset();
}

void TaskManager::OnCrash(const std::string& reason, std::vector<CommandAck>* reports) {
  if (!armed_ && !airborne_) return;
  StopMotors("crashed: " + reason, reports);
}

void TaskManager::Submit(const CommandRequest& req, const VehicleEstimate& est, double t,
                         std::vector<CommandAck>* reports) {
  auto reject = [&](const std::string& why) {
    reports->push_back({req.source, req.seq, req.command.Name(), AckResult::kRejected, 0, why});
  };
  auto instant = [&]() {
    reports->push_back({req.source, req.seq, req.command.Name(), AckResult::kAccepted, 0, ""});
    reports->push_back({req.source, req.seq, req.command.Name(), AckResult::kCompleted, 100, ""});
  };
  const Command& c = req.command;
  // Emergency stop: the motors off at once, wherever the vehicle is. Nothing refuses it (not a
  // failsafe, not the RC switch) but a vehicle whose motors are already off.
  if (c.id == CommandId::kEmergencyStop) {
    if (!armed_) return reject("already disarmed: the motors are off");
    StopMotors("motors stopped by the operator (emergency stop)", reports);
    return instant();
  }
  // Failsafes first: nothing less strict than what they require is accepted.
  if (required_ == FailsafeAction::kManual && c.id != CommandId::kDisarm)
    return reject("pilot has control (RC fail-safe switch)");
  const FailsafeAction level = c.id == CommandId::kHover    ? FailsafeAction::kHold
                               : c.id == CommandId::kReturn ? FailsafeAction::kReturn
                               : c.id == CommandId::kLand   ? FailsafeAction::kLand
                                                            : FailsafeAction::kNone;
  if (c.id != CommandId::kDisarm && level < required_)
    return reject("failsafe " + std::string(Name(required_)) + " active: " + failsafe_reason_);
  if (c.id == CommandId::kGoto)
    if (const std::string why = OutsideFence(Eigen::Vector3d(c.args[0], c.args[1], -c.args[2])); !why.empty())
      return reject("target is outside the geofence: " + why);
  if (c.id == CommandId::kTakeoff && c.args[0] > p_.fence_alt)
    return reject(AboveCeiling("take-off altitude", c.args[0]));
  if (airborne_ && c.id != CommandId::kArm && c.id != CommandId::kDisarm) enforced_ = level;
  switch (c.id) {
    case CommandId::kArm:
      if (armed_) return reject("already armed");
      if (!pre_arm_failing_.empty()) return reject("pre-arm checks failed: " + pre_arm_failing_);
      armed_ = true;
      armed_on_ground_since_ = t;
      reset_pending_ = true;
      return instant();
    case CommandId::kDisarm:
      if (!armed_) return reject("already disarmed");
      if (airborne_) return reject("vehicle is flying: land first");
      Disarm();
      return instant();
    case CommandId::kTakeoff: {
      if (!armed_) return reject("not armed: arm first");
      if (airborne_ && task_ != Task::kLand)
        return reject("already flying: use goto to change altitude");
      setpoint_ = Setpoint{};
      setpoint_.p_N = Eigen::Vector3d(est.p_N.x(), est.p_N.y(), -c.args[0]);
      setpoint_.yaw = est.euler.psi;
      if (!airborne_) reset_pending_ = true;
      airborne_ = true;
      armed_on_ground_since_ = -1.0;
      touchdown_t_ = -1.0;
      touched_down_ = false;
      return Begin(Task::kTakeoff, req, est, t, reports);
    }
    case CommandId::kSticks:
      if (!airborne_) return reject("not flying: take off first");
      Supersede("sticks", reports);
      carried_capture_.reset();
      Hold(est);
      task_ = Task::kSticks;
      sticks_holding_ = "waiting for the sticks' deadman";
      return instant();
    case CommandId::kHover:
      if (!airborne_) return reject("not flying");
      Supersede("hover", reports);
      carried_capture_.reset();
      Hold(est);  // thesis 2.3.2: the current position becomes the reference
      return instant();
    case CommandId::kLand:
      if (!airborne_) return reject("not flying");
      setpoint_ = Setpoint{};
      setpoint_.p_N = Eigen::Vector3d(est.p_N.x(), est.p_N.y(), 0.0);
      setpoint_.yaw = est.euler.psi;
      setpoint_.descent_rate = p_.land_speed;
      return Begin(Task::kLand, req, est, t, reports);
    case CommandId::kGoto:
      if (!airborne_) return reject("not flying: take off first");
      setpoint_.p_N = Eigen::Vector3d(c.args[0], c.args[1], -c.args[2]);
      setpoint_.descent_rate.reset();
      setpoint_.v_ff_N.setZero();
      setpoint_.speed_max_xy.reset();
      return Begin(Task::kGoto, req, est, t, reports);
    case CommandId::kTrack:
    case CommandId::kMission: {
      if (!missions_) return reject("this vehicle has no mission store");
      std::string error;
      auto steps = c.id == CommandId::kTrack ? missions_->StoredPath(static_cast<int>(c.args[0]), &error)
                                             : missions_->UploadedMission(&error);
      if (!steps) return reject(error);
      const MissionRunner* before = runner_.get();
      BeginPath(c.id == CommandId::kTrack ? Task::kTrack : Task::kMission, std::move(*steps), req, est, t, reports);
      if (task_ == Task::kMission && runner_ && runner_.get() != before) {  // accepted: a new run
        resume_upload_ = missions_->upload_count();
        resume_offset_ = 0;
        resume_first_ = 0;
        resume_step_ = 0;
      }
      return;
    }
    case CommandId::kResume: {
      // QGroundControl's "resume mission" after a return, a failsafe or a pause.
      if (!missions_) return reject("this vehicle has no mission store");
      if (!resume_step_) return reject("nothing to resume: no mission has been interrupted (fly one with 'mission')");
      std::string error;
      auto steps = missions_->UploadedMission(&error);
      if (!steps) return reject(error);
      if (missions_->upload_count() != resume_upload_)
        return reject("a new mission was uploaded since the last one stopped: fly it with 'mission'");
      waypoints::ResumedMission resumed;
      try {
        resumed = waypoints::ResumeSteps(*steps, *resume_step_, airborne_);
      } catch (const std::invalid_argument& e) {
        return reject(e.what());
      }
      const MissionRunner* before = runner_.get();
      BeginPath(Task::kMission, std::move(resumed.steps), req, est, t, reports);
      if (task_ == Task::kMission && runner_ && runner_.get() != before) {  // accepted: a new run
        resume_first_ = resumed.first;
        resume_offset_ = static_cast<std::ptrdiff_t>(resumed.first) - static_cast<std::ptrdiff_t>(resumed.prefix);
      }
      return;
    }
    case CommandId::kReturn: {
      if (!airborne_) return reject("not flying");
      std::vector<waypoints::MissionStep> steps(1);
      steps[0].kind = waypoints::MissionStep::Kind::kReturnHome;
      return BeginPath(Task::kReturn, std::move(steps), req, est, t, reports);
    }
    case CommandId::kFollow: {
      if (!airborne_) return reject("not flying: take off first");
      if (!target_.locked) return reject("no target locked: select one in the video first");
      if (!target_.on_ground) return reject("the target is not on the ground (its ray does not meet it): pitch the camera down");
      if (p_.follow.height_m > p_.fence_alt) return reject(AboveCeiling("flw_height", p_.follow.height_m));
      follower_ = std::make_unique<TargetFollower>(p_.follow, est);
      follow_state_ = TargetFollower::State::kFollowing;
      const TargetFollower::Output first = follower_->Update(target_, est, t);
      setpoint_ = first.setpoint;
      return Begin(Task::kFollow, req, est, t, reports);
    }
    case CommandId::kGps:  // a simulator fault: the control thread hands it to the simulator
    case CommandId::kEmergencyStop:
    case CommandId::kParam:  // the control thread sets parameters before commands reach here
      return;
    case CommandId::kTransition:
      // A tail-sitter's control thread takes its transitions before they reach here.
      return reject("this vehicle is a quadrotor: it has no wing to transition to");
    case CommandId::kChirp: {
      // Thesis 2.4.5: the vehicle first hovers, then one channel is excited.
      if (!airborne_ || task_ != Task::kHover) return reject("not hovering: hover first, then chirp");
      if (!(c.args[3] > c.args[2])) return reject("f1_hz must be above f0_hz");
      Hold(est);
      Begin(Task::kHover, req, est, t, reports);
      chirp_ = {static_cast<ServoChannel>(static_cast<int>(c.args[0])), c.args[1], c.args[2], c.args[3], c.args[4]};
      chirp_start_t_ = t;
      return;
    }
  }
}

void TaskManager::UpdateFollow(const VehicleEstimate& est, double t, std::vector<CommandAck>* reports) {
  if (!follower_) return;
  const TargetFollower::Output o = follower_->Update(target_, est, t);
  if (o.state == TargetFollower::State::kGaveUp) {
    Hold(est);
    // The operator stopping the tracker ends the follow as meant; losing the target is a failure.
    Finish(o.stopped_by_operator ? AckResult::kCompleted : AckResult::kFailed, o.reason + "; holding position", reports);
    return;
  }
  if (o.state != follow_state_ && active_report_) {
    // Say when it starts holding and when it follows again.
    Report(AckResult::kInProgress, 0, o.state == TargetFollower::State::kHolding ? o.reason + "; holding position" : "following",
           reports);
  }
  follow_state_ = o.state;
  setpoint_ = o.setpoint;
  // The geofence wins: a target that leaves it is watched from inside (at the edge, less the
  // acceptance radius).
  const double r = setpoint_.p_N.head<2>().norm(), r_max = p_.fence_radius - p_.reached_radius;
  if (r > r_max) setpoint_.p_N.head<2>() *= r_max / r;
}

double TaskManager::Progress(const VehicleEstimate& est) const {
  if (task_ == Task::kLand) {
    const double start_alt = std::max(-start_p_N_.z(), 1e-3);
    return std::clamp(1.0 - est.altitude() / start_alt, 0.0, 1.0);
  }
  const double total = (setpoint_.p_N - start_p_N_).norm();
  if (total < 1e-6) return 1.0;
  return std::clamp(1.0 - (setpoint_.p_N - est.p_N).norm() / total, 0.0, 1.0);
}

TaskManager::Output TaskManager::Update(const VehicleEstimate& est, double t,
                                        std::vector<CommandAck>* reports) {
  const double dt = std::max(0.0, t - last_t_);
  last_t_ = t;
  const bool path_task = task_ == Task::kTrack || task_ == Task::kMission || task_ == Task::kReturn;
  if (path_task && runner_) {
    const int before = path_.percent;
    path_ = runner_->Update(est, dt);
    setpoint_ = path_.setpoint;
    if (path_.percent > before || path_.holding) deadline_ = t + p_.stall_time;
    if (task_ == Task::kMission) {
      // Where a resume would start: this mission's step being flown (until it is done).
      const std::ptrdiff_t step = static_cast<std::ptrdiff_t>(path_.step) + resume_offset_;
      // Done, or landing at its end (its last item): nothing is left to resume.
      if (path_.done || path_.land) resume_step_.reset();
      else resume_step_ = static_cast<std::size_t>(std::max<std::ptrdiff_t>(step, static_cast<std::ptrdiff_t>(resume_first_)));
    }
    if (path_.percent != last_percent_ && t - last_progress_t_ >= 0.5 && path_.percent < 100) {
      last_percent_ = path_.percent;
      last_progress_t_ = t;
      Report(AckResult::kInProgress, path_.percent, "", reports);
    }
    if (path_.land) {
      runner_.reset();
      path_ = MissionRunner::Output{};
      StartLanding(est);  // the command completes on touchdown
    } else if (path_.done) {
      runner_.reset();
      path_ = MissionRunner::Output{};
      setpoint_.v_ff_N.setZero();
      task_ = Task::kHover;
      Finish(AckResult::kCompleted, "", reports);
    } else if (t > deadline_) {
      Hold(est);
      Finish(AckResult::kFailed, "no progress along the path; holding position", reports);
    }
  }
  // Armed on the ground with nothing to do: disarm (PX4's COM_DISARM_PRFLT and COM_DISARM_LAND).
  if (armed_ && !airborne_) {
    char buf[96];
    if (touchdown_t_ >= 0.0 && t - touchdown_t_ >= p_.disarm_land) {
      std::snprintf(buf, sizeof buf, "disarmed %.0f s after the landing", p_.disarm_land);
      Disarm();
      note_ = buf;
    } else if (touchdown_t_ < 0.0 && armed_on_ground_since_ >= 0.0 && p_.disarm_preflight > 0.0 &&
               t - armed_on_ground_since_ >= p_.disarm_preflight) {
      std::snprintf(buf, sizeof buf, "disarmed: armed on the ground for %.0f s without a takeoff", p_.disarm_preflight);
      Disarm();
      note_ = buf;
    }
  }
  if (task_ == Task::kFollow) UpdateFollow(est, t, reports);
  if (task_ == Task::kSticks) UpdateSticks(est, t, dt);
  else sticks_holding_.clear();
  if (task_ != Task::kFollow) follower_.reset();
  if (task_ == Task::kLand && setpoint_.descent_rate) {
    // Slow down for the touchdown.
    setpoint_.descent_rate =
        est.altitude() < p_.land_slow_alt ? p_.land_speed / 3.0 : p_.land_speed;
  }
  Output o;
  if (chirp_.channel != ServoChannel::kNone) {
    const double elapsed = t - chirp_start_t_;
    if (task_ != Task::kHover || !airborne_) {
      chirp_ = Chirp{};
    } else if (elapsed >= chirp_.duration_s) {
      chirp_ = Chirp{};
      Finish(AckResult::kCompleted, "", reports);
    } else {
      o.chirp_channel = chirp_.channel;
      o.chirp_value = chirp_.Value(elapsed);
      const int percent = static_cast<int>(100.0 * elapsed / chirp_.duration_s);
      if (t - last_progress_t_ >= 0.5 && percent != last_percent_) {
        last_percent_ = percent;
        last_progress_t_ = t;
        Report(AckResult::kInProgress, percent, "", reports);
      }
    }
  }
  const bool long_task = task_ == Task::kTakeoff || task_ == Task::kGoto || task_ == Task::kLand;
  if (long_task) {
    // Never given up while it gets nearer: a vehicle slowed by its sensors (avoidance on a slow
    // stereo pair) has task_stall_time from its last metre of progress, as a path task has.
    const double to_go = (setpoint_.p_N - est.p_N).norm();
    if (to_go < closest_to_goal_ - kProgressStep_m) {
      closest_to_goal_ = to_go;
      deadline_ = std::max(deadline_, t + p_.stall_time);
    }
    const int percent = static_cast<int>(std::floor(100.0 * Progress(est) + 1e-9));
    if (t - last_progress_t_ >= 0.5 && percent != last_percent_ && percent < 100) {
      last_percent_ = percent;
      last_progress_t_ = t;
      Report(AckResult::kInProgress, percent, "", reports);
    }
    if (task_ == Task::kLand) {
      // Down when still at the ground's height, or when the vertical speed has stayed under a
      // third of the slow descent rate for four times as long while a descent is commanded: the
      // ground has stopped the descent, whatever the height estimate says. Not gated on height
      // (as PX4's land detector is not): without GPS, after a descent on visual odometry, the
      // estimate has been 3 m up at touchdown, and a landing waiting for "below 2 m" sat on the
      // ground with the rotors running while the blind INS drifted away (gps_denied's outliers).
      const double slow_rate = p_.land_speed / 3.0;
      const bool at_ground = est.altitude() < p_.landed_alt && std::abs(est.v_N.z()) < 0.2;
      const bool stopped = std::abs(est.v_N.z()) < slow_rate / 3.0;
      if ((!at_ground && !stopped) || descent_deferred_) still_since_ = -1.0;
      else if (still_since_ < 0.0) still_since_ = t;
      const double needed = at_ground ? p_.landed_time : 4.0 * p_.landed_time;
      if (still_since_ >= 0.0 && t - still_since_ >= needed) {
        // Touchdown: the rotors idle for disarm_land, then stop (PX4's auto-disarm); report.
        airborne_ = false;
        enforced_ = FailsafeAction::kNone;
        touched_down_ = true;
        if (p_.disarm_land > 0.0) touchdown_t_ = t;
        else Disarm();
        carried_capture_.reset();
        task_ = Task::kIdle;
        setpoint_.descent_rate.reset();
        Finish(AckResult::kCompleted, "", reports);
      }
    } else {
      // A goal nearer an obstacle than the clearance is reached where avoidance stops short of it.
      const bool short_of_it = task_ == Task::kGoto && stand_in_N_ && !wing_;
      const Eigen::Vector3d off = (short_of_it ? *stand_in_N_ : setpoint_.p_N) - est.p_N;
      const bool reached = wing_ ? wing_->OnLoiterCircle(setpoint_.p_N, est.p_N)
                                 : off.norm() < p_.reached_radius && est.v_N.norm() < p_.reached_speed;
      if (reached) {
        task_ = Task::kHover;  // hold the reached target
        if (short_of_it) {
          char buf[64];
          std::snprintf(buf, sizeof buf, "stopped %.1f m short: ", (setpoint_.p_N - est.p_N).norm());
          setpoint_.p_N = *stand_in_N_;
          Finish(AckResult::kCompleted, buf + stand_in_why_, reports);
        } else {
          Finish(AckResult::kCompleted, "", reports);
        }
      }
    }
    // A landing never gives up: holding instead would keep the vehicle in the air.
    if (long_task && task_ != Task::kLand && active_report_ && t > deadline_) {
      // Give up safely: hold where we are and say so.
      setpoint_.p_N = est.p_N;
      setpoint_.descent_rate.reset();
      task_ = Task::kHover;
      Finish(AckResult::kFailed, "target not reached in time; holding position", reports);
    }
  }
  o.armed = armed_;
  o.airborne = airborne_;
  o.task = task_;
  o.setpoint = setpoint_;
  if (airborne_ && (task_ == Task::kGoto || task_ == Task::kFollow)) o.goal_N = setpoint_.p_N;
  if (airborne_ && runner_ && path_.leg_end_N) o.goal_N = path_.leg_end_N;
  if (runner_) {
    o.mission_item = path_.item;
    o.capture_interval_s = path_.capture_interval_s;
    o.capture_distance_m = path_.capture_distance_m;
  }
  if (!o.capture_interval_s && !o.capture_distance_m && carried_capture_) {
    o.capture_interval_s = carried_capture_->first;
    o.capture_distance_m = carried_capture_->second;
  }
  o.reset_controller = reset_pending_ || !airborne_;
  reset_pending_ = false;
  o.touched_down = touched_down_ && !airborne_;
  o.note = std::move(note_);
  note_.clear();
  return o;
}

void TaskManager::ReportProgressNote(const std::string& reason, std::vector<CommandAck>* reports) const {
  if (active_report_) Report(AckResult::kInProgress, std::max(0, last_percent_), reason, reports);
}

void TaskManager::UpdateSticks(const VehicleEstimate& est, double t, double dt) {
  const bool fresh = sticks_ && t - sticks_->utime * 1e-6 <= p_.stick_timeout;
  setpoint_.v_ff_N.setZero();
  setpoint_.yaw_rate_ff = 0.0;
  setpoint_.speed_max_xy.reset();
  setpoint_.descent_rate.reset();
  if (!fresh || !sticks_->deadman) {
    sticks_holding_ = !sticks_ ? "waiting for the sticks' deadman"
                      : !fresh ? "sticks silent: holding"
                               : "deadman released: holding";
    return;
  }
  const ManualSticks& s = *sticks_;
  const double psi = est.euler.psi;
  const double f = s.forward * p_.speed_max_xy, r = s.right * p_.speed_max_xy;
  Eigen::Vector3d v_N(std::cos(psi) * f - std::sin(psi) * r, std::sin(psi) * f + std::cos(psi) * r,
                      s.up >= 0 ? -s.up * p_.speed_max_up : -s.up * p_.speed_max_down);
  Eigen::Vector3d next = setpoint_.p_N + v_N * dt;
  next.z() = std::min(next.z(), -0.5);  // the sticks do not land: `land` does
  // The reference leads the vehicle by at most a few metres (a gust, a slow climb).
  constexpr double kLead = 2.0;
  const Eigen::Vector3d lead = next - est.p_N;
  if (lead.norm() > kLead) next = est.p_N + lead * (kLead / lead.norm());
  if (const std::string why = OutsideFence(next); !why.empty()) {
    sticks_holding_ = "the geofence stops the sticks: " + why;
    return;
  }
  sticks_holding_.clear();
  setpoint_.p_N = next;
  setpoint_.v_ff_N = v_N;
  const double yaw_rate = s.yaw * p_.stick_yaw_rate;
  setpoint_.yaw = std::remainder(setpoint_.yaw + yaw_rate * dt, 2.0 * M_PI);
  setpoint_.yaw_rate_ff = yaw_rate;
}

}  // namespace uav::control
