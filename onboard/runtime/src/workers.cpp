#include "uav/runtime/workers.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "uav/control/mixer.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::runtime {

void ImuWorker::Tick(int64_t utime) {
  const hal::SensorSample s = backend_.ReadSensors();
  const BlackboardData before = board_.Snapshot();
  if (before.vision_height && before.vision_height->utime > vision_height_utime_) {
    vision_height_utime_ = before.vision_height->utime;
    ins_.QueueHeight(before.vision_height->utime, before.vision_height->height_m, before.vision_height->sigma_m);
  }
  std::optional<BlackboardData::VisionPosition> vo;
  if (before.vision_position && before.vision_position->utime > vision_position_utime_) {
    vo = before.vision_position;
    vision_position_utime_ = vo->utime;
    ins_.QueueVisualPosition(vo->utime, vo->p_N, vo->sigma_m, vo->segment);
  }
  // Ground contact: flying, on the ground, falling with the motors stopped, crashed. Its limits
  // (fs_crash_*, prearm_max_tilt) follow the parameters when they change over the link.
  if (const auto params = board_.ParametersNewerThan(&params_version_))
    land_.SetParams(control::LandDetectorParams::FromParameters(*params));
  control::LandDetectorInputs contact;
  contact.t = utime * 1e-6;
  contact.f_B = s.accel_B;
  contact.w_B = s.gyro_B;
  contact.R_NB = before.estimate.q_NB.toRotationMatrix();
  contact.motors_on = before.armed && before.airborne;
  contact.landing = before.task == control::Task::kLand || before.touched_down;
  const control::GroundState was = land_.state();
  const control::GroundState ground = land_.Update(contact);
  if (ground == control::GroundState::kFalling && was != ground)
    board_.PushStatus(Severity::kError, "falling: the motors stopped in the air");
  if (ground == control::GroundState::kCrashed && was != ground)
    board_.PushStatus(Severity::kError, "CRASH: " + land_.crash_reason());
  // The crash is over once it stands upright and still: the INS, which ran on a tumbling IMU,
  // aligns anew as at power-up (level and heading from gravity and the field, position from GPS).
  if (ground == control::GroundState::kCrashed && land_.upright_at_rest()) {
    ins_.Realign();
    land_.Recover();
    board_.PushStatus(Severity::kWarning, "crash over: upright and still; navigation aligns anew");
  }
  // Standing on the ground (not yet taken off, or landed) is a measurement too; falling or
  // tumbling after the motors stopped in the air is not.
  const bool tumbling = land_.state() == control::GroundState::kFalling ||
                        (land_.state() == control::GroundState::kCrashed && !land_.at_rest()) ||
                        (land_.state() == control::GroundState::kFlying && !contact.motors_on);
  ins_.Update(s, !before.airborne && !tumbling);
  const hal::VehicleEstimate e = ins_.estimate();
  // The 9-state VO+IMU filter (thesis 5.7): the IMU's acceleration in N drives it at 50 Hz, each
  // VO position corrects it; a new odometry segment starts it again where the INS is.
  const double dt = last_utime_ < 0 ? 0.0 : (utime - last_utime_) * 1e-6;
  last_utime_ = utime;
  if (vo_filter_.initialized())
    vo_filter_.Predict(e.q_NB.toRotationMatrix() * e.f_B + Eigen::Vector3d(0, 0, ins_.gravity()), dt);
  if (vo) {
    if (!vo_filter_.initialized() || vo->segment != vision_segment_) {
      vo_filter_.Reset(vo->p_N, e.v_N, vo->sigma_m, 0.1);
      vision_segment_ = vo->segment;
    } else if (const auto p_then = std::llabs(vo->utime - utime) <= nav::PositionHistory::kMatchUs
                                       ? std::optional<Eigen::Vector3d>(vo_filter_.p_N())
                                       : vo_filter_track_.At(vo->utime)) {
      // Late by the odometry's latency: the innovation against the track at the exposure.
      vo_filter_.Correct(vo->p_N + (vo_filter_.p_N() - *p_then), vo->sigma_m);
    }
  }
  if (vo_filter_.initialized()) vo_filter_track_.Record(utime, vo_filter_.p_N());
  board_.Update([&](BlackboardData& d) {
    d.sample = s;
    d.estimate = e;
    d.ground_state = land_.state();
    d.at_rest = land_.at_rest();
    d.rest_tilt_rad = land_.rest_tilt_rad();
    d.crash_reason = land_.crash_reason();
    d.position_source = ins_.position_source();
    if (vo_filter_.initialized()) d.vo_track_N = vo_filter_.p_N();
  });
}

