#include "uav/avoid/safety_layer.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace uav::avoid {

namespace {
double WrapPi(double a) { return std::remainder(a, 2.0 * M_PI); }
// Below this the vehicle is taken as stopped short (blocked); above twice it moves again.
constexpr double kBlockedSpeed = 0.2;
// [m/s] above this the vehicle's velocity gives the way it travels (turns are measured from it).
constexpr double kTravelSpeed = 0.5;
// [m/s] the last body-and-margin's length to a goal is flown at least this fast.
constexpr double kArrivalSpeed = 0.5;
// [rad] beyond the edge of the watching pair's view the speed falls over this angle to what
// stops the vehicle within its clearance.
constexpr double kViewEdge = 10.0 * M_PI / 180.0;
// [m] how far inside a corner of the detour the vehicle may cut. The planner's shortcuts keep
// the clearance plus a small margin at their corners, which lie on the obstacles they turn
// round: a carrot chased round a corner cuts it toward that obstacle (by 0.35 of the lead at a
// right angle, 0.7 m with a 2 m lead).
constexpr double kCornerCut = 0.2;

// The fastest the vehicle may pass a corner where the path turns by `deflection` [rad]: on the
// arc that stays within kCornerCut of the corner, r = kCornerCut / (1 / cos(deflection / 2) - 1),
// with `accel` as the lateral acceleration, v = sqrt(accel r).
double CornerSpeed(double deflection, double accel) {
  const double c = std::cos(0.5 * std::min(deflection, M_PI - 1e-3));
  return std::sqrt(accel * kCornerCut / (1.0 / c - 1.0 + 1e-9));
}

// The carrot: lookahead_m on along the path from arc length s, brought nearer while the straight
// way from p to it strays more than kCornerCut from the path's corners in between.
Eigen::Vector3d Carrot(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& p, double s, double lookahead_m) {
  double lead = lookahead_m;
  for (; lead > 0.25; lead *= 0.8) {
    const Eigen::Vector3d carrot = PointAt(path, s + lead);
    const Eigen::Vector3d chord = carrot - p;
    bool within = true;
    double along = 0.0;
    for (std::size_t i = 1; within && i + 1 < path.size(); ++i) {
      along += (path[i] - path[i - 1]).norm();
      if (along <= s) continue;
      if (along >= s + lead) break;
      const double t = chord.squaredNorm() > 1e-12 ? std::clamp((path[i] - p).dot(chord) / chord.squaredNorm(), 0.0, 1.0) : 0.0;
      within = (p + t * chord - path[i]).norm() <= kCornerCut;
    }
    if (within) return carrot;
  }
  return PointAt(path, s + lead);
}

// The fastest the vehicle may fly along `leg` without leaving it: the position controller
// bounds the climb and the sink (ctl_speed_max_up, ctl_speed_max_down) apart from the speed across
// the ground, so on a leg steeper than those allow it keeps its ground speed and falls behind the
// leg's height. On a dive under a cable (6.2 to 3.0 m up over 3.5 m, 1/12 field, seed 82) it flew
// 3.2 m/s across the ground sinking at 1 m/s: above the dive and toward the cable. Along the leg,
// v <= v_sink |leg| / |dz| (v_climb going up).
double SlopeSpeed(const Eigen::Vector3d& leg_N, const AvoidanceParams& p) {
  const double dz = leg_N.z();  // down
  if (std::abs(dz) < 1e-9) return 1e9;
  return (dz > 0 ? p.sink_speed : p.climb_speed) * leg_N.norm() / std::abs(dz);
}

// The same across the ground: v_xy <= v_sink |leg_xy| / |dz|.
double GroundSpeedOnSlope(const Eigen::Vector3d& leg_N, const AvoidanceParams& p) {
  return leg_N.norm() < 1e-9 ? 1e9 : SlopeSpeed(leg_N, p) * leg_N.head<2>().norm() / leg_N.norm();
}

// The speed that lets the vehicle slow, after its reaction time, to the speed of each leg within
// reach from arc length s: the speed of its turn and of its slope (SlopeSpeed). A turn is
// measured from the way the vehicle travels now (its velocity, `travel`) to each leg ahead, not
// corner by corner: three corners of 50 degrees within a metre are one hairpin, and a replanned
// path may leave at a right angle to the way the vehicle flies (it carried on 2 m toward a trunk
// while it turned round, 1/25 field, seed 11). The leg the vehicle is on is taken at once.
double LegLimit(const std::vector<Eigen::Vector3d>& path, double s, const Eigen::Vector3d& travel, const AvoidanceParams& p,
                double speed) {
  const double accel = p.brake_accel, reaction_s = p.reaction_s;
  double limit = speed, along = 0.0;
  auto leg_speed = [&](const Eigen::Vector3d& leg) {
    if (leg.norm() < 1e-6) return speed;
    const double deflection = std::acos(std::clamp(travel.dot(leg.normalized()), -1.0, 1.0));
    return std::min(std::max(kArrivalSpeed, CornerSpeed(deflection, accel)), SlopeSpeed(leg, p));
  };
  const double reach = speed * reaction_s + speed * speed / (2 * accel) + 1.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const double start = along;
    along += (path[i] - path[i - 1]).norm();
    if (along <= s) continue;
    const double d = std::max(0.0, start - s);
    if (d > reach) break;
    const double v = leg_speed(path[i] - path[i - 1]);
    limit = std::min(limit, d <= 0.0 ? v : -accel * reaction_s + std::sqrt(accel * accel * reaction_s * reaction_s + v * v + 2 * accel * d));
  }
  return limit;
}
}  // namespace

