// The control thread's U-Lion part (thesis 2.6): the tail-sitter's controller in place of the
// quadrotor's, its transitions, and the task manager's setpoints turned into hover positions,
// legs on the wing and loiter circles.
#include <cmath>

#include "uav/runtime/workers.hpp"

namespace uav::runtime {
namespace {

// A loiter circle this many turn radii across: the bank it needs leaves the controller margin.
constexpr double kLoiterRadii = 1.5;
// On the wing a waypoint counts as reached within this share of the turn radius, so the turn to
// the next leg starts where it can.
constexpr double kAcceptanceRadii = 0.5;
// A leg continues from the last one's end when the vehicle is within this many acceptance radii
// of it (a path's next leg); otherwise it starts where the vehicle is (a new goto).
constexpr double kContinueLegRadii = 3.0;
// A path's leg at least this many loiter radii long is flown on the wing; the front transition
// starts once the belly faces the leg's end within this [rad].
constexpr double kWingLegLoiterRadii = 2.0;
constexpr double kTransitionHeadingError = 10 * M_PI / 180;
// A landing's approach on the wing ends this close above ts_land_approach_alt [m].
constexpr double kApproachAltitudeTolerance = 2.0;
// The hover lets go of the point where the back transition stopped once this slow [m/s].
constexpr double kReleaseHoldSpeed = 0.5;

bool OnTheWing(control::TailSitterMode m) {
  return m == control::TailSitterMode::kCruise || m == control::TailSitterMode::kTransitionToWing;
}

double BellyHeading(const hal::VehicleEstimate& est) {
  const Eigen::Vector3d belly = est.q_NB * Eigen::Vector3d::UnitZ();
  return std::atan2(belly.y(), belly.x());
}

}  // namespace

control::WingBorne ControlWorker::WingBorne() const {
  const control::TailSitterController& ctl = tailsitter_->controller;
  return {kAcceptanceRadii * ctl.TurnRadius(), ctl.params().cruise_speed, kLoiterRadii * ctl.TurnRadius()};
}

void ControlWorker::UseTailSitter(const control::TailSitterControlParams& params) {
  tailsitter_.emplace(params);
}

bool ControlWorker::TailSitterCommand(const control::CommandRequest& req, const BlackboardData& d,
                                      std::vector<CommandAck>* reports) {
  const Command& c = req.command;
  auto reject = [&](const std::string& why) {
    reports->push_back({req.source, req.seq, c.Name(), CommandResult::kRejected, 0, why});
    return true;
  };
  const control::TailSitterMode mode = tailsitter_->controller.mode();
  if (c.id == CommandId::kChirp) return reject("chirp excites the X650's servo channels; U-Lion has none of them");
  if ((c.id == CommandId::kSticks || c.id == CommandId::kFollow) && mode != control::TailSitterMode::kHover)
    return reject("U-Lion is in " + Spoken(Name(mode)) + ": transition mc to hover first");
  if (c.id != CommandId::kTransition) return false;
  const bool to_wing = c.args.at(0) == 1.0;
  if (!d.airborne) return reject("not flying: take off first");
  // A failsafe, not the operator's own `hover` or `land` (which also raise the task's level).
  if (failsafes_.required() != FailsafeAction::kNone)
    return reject("failsafe " + std::string(Name(failsafes_.required())) + " active: " + failsafes_.reason());
  if (tailsitter_->transition) return reject("a transition is already being carried out");
  const std::string why = tailsitter_->controller.StartTransition(to_wing, d.estimate);
  if (!why.empty()) return reject(why);
  reports->push_back({req.source, req.seq, c.Name(), CommandResult::kAccepted, 0, ""});
  tailsitter_->transition = CommandAck{req.source, req.seq, c.Name(), CommandResult::kInProgress, 0, ""};
  tailsitter_->transition_to_wing = to_wing;
  board_.PushStatus(Severity::kInfo, to_wing ? "transition to the wing" : "transition to hover");
  return true;
}

airframe::TailSitterInputs ControlWorker::FlyTailSitter(const control::TaskManager::Output& out, const control::Setpoint& setpoint,
                                                   const BlackboardData& d, std::vector<CommandAck>* reports) {
  TailSitterControl& ts = *tailsitter_;
  control::TailSitterController& ctl = ts.controller;
  const hal::VehicleEstimate& est = d.estimate;
  // Back to hover on its own before a landing (a wing cannot land here) and on a failsafe that
  // holds or lands. A failsafe return flies home on the wing, as PX4's VTOL return does: U-Lion
  // cruises 40 minutes on a pack it hovers on for under 4, so a return in hover from the fence
  // would end in the battery's forced landing; the landing at home transitions back.
  const FailsafeAction failsafe = failsafes_.required();
  const bool failsafe_hover = failsafe != FailsafeAction::kNone && failsafe != FailsafeAction::kReturn;
  const bool landing = out.task == control::Task::kLand || setpoint.descent_rate;
  // A landing from the wing first circles its point down to ts_land_approach_alt (hover costs 11
  // times the cruise's power) and transitions on that circle, a loiter radius from the point; a
  // failsafe that lands transitions where it is.
  const bool approach = landing && !failsafe_hover && ctl.mode() == control::TailSitterMode::kCruise &&
                        (est.altitude() > ctl.params().land_approach_alt + kApproachAltitudeTolerance ||
                         !WingBorne().OnLoiterCircle(Eigen::Vector3d(setpoint.p_N.x(), setpoint.p_N.y(), est.p_N.z()), est.p_N));
  if (approach && !ts.approaching)
    board_.PushStatus(Severity::kInfo, "landing: circling down on the wing to " +
                                           std::to_string(static_cast<int>(ctl.params().land_approach_alt)) + " m");
  ts.approaching = approach;
  const bool must_hover = (landing && !approach) || failsafe_hover;
  if (must_hover && OnTheWing(ctl.mode()) && ctl.StartTransition(false, est).empty()) {
    board_.PushStatus(Severity::kInfo, landing ? "transition to hover before landing"
                                               : "transition to hover: failsafe " + std::string(Name(failsafe)));
    if (ts.transition) {
      CommandAck ack = *ts.transition;
      ack.result = CommandResult::kFailed;
      ack.reason = "replaced by the transition to hover";
      reports->push_back(ack);
      ts.transition.reset();
    }
  }
  control::TailSitterSetpoint sp;
  sp.p_N = setpoint.p_N;
  const double turn_radius = ctl.TurnRadius();
  const bool path = out.task == control::Task::kTrack || out.task == control::Task::kMission || out.task == control::Task::kReturn;
  // A path's leg long enough for the wing is flown on it (PX4's VTOL missions transition after the
  // take-off): the belly turns toward the leg's end, then the front transition goes that way.
  if (path && !must_hover && out.goal_N && ctl.mode() == control::TailSitterMode::kHover && !ctl.holding()) {
    const Eigen::Vector2d to_end = out.goal_N->head<2>() - est.p_N.head<2>();
    if (to_end.norm() > kWingLegLoiterRadii * WingBorne().loiter_radius_m) {
      ts.hover_heading = std::atan2(to_end.y(), to_end.x());
      sp.face_heading = true;
      const double error = std::abs(std::remainder(BellyHeading(est) - ts.hover_heading, 2 * M_PI));
      if (error < kTransitionHeadingError && ctl.StartTransition(true, est).empty())
        board_.PushStatus(Severity::kInfo, "transition to the wing for the " + std::string(Name(out.task)));
    }
  }
  if (OnTheWing(ctl.mode())) {
    const Eigen::Vector3d goal = out.goal_N.value_or(setpoint.p_N);
    if (!ts.leg_to_N || (goal - *ts.leg_to_N).norm() > 1.0) {
      const bool continues = ts.leg_to_N && (est.p_N - *ts.leg_to_N).head<2>().norm() < kContinueLegRadii * kAcceptanceRadii * turn_radius;
      ts.leg_from_N = continues ? *ts.leg_to_N : est.p_N;
      ts.leg_to_N = goal;
    }
    sp.p_N = goal;
    const control::WingBorne wing = WingBorne();
    // A held point (a goto reached, a hover) is circled; a goto's target once on its circle.
    const bool hold = out.task != control::Task::kGoto;
    if (approach) {
      sp.p_N = Eigen::Vector3d(setpoint.p_N.x(), setpoint.p_N.y(), -ctl.params().land_approach_alt);
      sp.heading = control::OrbitCourse(setpoint.p_N.head<2>(), est.p_N.head<2>(), wing.loiter_radius_m);
    } else if (!path && (hold || wing.OnLoiterCircle(Eigen::Vector3d(goal.x(), goal.y(), est.p_N.z()), est.p_N))) {
      sp.heading = control::OrbitCourse(goal.head<2>(), est.p_N.head<2>(), wing.loiter_radius_m);
    } else {
      sp.leg_from_N = ts.leg_from_N;
    }
  } else {
    ts.leg_from_N.reset();
    ts.leg_to_N.reset();
    sp.heading = ts.hover_heading;
    // After a back transition the hover holds where it could stop; once stopped it goes on to the
    // setpoint, and a landing descends only when it is over its point.
    if (ctl.holding() && ctl.mode() == control::TailSitterMode::kHover && est.v_N.head<2>().norm() < kReleaseHoldSpeed)
      ctl.ReleaseHold();
    const bool over = (setpoint.p_N - est.p_N).head<2>().norm() < tasks_.params().reached_radius;
    if (setpoint.descent_rate && !ctl.holding() && over) sp.descent_rate = setpoint.descent_rate;
    if (setpoint.descent_rate && !sp.descent_rate) sp.p_N.z() = est.p_N.z();
  }
  tasks_.DeferDescent(setpoint.descent_rate && !sp.descent_rate);
  const double airspeed = d.sample.airspeed_valid ? d.sample.airspeed_mps : est.v_N.norm();
  const airframe::TailSitterInputs u = ctl.Update(est, airspeed, sp, period_s_);
  // Mode changes: the task manager flies through corners on the wing; transitions end.
  if (ctl.mode() != ts.last_mode) {
    const control::TailSitterMode m = ctl.mode();
    board_.PushStatus(Severity::kInfo, "U-Lion: " + Spoken(Name(m)));
    if (m == control::TailSitterMode::kCruise)
      tasks_.SetWingBorne(WingBorne());
    else if (ts.last_mode == control::TailSitterMode::kCruise)
      tasks_.SetWingBorne(std::nullopt);
    if (m == control::TailSitterMode::kHover) ts.hover_heading = BellyHeading(est);
    if (ts.transition && (m == control::TailSitterMode::kCruise || m == control::TailSitterMode::kHover)) {
      // Done when it ends where it was asked to go; a front transition that aborted ends in hover.
      CommandAck ack = *ts.transition;
      const bool done = (m == control::TailSitterMode::kCruise) == ts.transition_to_wing;
      ack.result = done ? CommandResult::kCompleted : CommandResult::kFailed;
      ack.percent = done ? 100 : 0;
      ack.reason = done ? "" : ctl.event().empty() ? "ended in " + Spoken(Name(m)) : ctl.event();
      reports->push_back(ack);
      ts.transition.reset();
    }
    ts.last_mode = m;
  }
  if (ctl.event() != ts.last_event) {
    if (!ctl.event().empty()) board_.PushStatus(Severity::kWarning, ctl.event());
    ts.last_event = ctl.event();
  }
  return u;
}

}  // namespace uav::runtime