ControlWorker::ControlWorker(const control::TaskParams& task_params,
                             const control::ControllerParams& controller_params,
                             const control::FailsafeParams& failsafe_params, double period_s,
                             Blackboard& board, control::MissionSource* missions,
                             const avoid::AvoidanceParams& avoidance, const control::PreArmParams& pre_arm)
    : tasks_(task_params, missions), missions_(missions), controller_(controller_params), pre_arm_params_(pre_arm), failsafe_params_(failsafe_params),
      failsafes_(failsafe_params), safety_(avoidance), period_s_(period_s), board_(board) {}

void ControlWorker::InjectFault(const control::CommandRequest& req, std::vector<CommandAck>* reports) {
  // A simulator fault changes the world, not what the vehicle does: no failsafe refuses it, and
  // a vehicle with no simulator behind it refuses it (a real receiver is not switched off from
  // the ground).
  const std::string name = req.command.Name();
  const std::string refused = inject_fault_ ? inject_fault_(req.command) : "no simulator: faults are injected only into a simulated vehicle";
  if (!refused.empty()) {
    reports->push_back({req.source, req.seq, name, CommandResult::kRejected, 0, refused});
    return;
  }
  reports->push_back({req.source, req.seq, name, CommandResult::kAccepted, 0, ""});
  reports->push_back({req.source, req.seq, name, CommandResult::kCompleted, 100, ""});
}

void ControlWorker::ServeParameters(const ParameterSet& params) {
  // Every setting a change reaches, built from the candidate set: what the constructors refuse
  // (inconsistent thresholds, a planning cell off the map's grid) refuses the change.
  parameters_.emplace(params, [](const ParameterSet& p) {
    control::TaskParams::FromParameters(p);
    control::ControllerParams::FromParameters(p);
    control::FailsafeParams::FromParameters(p);
    control::PreArmParams::FromParameters(p);
    avoid::AvoidancePlanner planner_check(avoid::AvoidanceParams::FromParameters(p));
  });
  board_.Update([&](BlackboardData& b) {
    b.params = std::make_shared<const ParameterSet>(params);
    b.params_version = 0;
  });
}

void ControlWorker::SetParameter(const control::CommandRequest& req, const BlackboardData& d, int64_t utime,
                                 std::vector<CommandAck>* reports) {
  CommandAck ack{req.source, req.seq, "param", CommandResult::kRejected, 0, ""};
  if (!parameters_) {
    ack.reason = "this vehicle does not serve its parameters";
    reports->push_back(ack);
    return;
  }
  const ParameterServer::Outcome o = parameters_->Set(req.command.parameter, req.command.args.at(0), d.armed);
  ack.result = o.accepted ? CommandResult::kCompleted : CommandResult::kRejected;
  ack.percent = o.accepted ? 100 : 0;
  ack.reason = o.message;
  reports->push_back(ack);
  if (!o.changed) return;  // the answer says why; a change is news for every GCS
  board_.PushStatus(Severity::kInfo, "parameter " + o.message);
  const ParameterSet& p = parameters_->params();
  tasks_.SetParams(control::TaskParams::FromParameters(p));
  controller_.SetParams(control::ControllerParams::FromParameters(p));
  failsafe_params_ = control::FailsafeParams::FromParameters(p);
  failsafes_.SetParams(failsafe_params_);
  pre_arm_params_ = control::PreArmParams::FromParameters(p);
  safety_.SetParams(avoid::AvoidanceParams::FromParameters(p));
  board_.Update([&](BlackboardData& b) {
    b.params = std::make_shared<const ParameterSet>(p);
    b.params_version = parameters_->version();
  });
  PublishParameters(utime);
}