control::Setpoint SafetyLayer::Hold(const control::Setpoint& task_setpoint, const hal::VehicleEstimate& est) {
  // Brake to where the vehicle can stop, then stay there.
  if (!hold_N_) {
    const Eigen::Vector3d v = est.v_N;
    hold_N_ = est.p_N + v * (v.norm() / (2.0 * p_.brake_accel));
  }
  control::Setpoint sp = task_setpoint;
  sp.p_N = *hold_N_;
  sp.v_ff_N.setZero();
  sp.descent_rate.reset();
  sp.yaw_rate_ff = 0.0;
  if (yaw_ref_) sp.yaw = *yaw_ref_;
  return sp;
}

double SafetyLayer::FaceTravel(const Eigen::Vector3d& direction_N, const hal::VehicleEstimate& est, double dt) {
  if (!yaw_ref_) yaw_ref_ = est.euler.psi;
  yaw_rate_ = 0.0;
  if (direction_N.head<2>().norm() > 0.5) {
    const double want = std::atan2(direction_N.y(), direction_N.x());
    const double step = std::clamp(WrapPi(want - *yaw_ref_), -p_.yaw_rate * dt, p_.yaw_rate * dt);
    yaw_ref_ = WrapPi(*yaw_ref_ + step);
    // The reference's rate goes with it: without it the yaw loop trails a turn at 1 rad/s by
    // the rate times ctl_yaw_rate_gain / ctl_yaw_gain, and the cameras look that far behind.
    if (dt > 0) yaw_rate_ = step / dt;
  }
  return *yaw_ref_;
}

void SafetyLayer::ObservePerception(int64_t perception_utime) {
  if (perception_utime <= last_perception_utime_) return;
  // A gap of seconds (a camera that stopped, then came back) is not the sensor's rate.
  const double interval = (perception_utime - last_perception_utime_) * 1e-6;
  if (last_perception_utime_ > 0 && interval < 5.0) {
    periods_s_[next_period_] = interval;
    next_period_ = (next_period_ + 1) % kPeriods;
  }
  last_perception_utime_ = perception_utime;
}

double SafetyLayer::PerceptionPeriod() const { return *std::max_element(periods_s_, periods_s_ + kPeriods); }

double SafetyLayer::StaleAfter() const { return std::max(p_.stale_s, 2.0 * PerceptionPeriod()); }

