#include "uav/control/mission_runner.hpp"

#include <algorithm>
#include <cmath>

namespace uav::control {

using waypoints::MissionStep;
using Kind = waypoints::MissionStep::Kind;

namespace {
bool IsPosition(const MissionStep& s) { return s.kind == Kind::kWaypoint; }
}  // namespace

MissionRunner::MissionRunner(std::vector<MissionStep> steps, const MissionRunnerParams& p,
                             const VehicleEstimate& est)
    : steps_(std::move(steps)), p_(p), ref_(est.p_N), target_(est.p_N), yaw_(est.euler.psi),
      asked_speed_(p.speed_max_xy), speed_(p.speed_max_xy) {
  // Path length for progress: the waypoints in order from where we are.
  Eigen::Vector3d at = est.p_N;
  for (const auto& s : steps_) {
    if (s.kind == Kind::kWaypoint) total_length_ += (s.p_N - at).norm(), at = s.p_N;
    if (s.kind == Kind::kTakeoff) {
      const Eigen::Vector3d up(at.x(), at.y(), -s.altitude_m);
      total_length_ += (up - at).norm(), at = up;
    }
    if (s.kind == Kind::kReturnHome) {
      const Eigen::Vector3d home(0, 0, at.z());
      total_length_ += (home - at).norm() - at.z(), at = Eigen::Vector3d::Zero();
    }
  }
  Advance();
}

bool MissionRunner::IsStopAfter(std::size_t step) const {
  // A waypoint is flown through when the next position step continues within 30 degrees and no
  // step in between needs the vehicle to be there (landing, return).
  const Eigen::Vector3d& here = steps_[step].p_N;
  Eigen::Vector3d before = ref_;
  for (std::size_t k = step + 1; k < steps_.size(); ++k) {
    const auto& s = steps_[k];
    if (s.kind == Kind::kSetSpeed || s.kind == Kind::kCaptureStart || s.kind == Kind::kCaptureStop) continue;
    if (!IsPosition(s)) return true;
    const Eigen::Vector3d in = here - before, out = s.p_N - here;
    if (in.norm() < 1e-6 || out.norm() < 1e-6) return out.norm() >= 1e-6;
    return in.normalized().dot(out.normalized()) < std::cos(30.0 * M_PI / 180.0);
  }
  return true;
}

void MissionRunner::SetSpeedLimits(double speed_max_xy, double speed_max_up, double speed_max_down) {
  p_.speed_max_xy = speed_max_xy, p_.speed_max_up = speed_max_up, p_.speed_max_down = speed_max_down;
  speed_ = std::min(asked_speed_, p_.speed_max_xy);
}

void MissionRunner::Advance() {
  moving_ = false;
  while (index_ < steps_.size()) {
    const MissionStep& s = steps_[index_];
    switch (s.kind) {
      case Kind::kSetSpeed:
        asked_speed_ = s.value;
        speed_ = std::min(asked_speed_, p_.speed_max_xy);
        ++index_;
        continue;
      case Kind::kCaptureStart:
        if (s.value > 0) capture_interval_s_ = s.value, capture_distance_m_.reset();
        else capture_distance_m_ = -s.value, capture_interval_s_.reset();
        ++index_;
        continue;
      case Kind::kCaptureStop:
        capture_interval_s_.reset(), capture_distance_m_.reset();
        ++index_;
        continue;
      case Kind::kWaypoint:
        leg_from_ = target_;
        target_ = s.p_N;
        if (!std::isnan(s.yaw_rad)) yaw_ = s.yaw_rad;
        moving_ = true;
        return;
      case Kind::kTakeoff:
        target_ = Eigen::Vector3d(ref_.x(), ref_.y(), -s.altitude_m);
        moving_ = true;
        return;
      case Kind::kReturnHome: {
        // Climb (or stay) to the return altitude over here, fly home (or to the nearest rally
        // point) at it, then land.
        if (!return_to_) {
          return_to_ = Eigen::Vector2d::Zero();
          for (std::size_t k = 0; k < p_.rally_N.size(); ++k)
            if (k == 0 || (p_.rally_N[k] - ref_.head<2>()).norm() < (*return_to_ - ref_.head<2>()).norm())
              return_to_ = p_.rally_N[k];
        }
        // At the step's altitude when it has one, else climbing to the return altitude.
        const double alt = s.altitude_m > 0 ? s.altitude_m : std::max(-ref_.z(), p_.return_alt);
        if (-ref_.z() < alt - 0.5 * p_.reached_radius) {
          target_ = Eigen::Vector3d(ref_.x(), ref_.y(), -alt);
        } else if ((ref_.head<2>() - *return_to_).norm() > 0.5 * p_.reached_radius) {
          target_ = Eigen::Vector3d(return_to_->x(), return_to_->y(), -alt);
        } else {
          landing_ = true;
          target_ = Eigen::Vector3d(return_to_->x(), return_to_->y(), ref_.z());
          return;
        }
        moving_ = true;
        return;
      }
      case Kind::kHold:  // at the point just reached (a stop: see IsStopAfter)
        hold_left_s_ = s.value;
        holding_ = true;
        return;
      case Kind::kLand:
        if (!std::isnan(s.p_N.x()) && (s.p_N.head<2>() - ref_.head<2>()).norm() > 0.5 * p_.reached_radius) {
          target_ = Eigen::Vector3d(s.p_N.x(), s.p_N.y(), ref_.z());
          moving_ = true;
          return;
        }
        landing_ = true;
        return;
    }
  }
  done_ = true;
}

MissionRunner::Output MissionRunner::Update(const VehicleEstimate& est, double dt) {
  Output o;
  Eigen::Vector3d v_ff = Eigen::Vector3d::Zero();
  if (holding_) {
    hold_left_s_ -= dt;
    if (hold_left_s_ <= 0.0) {
      holding_ = false;
      ++index_;
      Advance();
    }
  }
  if (moving_ && !landing_) {
    const Eigen::Vector3d to_go = target_ - ref_;
    double dist = to_go.norm();
    const bool stop = index_ < steps_.size() && (steps_[index_].kind != Kind::kWaypoint || (!wing_ && IsStopAfter(index_)));
    if (!waiting_) {
      const Eigen::Vector3d dir = dist > 1e-9 ? Eigen::Vector3d(to_go / dist) : Eigen::Vector3d::Zero();
      // A vehicle more than a leash away and ahead of the reference along the leg (back from a
      // detour around an obstacle, or a wing that outran the hover's reference in its front
      // transition) takes the reference along to where it is, up to the leg's end: the leash
      // below would otherwise hold the reference short of it for good.
      const double ahead = (est.p_N - ref_).dot(dir);
      if (ahead > 0.0 && (est.p_N - ref_).norm() > p_.leash) {
        const double jump = std::min(ahead, dist);
        ref_ += dir * jump;
        flown_length_ += jump;
        dist -= jump;
      }
      // Cruise speed, reduced so the vertical part stays within the climb/descent limits.
      double cruise = wing_ ? wing_->speed_mps : speed_;
      if (std::abs(dir.z()) > 1e-6)
        cruise = std::min(cruise, (dir.z() < 0 ? p_.speed_max_up : p_.speed_max_down) / std::abs(dir.z()));
      double v = std::min(ref_speed_ + p_.accel * dt, cruise);
      if (stop) v = std::min(v, std::sqrt(2.0 * p_.accel * dist));
      // Leash: the reference waits for a vehicle that has fallen behind.
      if ((ref_ - est.p_N).norm() > p_.leash) v = std::min(v, ref_speed_ * 0.5);
      ref_speed_ = v;
      const double step = v * dt;
      if (step >= dist) {
        ref_ = target_;
        flown_length_ += dist;
        if (stop) {
          waiting_ = true;
          ref_speed_ = 0.0;
        } else {
          ++index_;
          Advance();
        }
      } else {
        ref_ += dir * step;
        flown_length_ += step;
        v_ff = dir * v;
      }
    }
    // On the wing a waypoint is also reached once the vehicle has crossed the line through it
    // square to the leg (ArduPlane's finish line): a wing that passed wide of it (it was still
    // transitioning there) would otherwise fly on along the leg.
    const Eigen::Vector2d leg = (target_ - leg_from_).head<2>();
    const bool crossed = leg.norm() > 1e-6 && (est.p_N - target_).head<2>().dot(leg) > 0.0;
    const bool there = wing_ ? (est.p_N - target_).head<2>().norm() < wing_->acceptance_m || crossed
                             : (est.p_N - target_).norm() < p_.reached_radius && est.v_N.norm() < p_.reached_speed;
    if (waiting_ && there) {
      waiting_ = false;
      if (steps_[index_].kind == Kind::kReturnHome || steps_[index_].kind == Kind::kLand) {
        Advance();  // the next phase of the return/landing
      } else {
        ++index_;
        Advance();
      }
    }
  }
  o.setpoint.p_N = ref_;
  if (moving_ && !landing_ && !done_) o.leg_end_N = target_;
  o.setpoint.yaw = yaw_;
  o.setpoint.v_ff_N = v_ff;
  o.setpoint.speed_max_xy = speed_;
  o.land = landing_;
  o.done = done_;
  o.item = index_ < steps_.size() ? static_cast<int>(steps_[index_].item) : -1;
  o.step = index_;
  o.holding = holding_;
  o.percent = total_length_ > 1e-6 ? static_cast<int>(std::clamp(100.0 * flown_length_ / total_length_, 0.0, 100.0)) : 100;
  o.capture_interval_s = capture_interval_s_;
  o.capture_distance_m = capture_distance_m_;
  return o;
}

}  // namespace uav::control