void ControlWorker::PublishParameters(int64_t utime) {
  if (!parameters_) return;
  board_.reports.Put(ParameterTable::Of(parameters_->params(), parameters_->version(), utime));
  last_parameters_report_ = utime;
}

control::Setpoint ControlWorker::Avoid(const control::TaskManager::Output& out, const BlackboardData& d, int64_t utime,
                                       std::vector<CommandAck>* reports) {
  // Manual flight and failsafe landings are left alone; a failsafe's return goes through it.
  const std::optional<Eigen::Vector3d> goal = out.airborne ? out.goal_N : std::nullopt;
  const bool map_only = failsafes_.perception_lost();
  const avoid::SafetyLayer::Output a = safety_.Apply(out.setpoint, goal, d.estimate, d.avoid_plan.get(), utime, period_s_, map_only);
  tasks_.ObserveStandIn(a.stand_in_N, a.reason);
  board_.Update([&](BlackboardData& b) {
    b.avoid_request.active = a.state != avoid::AvoidState::kOff;
    b.avoid_request.map_only = map_only;
    if (goal) b.avoid_request.goal_N = *goal, b.avoid_request.via_N = out.setpoint.p_N;
    b.avoid_state = a.state;
    b.avoid_reason = a.reason;
    b.avoid_speed_limit = a.state == avoid::AvoidState::kOff ? -1.0 : a.speed_limit;
  });
  // The operator hears of each change of state once; a state that flaps (a slow sensor between
  // "avoiding" and "no data") is said once it settles, with how long it flapped. A new goal's
  // first plan is not news, nor is a clear way that follows nothing said.
  std::string state;
  if (a.state != avoid::AvoidState::kOff && !(a.state == avoid::AvoidState::kNoData && a.reason.rfind("no plan", 0) == 0)) {
    state = std::string(Name(a.state));
    std::replace(state.begin(), state.end(), '_', ' ');
    if (a.state == avoid::AvoidState::kClear) state = avoid_news_.said().empty() ? "" : "way clear";
  }
  if (const auto said = avoid_news_.Update(state, utime * 1e-6)) {
    const bool warn = a.state == avoid::AvoidState::kBlocked || a.state == avoid::AvoidState::kNoPath ||
                      a.state == avoid::AvoidState::kNoData;
    const std::string text = *said == state && !a.reason.empty() && a.state != avoid::AvoidState::kClear
                                 ? *said + ": " + a.reason
                                 : *said;
    board_.PushStatus(warn ? Severity::kWarning : Severity::kInfo, "obstacle avoidance: " + text);
    tasks_.ReportProgressNote(text, reports);
  }
  return a.setpoint;
}

void ControlWorker::CheckPreArm(const BlackboardData& d, int64_t utime) {
  if (d.armed) {
    tasks_.ObservePreArm("");
    return;
  }
  control::PreArmInputs in;
  in.gps_fix = d.sample.gps_fix;
  in.gps_satellites = d.sample.gps_satellites;
  in.position_source = d.position_source;
  in.p_N = d.estimate.p_N;
  in.v_N = d.estimate.v_N;
  in.attitude_covariance_B = d.estimate.attitude_covariance_B;
  in.sensor_age_s = (utime - d.sample.utime) * 1e-6;
  in.sensors_finite = d.sample.gyro_B.allFinite() && d.sample.accel_B.allFinite();
  in.battery_remaining = d.sample.battery_remaining;
  in.at_rest = d.at_rest;
  in.rest_tilt_rad = d.rest_tilt_rad;
  in.crash = d.ground_state == control::GroundState::kCrashed ? d.crash_reason : "";
  PreArmReport report;
  report.utime = utime;
  report.checks = control::EvaluatePreArm(in, pre_arm_params_);
  tasks_.ObservePreArm(report.Failing());
  if (last_pre_arm_report_ < 0 || utime - last_pre_arm_report_ >= 1000000) {
    board_.reports.Put(std::move(report));
    last_pre_arm_report_ = utime;
  }
}