SafetyLayer::Output SafetyLayer::Apply(const control::Setpoint& task_setpoint, const std::optional<Eigen::Vector3d>& goal_N,
                                       const hal::VehicleEstimate& est, const AvoidancePlan* plan, int64_t utime, double dt,
                                       bool map_only) {
  Output out;
  out.setpoint = task_setpoint;
  auto finish = [&](AvoidState s) {
    out.state = s;
    out.changed = s != state_;
    state_ = s;
    if (s != AvoidState::kNoData && s != AvoidState::kNoPath && s != AvoidState::kBlocked) hold_N_.reset();
    return out;
  };
  if (!p_.enabled || !goal_N) {
    yaw_ref_.reset();
    blocked_ = false;
    return finish(AvoidState::kOff);
  }
  if (plan && plan->perception_utime > 0) ObservePerception(plan->perception_utime);
  const double perception_age = plan && plan->perception_utime > 0 ? (utime - plan->perception_utime) * 1e-6 : 1e9;
  const double plan_age = plan ? (utime - plan->utime) * 1e-6 : 1e9;
  const double stale_s = StaleAfter();
  char buf[200];
  if (map_only && (!plan || !plan->map_only)) {
    // The map alone from now on: what was planned with the perception counts no more.
    out.reason = "obstacle perception lost: planning on the map alone; holding";
    out.setpoint = Hold(task_setpoint, est);
    return finish(AvoidState::kNoData);
  }
  if (perception_age > stale_s && !map_only) {
    if (perception_age > 1e8) std::snprintf(buf, sizeof buf, "no obstacle perception yet: holding");
    else std::snprintf(buf, sizeof buf, "obstacle perception %.1f s old (limit %.1f s): holding", perception_age, stale_s);
    out.reason = buf;
    out.setpoint = Hold(task_setpoint, est);
    return finish(AvoidState::kNoData);
  }
  if (plan_age > stale_s || (plan->goal_N - *goal_N).norm() > 2.0) {
    std::snprintf(buf, sizeof buf, "no plan to the goal for %.1f s: holding", std::min(plan_age, 99.0));
    // A new goal waits one replanning period for its first plan; only then is it said.
    out.reason = buf;
    out.setpoint = Hold(task_setpoint, est);
    return finish(AvoidState::kNoData);
  }
  if (plan->state == AvoidState::kNoPath) {
    out.reason = plan->reason + "; holding";
    out.setpoint = Hold(task_setpoint, est);
    return finish(AvoidState::kNoPath);
  }
  // The speed the seen space allows, from where the vehicle is now along the plan's path.
  const double s_now = ArcLengthOf(plan->path_N, est.p_N);
  const double d = std::max(0.0, plan->seen_free_m - s_now);
  // On the map alone the space seen free is what there is: the plan's age stands for the
  // perception's.
  const double a = p_.brake_accel,
               t = (map_only ? plan_age : std::max(perception_age, PerceptionPeriod())) + p_.reaction_s;
  const double arrival_m = p_.clearance();
  const bool arriving = (*goal_N - est.p_N).norm() <= arrival_m;
  // Within the clearance of its goal the vehicle's own body and margin already cover the rest of
  // the way (the planner ends short of a goal nearer an obstacle than that): it goes there at an
  // approach speed instead of holding short of a goal it was given (space just beside the goal
  // may never be seen free when only sky is behind it, or when the cameras are gone).
  double v_allow = std::max(arriving ? kArrivalSpeed : 0.0, -a * t + std::sqrt(a * a * t * t + 2.0 * a * d));
  out.speed_limit = v_allow;
  const double to_go = (plan->path_N.back() - est.p_N).norm();
  // Blocked when the seen space no longer lets it move and it is not at its goal; it moves again
  // once twice the threshold is allowed (hysteresis: no creeping start-stop).
  blocked_ = blocked_ ? v_allow < 2 * kBlockedSpeed : v_allow < kBlockedSpeed;
  if (blocked_ && to_go > arrival_m && !arriving) {
    std::snprintf(buf, sizeof buf, "stopped: %.1f m seen free ahead", d);
    out.reason = buf;
    out.setpoint = Hold(task_setpoint, est);
    // Keep turning toward the way on: the cameras may see it free.
    out.setpoint.yaw = FaceTravel(PointAt(plan->path_N, s_now + p_.lookahead_m) - est.p_N, est, dt);
    out.setpoint.yaw_rate_ff = yaw_rate_;
    return finish(AvoidState::kBlocked);
  }
  hold_N_.reset();
  control::Setpoint sp = task_setpoint;
  AvoidState state = AvoidState::kClear;
  Eigen::Vector3d direction = sp.p_N - est.p_N;
  if (plan->state == AvoidState::kAvoiding) {
    state = AvoidState::kAvoiding;
    out.reason = plan->reason;  // why the detour stops short of the goal, when it does
    // Only a plan for this very goal (a plan for the goal before may be flown for a step).
    if (plan->stops_short && !plan->path_N.empty() && (plan->goal_N - *goal_N).norm() < 0.01) out.stand_in_N = plan->path_N.back();
    const Eigen::Vector3d carrot = Carrot(plan->path_N, est.p_N, s_now, p_.lookahead_m);
    sp.p_N = carrot;
    direction = PointAt(plan->path_N, s_now + p_.lookahead_m) - est.p_N;
    const double cruise = std::min(p_.cruise_speed, task_setpoint.speed_max_xy.value_or(p_.cruise_speed));
    const Eigen::Vector3d tangent = PointAt(plan->path_N, s_now + 0.5) - PointAt(plan->path_N, s_now);
    // The way the vehicle travels: its velocity, or at low speed the path's own direction.
    if (est.v_N.norm() > kTravelSpeed || tangent.norm() > 1e-6) {
      const Eigen::Vector3d travel = est.v_N.norm() > kTravelSpeed ? est.v_N.normalized() : tangent.normalized();
      v_allow = std::min(v_allow, LegLimit(plan->path_N, s_now, travel, p_, cruise));
    }
    out.speed_limit = v_allow;
    sp.v_ff_N = tangent.norm() > 1e-6 && to_go > p_.lookahead_m ? Eigen::Vector3d(tangent.normalized() * std::min(cruise, v_allow))
                                                                : Eigen::Vector3d::Zero();
    sp.descent_rate.reset();
    sp.yaw_rate_ff = 0.0;
    // The controller bounds the climb and the sink apart from the speed across the ground and
    // the 3-D speed after both, so the carrot's pull alone (gain times lead) keeps the ground
    // speed and loses the height: across the ground the vehicle goes only as fast as its climb
    // or sink lets it keep to the way to the carrot (and to the leg it is on).
    const Eigen::Vector3d chord = carrot - est.p_N;
    const double ground = std::min(GroundSpeedOnSlope(chord, p_), GroundSpeedOnSlope(tangent, p_));
    // Never above the task's own limit (a task may ask for less than the arrival speed).
    if (ground < std::min(cruise, v_allow)) sp.speed_max_xy = std::min(cruise, std::max(kArrivalSpeed, ground));
  }
  // Moving where the watching pair does not look (PX4 Collision Prevention's CP_GO_NO_DATA): the
  // nose turns at avd_yaw_rate while a new detour may leave at a right angle at once, and the
  // space beside the cells seen free on it may never have been in view. There the vehicle goes
  // only as fast as it stops within its clearance: 1/12 seed 15 crossed the end of a wall that
  // was not in the map, its nose 50 degrees off its course, at 2.5 m/s.
  if (plan->view_half_rad > 0) {
    const Eigen::Vector2d way = est.v_N.head<2>().norm() > kTravelSpeed ? Eigen::Vector2d(est.v_N.head<2>()) : Eigen::Vector2d(direction.head<2>());
    if (way.norm() > 1e-6) {
      const double off = std::abs(WrapPi(std::atan2(way.y(), way.x()) - est.euler.psi - plan->view_azimuth_B));
      const double unseen = std::clamp((off - plan->view_half_rad) / kViewEdge, 0.0, 1.0);
      const double blind = -a * t + std::sqrt(a * a * t * t + 2.0 * a * p_.clearance());
      if (blind < v_allow) v_allow += unseen * (blind - v_allow);
      out.speed_limit = v_allow;
    }
  }
  // The limit holds for the speed in 3-D, not only across the ground: the stopping distance is
  // the same climbing. Applied to the horizontal speed alone, a detour climbing at the vehicle's
  // climb rate outran it (1/12 field, seed 3: 2.9 m/s, 2.4 of it upward, on a path that allowed
  // 1.0-1.5 m/s, into the side of a crown it had not seen).
  const double limit = std::max(0.05, v_allow);
  if (limit < p_.cruise_speed) sp.speed_max = limit;
  if (sp.v_ff_N.norm() > limit) sp.v_ff_N *= limit / sp.v_ff_N.norm();
  sp.yaw = FaceTravel(direction, est, dt);
  sp.yaw_rate_ff = yaw_rate_;
  out.setpoint = sp;
  return finish(state);
}

}  // namespace uav::avoid