void ControlWorker::Tick(int64_t utime) {
  const BlackboardData d = board_.Snapshot();
  const double t = utime * 1e-6;
  std::vector<CommandAck> reports;
  // Failsafes, then commands (refused if they would do less than the failsafes need), then the task.
  std::vector<std::string> events;
  if (missions_ && missions_->upload_count() != geofence_upload_) {
    // A new mission brings its geofence and rally points: in force at once, as PX4's.
    geofence_upload_ = missions_->upload_count();
    waypoints::Geofence fence = missions_->UploadedGeofence();
    if (!fence.empty())
      board_.PushStatus(Severity::kInfo, "geofence: " + std::to_string(fence.zones.size()) + " zones, " +
                                             std::to_string(fence.rally_N.size()) + " rally points in force");
    failsafes_.SetGeofence(fence);
    tasks_.SetGeofence(std::move(fence));
  }
  control::FailsafeInputs fin;
  fin.t = t;
  fin.airborne = d.airborne;
  fin.gcs_link_age_s = d.gcs_link_age_s;
  fin.battery_remaining = d.sample.battery_remaining;
  fin.p_N = d.estimate.p_N;
  fin.rc_manual = d.sample.rc_manual;
  // The INS on the IMU alone (no GPS fix, no visual position for a second) cannot hold a place.
  // A landing needs only the height (as PX4's Land mode): the cameras lose the ground in the last
  // metres, and holding there would only keep the vehicle in the air.
  fin.position_lost = d.position_source == PositionSource::kInertial && d.task != control::Task::kLand;
  fin.position_lost_reason = d.vision_unhealthy_reason.empty()
                                 ? "GPS lost and no visual odometry"
                                 : "GPS lost; visual odometry: " + d.vision_unhealthy_reason;
  // Obstacle perception lost in flight (it had come, and none for avd_blind_return): a stereo
  // camera failed. Only while avoidance flies a task: hovering, nothing needs it.
  if (safety_.params().enabled && d.airborne && d.avoid_request.active && d.avoid_plan && d.avoid_plan->perception_utime > 0) {
    const double age = (utime - d.avoid_plan->perception_utime) * 1e-6;
    fin.perception_lost = age > safety_.params().blind_return_s;
    char why[96];
    std::snprintf(why, sizeof why, "none for %.1f s", age);
    fin.perception_lost_reason = why;
    if (!d.obstacle_unhealthy_reason.empty()) fin.perception_lost_reason += " (" + d.obstacle_unhealthy_reason + ")";
  }
  const control::FailsafeAction required = failsafes_.Update(fin, &events);
  for (const auto& e : events) board_.PushStatus(e.rfind("failsafe", 0) == 0 || e.rfind("RC", 0) == 0 ? Severity::kWarning : Severity::kInfo, e);
  tasks_.EnforceFailsafe(required, failsafes_.reason(), d.estimate, t, &reports, failsafes_.perception_lost());
  // A crash stops the motors (ArduPilot's crash check disarms; PX4's failure detector terminates).
  if (d.ground_state == control::GroundState::kCrashed) tasks_.OnCrash(d.crash_reason, &reports);
  tasks_.ObserveTarget(d.target);
  tasks_.ObserveSticks(d.sticks);
  CheckPreArm(d, utime);
  for (const auto& req : board_.commands.TakeAll()) {
    if (req.command.id == CommandId::kParam) SetParameter(req, d, utime, &reports);
    else if (req.command.id == CommandId::kGps) InjectFault(req, &reports);
    else if (!(tailsitter_ && TailSitterCommand(req, d, &reports))) tasks_.Submit(req, d.estimate, t, &reports);
  }
  if (parameters_ && (last_parameters_report_ < 0 || utime - last_parameters_report_ >= 5'000'000)) PublishParameters(utime);
  const control::TaskManager::Output out = tasks_.Update(d.estimate, t, &reports);
  if (out.reset_controller) controller_.Reset();
  if (!out.note.empty()) board_.PushStatus(Severity::kInfo, out.note);
  if (tasks_.sticks_holding() != last_sticks_said_) {
    last_sticks_said_ = tasks_.sticks_holding();
    if (out.task == control::Task::kSticks)
      board_.PushStatus(Severity::kInfo, last_sticks_said_.empty() ? "sticks: flying" : "sticks: " + last_sticks_said_);
  }
  const control::Setpoint setpoint = Avoid(out, d, utime, &reports);
  // A setpoint that is not finite or leaves the envelope never reaches the controller. U-Lion's
  // envelope reaches its cruise speed: the mission's reference runs at it on the wing.
  const double speed_max_xy = tailsitter_ ? std::max(controller_.params().speed_max_xy, tailsitter_->controller.params().cruise_speed)
                                          : controller_.params().speed_max_xy;
  const std::string bad = control::CheckSetpoint(setpoint, failsafe_params_, speed_max_xy);
  if (bad.empty()) last_valid_setpoint_ = setpoint;
  if (bad != last_setpoint_error_ && !bad.empty()) board_.PushStatus(Severity::kError, "setpoint rejected: " + bad + "; holding the last valid one");
  last_setpoint_error_ = bad;
  control::ServoCommand servo;  // throttle -1: rotors off
  std::optional<TailSitterStatus> tailsitter;
  if (tailsitter_) {
    // U-Lion: its own controller in every mode (its RC link has no fail-safe switch wired).
    tailsitter.emplace();
    if (out.airborne) tailsitter->inputs = FlyTailSitter(out, last_valid_setpoint_, d, &reports);
    const control::TailSitterController& ctl = tailsitter_->controller;
    tailsitter->mode = ctl.mode();
    tailsitter->transition_progress = ctl.transition_progress();
    tailsitter->airspeed_mps = d.sample.airspeed_mps;
  } else if (required == control::FailsafeAction::kManual && out.airborne) {
    // Thesis 2.3.2 fail-safe switch: the pilot's sticks go straight to the servos.
    servo = {d.sample.rc_sticks[0], d.sample.rc_sticks[1], d.sample.rc_sticks[2], d.sample.rc_sticks[3]};
    controller_.Reset();
  } else if (out.airborne) {
    servo = controller_.Update(d.estimate, last_valid_setpoint_, period_s_);
    // System identification: the chirp goes on top of the controller's output (thesis 2.4.5).
    switch (out.chirp_channel) {
      case control::ServoChannel::kNone: break;
      case control::ServoChannel::kAileron: servo.aileron += out.chirp_value; break;
      case control::ServoChannel::kElevator: servo.elevator += out.chirp_value; break;
      case control::ServoChannel::kThrottle: servo.throttle += out.chirp_value; break;
      case control::ServoChannel::kRudder: servo.rudder += out.chirp_value; break;
    }
  }
  board_.Update([&](BlackboardData& b) {
    b.servo = servo;
    b.tailsitter = tailsitter;
    b.armed = out.armed;
    b.airborne = out.airborne;
    b.touched_down = out.touched_down;
    b.task = out.task;
    b.failsafe = required;
    b.mission_item = out.mission_item;
    b.capture_interval_s = out.capture_interval_s;
    b.capture_distance_m = out.capture_distance_m;
    b.chirp_channel = static_cast<int>(out.chirp_channel);
    b.fence_radius_m = failsafe_params_.fence_radius_m;
    b.fence_alt_m = failsafe_params_.fence_alt_m;
  });
  board_.task_reports.PushAll(reports);
  // Operator-facing events.
  if (out.armed != last_armed_)
    board_.PushStatus(Severity::kInfo, out.armed ? "armed" : "disarmed");
  if (out.task != last_task_) {
    char buf[160];
    const Eigen::Vector3d& p = out.setpoint.p_N;
    std::snprintf(buf, sizeof buf, "task %s (target N %.1f E %.1f alt %.1f m)",
                  std::string(Name(out.task)).c_str(), p.x(), p.y(), -p.z());
    board_.PushStatus(Severity::kInfo, buf);
  }
  const bool capturing = out.capture_interval_s || out.capture_distance_m;
  if (capturing != last_capturing_) board_.PushStatus(Severity::kInfo, capturing ? "camera capture on" : "camera capture off");
  last_capturing_ = capturing;
  last_armed_ = out.armed;
  last_task_ = out.task;
}

void ServoWorker::Tick(int64_t utime) {
  const BlackboardData d = board_.Snapshot();
  if (d.tailsitter) {
    // U-Lion's eight channels (airframe::ToChannels). On the ground the surfaces are neutral and the
    // battery at the tail (the hover CG); armed, the rotors idle.
    airframe::TailSitterInputs in;
    in.battery = 1.0;
    if (d.armed && d.airborne) in = d.tailsitter->inputs;
    hal::OutputChannels channels = airframe::ToChannels(in);
    if (!(d.armed && d.airborne)) channels[0] = d.armed ? rotor_input_idle_ : -1.0;
    backend_.WriteOutputs(channels);
    board_.Update([&](BlackboardData& b) { b.rotor_inputs = {channels[0], channels[0], -1, -1}; });
    return;
  }
  // Disarmed: stopped. Armed on the ground: idle, no lift. Flying: mixed, or to the gyro.
  std::array<double, 4> outputs = {-1.0, -1.0, -1.0, -1.0};
  std::array<double, 4> rotors = outputs;
  if (mode_ == hal::AttitudeMode::kDirect) {
    if (d.armed && d.airborne) rotors = control::MixToRotors(d.servo);
    else if (d.armed) rotors.fill(rotor_input_idle_);
    outputs = rotors;
  } else {
    // The gyro mixes; on the ground only the throttle channel moves (idle or off).
    control::ServoCommand c = d.servo;
    if (!(d.armed && d.airborne)) c = {0.0, 0.0, d.armed ? rotor_input_idle_ : -1.0, 0.0};
    outputs = {c.aileron, c.elevator, c.throttle, c.rudder};
    rotors.fill(c.throttle);  // the collective the gyro passes on (thesis 2.5)
  }
  hal::OutputChannels channels = hal::UnwiredChannels();
  std::copy(outputs.begin(), outputs.end(), channels.begin());
  backend_.WriteOutputs(channels);
  board_.Update([&](BlackboardData& b) { b.rotor_inputs = rotors; });
}

void LogWorker::Tick(int64_t utime) {
  if (!log_) return;
  const BlackboardData d = board_.Snapshot();
  log_->Write(utime, d, board_.reports.Columns());
  if (was_airborne_ && !d.airborne) {
    // Touchdown: the log up to here, named by the landing (a later offer holds the next flight).
    log_->Flush();
    const std::filesystem::path path(log_->path());
    const std::string name = path.stem().string() + "_landing" + std::to_string(++landings_) + ".csv";
    try {
      board_.downloads.Push({name, ReadTextFile(path.string(), "flight log")});
    } catch (const std::exception& e) {
      board_.PushStatus(Severity::kWarning, std::string("flight log not offered for download: ") + e.what());
    }
  }
  was_airborne_ = d.airborne;
}

}  // namespace uav::runtime
