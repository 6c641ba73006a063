#include "uav/control/tailsitter_controller.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "uav/shared/flight_envelope.hpp"

namespace uav::control {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDeg = kPi / 180;
// PX4's tail-sitter front transition: the pitch ramps over VT_F_TRANS_DUR (5 s) and the
// transition may end past 63 degrees of rotation (its PITCH_TRANSITION_FRONT_P1).
constexpr double kPx4RampDuration = 5.0;
constexpr double kPx4SwitchRotation = 63 * kDeg;
// Hover takes over from the back transition within this of vertical (its position loop brakes
// what speed is left, to the point where it can stop).
constexpr double kBackDoneTilt = 10 * kDeg;
// Share of the available thrust the front transition's pitch schedule counts on, leaving the
// rest for the altitude loop.
constexpr double kScheduleThrustShare = 0.8;
// The attitude integrator's reach [rad s]: with ts_att_int 15 it may add 30 rad/s^2 x J, enough
// to trim a stable wing's restoring moment at any angle of attack the pitch loop asks for.
constexpr double kAttIntLimit = 2.0;
// Weathervane: the wind's push [m/s^2] that turns the hover heading, and the turn rate [rad/s].
constexpr double kWeathervaneAccel = 0.3;
constexpr double kWeathervaneRate = 30 * kDeg;
// Turns on the wing keep the airspeed this factor above the stall speed at their load factor.
constexpr double kStallMargin = 1.15;
// L1 guidance's look-ahead in seconds of flight: 30 m at 12 m/s, about the turn's diameter at
// ts_bank_max (PX4's NPFG and L1 use 15-25 s periods, about the same distance).
constexpr double kL1Time = 2.5;
// Roll-in rate of the bank setpoint [rad/s]: the roll loop follows it without overshoot.
constexpr double kBankRate = 30 * kDeg;

Eigen::Matrix3d Rz(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ()).toRotationMatrix(); }
Eigen::Matrix3d Ry(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitY()).toRotationMatrix(); }
Eigen::Matrix3d Rx(double a) { return Eigen::AngleAxisd(a, Eigen::Vector3d::UnitX()).toRotationMatrix(); }

double Elevation(const Eigen::Matrix3d& R) { return std::asin(std::clamp(-R(2, 0), -1.0, 1.0)); }

double Wrap(double a) { return std::remainder(a, 2 * kPi); }

// Lift slope of a small symmetric surface (Helmbold's low-aspect-ratio formula, 2 pi AR / (AR + 2)).
double LowAspectSlope(double area, double span) {
  const double ar = span * span / area;
  return 2 * kPi * ar / (ar + 2);
}

}  // namespace

double L1Course(const Eigen::Vector2d& from_N, const Eigen::Vector2d& to_N, const Eigen::Vector2d& p_N, double l1_m) {
  const Eigen::Vector2d leg = to_N - from_N;
  if (leg.norm() < 1e-6) return std::atan2((to_N - p_N).y(), (to_N - p_N).x());
  const Eigen::Vector2d d = leg.normalized();
  const Eigen::Vector2d r = p_N - from_N;
  const double along = r.dot(d), cross = d.x() * r.y() - d.y() * r.x();
  const double ahead = std::abs(cross) < l1_m ? std::sqrt(l1_m * l1_m - cross * cross) : 0.0;
  const Eigen::Vector2d carrot = from_N + d * (along + ahead);
  return std::atan2((carrot - p_N).y(), (carrot - p_N).x());
}

double OrbitCourse(const Eigen::Vector2d& centre_N, const Eigen::Vector2d& p_N, double radius_m) {
  const Eigen::Vector2d r = p_N - centre_N;
  const double d = r.norm();
  if (d < 1e-6) return 0.0;
  const double bearing = std::atan2(r.y(), r.x());  // from the centre to the vehicle
  // Clockwise: the tangent is 90 degrees right of the outward bearing; outside the circle turn in,
  // by 45 degrees at a third of the radius off. The course loop needs a steady angle to hold the
  // circle's turn (about 20 degrees with L1's look-ahead at 1.5 turn radii): this gain keeps the
  // circle within a tenth of its radius.
  const double correction = std::clamp(3.0 * (d - radius_m) / radius_m, -1.0, 1.0) * (kPi / 4);
  return Wrap(bearing + kPi / 2 + correction);
}

double TailSitterController::TurnRadius() const {
  return CoordinatedTurnRadius(p_.cruise_speed, p_.bank_max, p_.vehicle.gravity);
}


TailSitterControlParams TailSitterControlParams::FromParameters(const ParameterSet& p) {
  TailSitterControlParams c;
  static_cast<PositionLoopParams&>(c) = PositionLoopParams::FromParameters(p);
  c.vehicle = airframe::TailSitterParams::FromParameters(p);
  c.att_gain = p.Get("ts_att_gain");
  c.rate_gain = p.Get("ts_rate_gain");
  c.att_int = p.Get("ts_att_int");
  c.tilt_max = p.Get("ts_tilt_max");
  c.cruise_speed = p.Get("ts_cruise_speed");
  c.trans_airspeed = p.Get("ts_trans_airspeed");
  c.trans_pitch_rate = p.Get("ts_trans_pitch_rate") * kDeg;
  c.back_pitch_rate = p.Get("ts_back_pitch_rate") * kDeg;
  c.trans_timeout = p.Get("ts_trans_timeout");
  c.trans_alt_loss = p.Get("ts_trans_alt_loss");
  c.trans_min_alt = p.Get("ts_trans_min_alt");
  c.land_approach_alt = p.Get("ts_land_approach_alt");
  c.bank_max = p.Get("ts_bank_max");
  c.weathervane = p.Get("ts_weathervane") != 0;
  return c;
}

TailSitterController::TailSitterController(const TailSitterControlParams& params)
    : p_(params), wing_(params.vehicle.wing, params.vehicle.wing_coefficients) {
  const auto& v = p_.vehicle;
  airframe::PowerModel power;
  power.mass_kg = v.mass_kg;
  power.disk_area_m2 = kPi / 4 * v.rotor_diameter_m * v.rotor_diameter_m;
  power.parasite_drag_area_m2 = v.fuselage_axial_m2;
  const airframe::CruiseTrim trim = airframe::TrimCruise(wing_, power, p_.cruise_speed, v.air_density);
  if (!trim.found || trim.alpha_rad > wing_.MaxLiftAlphaRad())
    throw std::invalid_argument("ts_cruise_speed " + std::to_string(p_.cruise_speed) +
                                " m/s: the wing cannot carry the weight below its stall angle (stall speed " +
                                std::to_string(wing_.StallSpeed(v.mass_kg, v.air_density)) + " m/s)");
  if (p_.trans_airspeed < wing_.StallSpeed(v.mass_kg, v.air_density))
    throw std::invalid_argument("ts_trans_airspeed " + std::to_string(p_.trans_airspeed) + " m/s is below the stall speed " +
                                std::to_string(wing_.StallSpeed(v.mass_kg, v.air_density)) + " m/s");
  if (p_.land_approach_alt < p_.trans_min_alt)
    throw std::invalid_argument("ts_land_approach_alt " + std::to_string(p_.land_approach_alt) +
                                " m is below ts_trans_min_alt " + std::to_string(p_.trans_min_alt) +
                                " m: the landing's back transition would be refused");
  stall_speed_ = wing_.StallSpeed(v.mass_kg, v.air_density);
  cruise_alpha_ = trim.alpha_rad;
  cruise_thrust_ = trim.thrust_n;
}

double TailSitterController::PitchForVertical(double airspeed, double thrust_n, double vertical_n) const {
  const auto& v = p_.vehicle;
  for (double pitch = 0.0; pitch < kPi / 2; pitch += 0.5 * kDeg)
    if (thrust_n * std::sin(pitch) + wing_.Lift(pitch, airspeed, v.air_density) >= vertical_n) return pitch;
  return kPi / 2;
}

double TailSitterController::AvailableThrust(double airspeed) const {
  const auto& v = p_.vehicle;
  return v.thrust_max_n * std::max(0.05, 1 - std::max(0.0, airspeed) / v.prop_pitch_speed_mps);
}

double TailSitterController::ThrustCommand(double thrust_n, double airspeed) const {
  return std::clamp(thrust_n / AvailableThrust(airspeed), 0.0, 1.0);
}

std::string TailSitterController::StartTransition(bool to_wing, const hal::VehicleEstimate& est) {
  if (mode_ == TailSitterMode::kTransitionToWing || mode_ == TailSitterMode::kTransitionToHover)
    return "already in the " + Spoken(Name(mode_));
  if (to_wing && mode_ != TailSitterMode::kHover) return "not hovering: already on the wing";
  if (!to_wing && mode_ != TailSitterMode::kCruise) return "not on the wing: already hovering";
  if (to_wing && est.altitude() < p_.trans_min_alt)
    return "altitude " + std::to_string(est.altitude()).substr(0, 4) + " m is below ts_trans_min_alt " +
           std::to_string(p_.trans_min_alt).substr(0, 4) + " m";
  event_.clear();
  Enter(to_wing ? TailSitterMode::kTransitionToWing : TailSitterMode::kTransitionToHover, est);
  return "";
}

void TailSitterController::Enter(TailSitterMode m, const hal::VehicleEstimate& est) {
  const Eigen::Matrix3d R = est.q_NB.toRotationMatrix();
  if (m == TailSitterMode::kTransitionToWing) {
    // The course is where the belly faces.
    const Eigen::Vector3d belly = R.col(2);
    course_ = std::atan2(belly.y(), belly.x());
    h_ref_ = h_start_ = est.altitude();
    hold_set_ = false;
  }
  if (m == TailSitterMode::kTransitionToHover) {
    const Eigen::Vector3d nose = R.col(0);
    if (mode_ == TailSitterMode::kCruise) course_ = std::atan2(nose.y(), nose.x());
    h_ref_ = mode_ == TailSitterMode::kTransitionToWing ? h_start_ : est.altitude();
  }
  // Hover trims differently from the wing: its integrators start afresh.
  if (m == TailSitterMode::kHover) int_v_N_.setZero(), int_att_.setZero();
  int_h_ = int_speed_ = int_pitch_ = bank_sp_ = 0.0;
  mode_ = m;
  mode_time_ = 0.0;
  pitch_start_ = pitch_sp_ = Elevation(R);
}

double TailSitterController::transition_progress() const {
  switch (mode_) {
    case TailSitterMode::kTransitionToWing:
      return std::clamp((pitch_start_ - pitch_sp_) / std::max(1e-3, pitch_start_ - cruise_alpha_), 0.0, 1.0);
    case TailSitterMode::kTransitionToHover:
      return std::clamp((pitch_sp_ - pitch_start_) / std::max(1e-3, kPi / 2 - pitch_start_), 0.0, 1.0);
    default: return 1.0;
  }
}

Eigen::Vector3d TailSitterController::PropwashLift_B(double thrust_n) const {
  const auto& v = p_.vehicle;
  const double disk = kPi / 4 * v.rotor_diameter_m * v.rotor_diameter_m;
  const double wash = airframe::SlipstreamSpeed(std::max(0.0, thrust_n), disk, v.air_density);
  const double washed_area = std::min(v.SlipstreamDiameter(), v.wing.span_m) * v.wing.chord_m;
  return Eigen::Vector3d(0, 0, -0.5 * v.air_density * wash * wash * washed_area * wing_.At(0.0).lift);
}

double TailSitterController::HoverHeading(double requested, bool face, double dt) {
  if (!p_.weathervane) return hover_heading_ = requested;
  // The velocity integrator leans into what pushes the vehicle: turn the wing edge-on to it,
  // whichever of the two ways is nearer, at a limited rate (PX4's weathervane, for a wing).
  // Asked to face a heading (to transition that way), turn there at the same rate.
  const Eigen::Vector2d push = int_v_N_.head<2>();
  double target = hover_heading_;
  if (face && hover_heading_set_) {
    target = requested;
  } else if (push.norm() > kWeathervaneAccel) {
    target = std::atan2(push.y(), push.x()) + kPi / 2;
    if (std::abs(Wrap(target - hover_heading_)) > kPi / 2) target += kPi;
  } else if (!hover_heading_set_) {
    target = requested;
  }
  if (!hover_heading_set_) hover_heading_ = requested, hover_heading_set_ = true;
  const double step = std::clamp(Wrap(target - hover_heading_), -kWeathervaneRate * dt, kWeathervaneRate * dt);
  return hover_heading_ = Wrap(hover_heading_ + step);
}

double TailSitterController::AltitudeThrust(const hal::VehicleEstimate& est, double airspeed, double pitch, double h_ref,
                                            double dt) {
  const auto& v = p_.vehicle;
  const double climb = -est.v_N.z();
  const double v_up = std::clamp(p_.pos_gain_z * (h_ref - est.altitude()), -p_.speed_max_down, p_.speed_max_up);
  int_h_ = std::clamp(int_h_ + p_.vel_int_z * (v_up - climb) * dt, -p_.vel_int_limit, p_.vel_int_limit);
  const double a_up = p_.vel_gain_z * (v_up - climb) + int_h_;
  const double vertical = v.mass_kg * (v.gravity + a_up);
  last_vertical_n_ = vertical;
  // The wing's lift at the angle of attack the ground velocity gives (calm air assumed; the
  // integrator takes up the wind).
  const Eigen::Vector3d air_B = est.q_NB.conjugate() * est.v_N;
  const double alpha = std::atan2(air_B.z(), std::max(1e-3, std::abs(air_B.x()))) ;
  const double gamma = std::atan2(climb, std::max(0.1, est.v_N.head<2>().norm()));
  const double lift = wing_.Lift(alpha, airspeed, v.air_density) * std::cos(gamma);
  return std::max(0.0, (vertical - lift) / std::max(0.2, std::sin(pitch)));
}

airframe::TailSitterInputs TailSitterController::Attitude(const hal::VehicleEstimate& est, const Eigen::Matrix3d& R_d,
                                                     const Eigen::Vector3d& w_d_B, double thrust_n, double airspeed,
                                                     double dt, double boost_limit_n) {
  const auto& v = p_.vehicle;
  const Eigen::Matrix3d R = est.q_NB.toRotationMatrix();
  // Lee, Leok and McClamroch's attitude error on SO(3): no singularity at the hover's 90 deg.
  const Eigen::Matrix3d E = R_d.transpose() * R - R.transpose() * R_d;
  const Eigen::Vector3d e_R = 0.5 * Eigen::Vector3d(E(2, 1), E(0, 2), E(1, 0));
  const Eigen::Vector3d e_w = est.w_B - R.transpose() * R_d * w_d_B;
  int_att_ = (int_att_ + e_R * dt).cwiseMax(-kAttIntLimit).cwiseMin(kAttIntLimit);
  const Eigen::Vector3d moment =
      v.inertia.cwiseProduct(-p_.att_gain * e_R - p_.rate_gain * e_w - p_.att_int * int_att_);

  // Each effector's moment per unit command at this airspeed and the propwash of `thrust`.
  const double rho = v.air_density, V = std::max(0.0, airspeed);
  const double disk = kPi / 4 * v.rotor_diameter_m * v.rotor_diameter_m;
  const double q_free = 0.5 * rho * V * V;
  const double tau_d = v.flap_effectiveness * v.surface_max_rad;
  const double ds = v.SlipstreamDiameter(), inner = 0.5 * ds, outer = 0.5 * v.wing.span_m - inner;
  const double cg = -v.battery_kg * 0.5 * v.battery_travel_m / v.mass_kg;  // mid travel: within 3 cm either way
  const double tail_washed = std::min(ds, v.tail_span_m) / v.tail_span_m;
  const double tail_slope = LowAspectSlope(v.tail_area_m2, v.tail_span_m);
  struct Effectiveness {
    double aileron, canard, rotor, elevator, gimbal;
  };
  const auto effectiveness = [&](double thrust) {
    const double wash = airframe::SlipstreamSpeed(std::max(0.0, thrust), disk, rho, V) - V;
    const double q_wash = 0.5 * rho * (V + wash) * (V + wash);
    Effectiveness k;
    k.aileron = 2 * tau_d * wing_.LiftSlopePerRad() * v.wing.chord_m *
                (q_wash * inner * 0.5 * inner + q_free * outer * (inner + 0.5 * outer));
    k.canard = 2 * tau_d * q_wash * v.canard_area_m2 * LowAspectSlope(v.canard_area_m2, 2 * v.canard_y_m) * v.canard_y_m;
    k.rotor = v.rotor_torque_max_nm;
    k.elevator = tau_d * tail_slope * v.tail_area_m2 * (cg - v.tail_x_m) * (tail_washed * q_wash + (1 - tail_washed) * q_free);
    k.gimbal = std::max(1.0, thrust) * (v.rotor_x_m - cg) * std::sin(v.gimbal_max_rad);
    return k;
  };
  // Past the stall the surfaces alone cannot turn a stable airframe: thrust (through the gimbal
  // and the propwash over the elevator and canards) is raised, up to `boost_limit_n`, until the
  // moment asked for is within reach on every axis.
  Effectiveness k = effectiveness(thrust_n);
  const auto out_of_reach = [&](const Effectiveness& e) {
    return std::abs(moment.x()) > e.aileron + e.canard + e.rotor || std::abs(moment.y()) > e.elevator + e.gimbal ||
           std::abs(moment.z()) > e.gimbal;
  };
  for (double boosted = thrust_n; out_of_reach(k) && boosted < boost_limit_n;) {
    boosted = std::min(boost_limit_n, boosted + 0.05 * v.thrust_max_n);
    thrust_n = boosted;
    k = effectiveness(thrust_n);
  }
  // Least-norm share per axis: u_i = k_i M / sum k^2.
  const double sx = k.aileron * k.aileron + k.canard * k.canard + k.rotor * k.rotor;
  const double sy = k.gimbal * k.gimbal + k.elevator * k.elevator;
  airframe::TailSitterInputs u;
  u.aileron = std::clamp(k.aileron * moment.x() / sx, -1.0, 1.0);
  u.canard = std::clamp(k.canard * moment.x() / sx, -1.0, 1.0);
  u.rotor_torque = std::clamp(k.rotor * moment.x() / sx, -1.0, 1.0);
  u.gimbal_pitch = std::clamp(k.gimbal * moment.y() / sy, -1.0, 1.0);
  u.elevator = std::clamp(k.elevator * moment.y() / sy, -1.0, 1.0);
  u.gimbal_yaw = std::clamp(moment.z() / k.gimbal, -1.0, 1.0);
  u.thrust = ThrustCommand(thrust_n, V);
  last_thrust_n_ = thrust_n;
  return u;
}

airframe::TailSitterInputs TailSitterController::Update(const hal::VehicleEstimate& est, double airspeed,
                                                   const TailSitterSetpoint& sp, double dt) {
  const auto& v = p_.vehicle;
  const Eigen::Matrix3d R = est.q_NB.toRotationMatrix();
  const double elevation = Elevation(R);
  mode_time_ += dt;
  // A new hover setpoint releases the hold a back transition or an abort took.
  if (hold_set_ && (sp.p_N - hold_released_by_).norm() > 1e-6 && mode_ == TailSitterMode::kHover) hold_set_ = false;
  if (!hold_set_) hold_released_by_ = sp.p_N;
  airframe::TailSitterInputs u;
  switch (mode_) {
    case TailSitterMode::kHover: {
      const Eigen::Vector3d target = hold_set_ ? hold_N_ : sp.p_N;
      const Eigen::Vector3d e_p = target - est.p_N;
      Eigen::Vector3d v_des;
      v_des.head<2>() = p_.pos_gain_xy * e_p.head<2>();
      if (v_des.head<2>().norm() > p_.speed_max_xy) v_des.head<2>() *= p_.speed_max_xy / v_des.head<2>().norm();
      v_des.z() = sp.descent_rate ? *sp.descent_rate : std::clamp(p_.pos_gain_z * e_p.z(), -p_.speed_max_up, p_.speed_max_down);
      const Eigen::Vector3d e_v = v_des - est.v_N;
      int_v_N_.head<2>() += p_.vel_int_xy * e_v.head<2>() * dt;
      int_v_N_.z() += p_.vel_int_z * e_v.z() * dt;
      int_v_N_ = int_v_N_.cwiseMax(-p_.vel_int_limit).cwiseMin(p_.vel_int_limit);
      Eigen::Vector3d a(p_.vel_gain_xy * e_v.x(), p_.vel_gain_xy * e_v.y(), p_.vel_gain_z * e_v.z());
      a += int_v_N_;
      if (a.head<2>().norm() > p_.accel_max_xy) a.head<2>() *= p_.accel_max_xy / a.head<2>().norm();
      // The cambered wing's strips in the propwash lift toward the back (-z_B) even in still
      // air: the thrust axis leans to balance it.
      Eigen::Vector3d F = v.mass_kg * (a - Eigen::Vector3d(0, 0, v.gravity)) - R * PropwashLift_B(last_thrust_n_);
      F.z() = std::min(F.z(), -0.2 * v.mass_kg * v.gravity);  // always some thrust upward
      const double horizontal_max = -F.z() * std::tan(p_.tilt_max);
      if (F.head<2>().norm() > horizontal_max) F.head<2>() *= horizontal_max / F.head<2>().norm();
      const Eigen::Vector3d x_d = F.normalized();
      const double heading = HoverHeading(sp.heading, sp.face_heading, dt);
      const Eigen::Vector3d h(std::cos(heading), std::sin(heading), 0);
      const Eigen::Vector3d z_d = (h - h.dot(x_d) * x_d).normalized();
      Eigen::Matrix3d R_d;
      R_d << x_d, z_d.cross(x_d), z_d;
      const double thrust = std::max(0.0, F.dot(R.col(0)));
      u = Attitude(est, R_d, Eigen::Vector3d::Zero(), thrust, airspeed, dt, thrust);
      u.battery = 1;  // the CG away from the rotor (thesis 2.6.3)
      pitch_sp_ = Elevation(R_d);
      break;
    }
    case TailSitterMode::kTransitionToWing: {
      const double previous = pitch_sp_;
      double thrust = AltitudeThrust(est, airspeed, elevation, h_ref_, dt);
      if (p_.schedule == TransitionSchedule::kLiftLimited) {
        // Most of the thrust there is, and the nose as low as the altitude loop's vertical force
        // allows with it and the wing's lift at this airspeed: the fastest way onto the wing.
        const double full = kScheduleThrustShare * AvailableThrust(airspeed);
        pitch_sp_ = std::max(pitch_sp_ - p_.trans_pitch_rate * dt, PitchForVertical(airspeed, full, last_vertical_n_));
        thrust = std::min(thrust, full);
      } else {
        pitch_sp_ = std::max(pitch_start_ - (kPi / 2) * mode_time_ / kPx4RampDuration, cruise_alpha_);
      }
      const Eigen::Vector3d w_d_B(0, (pitch_sp_ - previous) / dt, 0);
      u = Attitude(est, Rz(course_) * Ry(pitch_sp_), w_d_B, thrust, airspeed, dt, thrust);
      u.battery = 0;
      const double lost = h_start_ - est.altitude();
      if (mode_time_ > p_.trans_timeout || lost > p_.trans_alt_loss) {
        event_ = "transition to wing aborted: " +
                 (lost > p_.trans_alt_loss ? "lost " + std::to_string(lost).substr(0, 4) + " m of height"
                                           : "not complete in " + std::to_string(p_.trans_timeout).substr(0, 4) + " s") +
                 "; back to hover";
        Enter(TailSitterMode::kTransitionToHover, est);
        break;
      }
      const bool rotated = p_.schedule == TransitionSchedule::kLiftLimited || pitch_start_ - pitch_sp_ >= kPx4SwitchRotation;
      if (airspeed >= p_.trans_airspeed && rotated) Enter(TailSitterMode::kCruise, est);
      break;
    }
    case TailSitterMode::kCruise: {
      const double V = std::max(airspeed, 1.0);
      const double ground_speed = std::max(1.0, est.v_N.head<2>().norm());
      const double l1 = kL1Time * ground_speed;
      course_ = sp.leg_from_N ? L1Course(sp.leg_from_N->head<2>(), sp.p_N.head<2>(), est.p_N.head<2>(), l1) : sp.heading;
      const double e_speed = p_.cruise_speed - airspeed;
      int_speed_ = std::clamp(int_speed_ + 0.5 * e_speed * dt, -3.0, 3.0);
      const double thrust = std::max(0.0, cruise_thrust_ + v.mass_kg * (1.0 * e_speed + int_speed_));
      const double climb = -est.v_N.z(), speed = std::max(1.0, est.v_N.norm());
      const double v_up = std::clamp(0.5 * (-sp.p_N.z() - est.altitude()), -2.0, 2.0);
      const double gamma_d = std::asin(std::clamp(v_up / V, -0.3, 0.3));
      const double gamma = std::asin(std::clamp(climb / speed, -1.0, 1.0));
      int_pitch_ = std::clamp(int_pitch_ + 0.5 * (gamma_d - gamma) * dt, -0.2, 0.2);
      const double pitch = cruise_alpha_ + gamma_d + 1.0 * (gamma_d - gamma) + int_pitch_;
      const double chi = std::atan2(est.v_N.y(), est.v_N.x());
      // A bank's load factor raises the stall speed by sqrt(n): keep kStallMargin above it.
      const double n_max = std::pow(V / (kStallMargin * stall_speed_), 2);
      const double bank_limit = std::min(p_.bank_max, n_max > 1 ? std::acos(1 / n_max) : 0.0);
      // L1's lateral acceleration toward the look-ahead point (or along the course held):
      // 2 V^2 sin(eta) / L1, eta the angle from the ground track to it.
      const double eta = std::clamp(Wrap(course_ - chi), -kPi / 2, kPi / 2);
      const double lateral = 2 * ground_speed * ground_speed * std::sin(eta) / l1;
      const double bank_target = std::clamp(std::atan(lateral / v.gravity), -bank_limit, bank_limit);
      bank_sp_ += std::clamp(bank_target - bank_sp_, -kBankRate * dt, kBankRate * dt);
      const double bank = bank_sp_;
      // Yaw is left to the fin: the nose's heading is the reference's (no yaw error, so no
      // sideslip forced in a crosswind), the turn rate fed forward, the yaw integrator off.
      const double yaw = std::atan2(R(1, 0), R(0, 0));
      const Eigen::Matrix3d R_d = Rz(yaw) * Ry(pitch) * Rx(bank);
      int_att_.z() = 0.0;
      const Eigen::Vector3d w_d_N(0, 0, v.gravity * std::tan(bank) / V);  // coordinated turn
      pitch_sp_ = pitch;
      u = Attitude(est, R_d, R_d.transpose() * w_d_N, thrust, airspeed, dt, 0.5 * v.mass_kg * v.gravity);
      u.battery = 0;
      break;
    }
    case TailSitterMode::kTransitionToHover: {
      const double previous = pitch_sp_;
      pitch_sp_ = std::min(pitch_sp_ + p_.back_pitch_rate * dt, kPi / 2);
      // Never more thrust than the weight (nose-low, more only speeds the vehicle up), none for
      // height with the nose below the horizon; thrust for pitch authority up to the weight.
      const double weight = v.mass_kg * v.gravity;
      const double thrust =
          std::min(AltitudeThrust(est, airspeed, elevation, h_ref_, dt), weight * std::max(0.0, std::sin(elevation)));
      const Eigen::Vector3d w_d_B(0, (pitch_sp_ - previous) / dt, 0);
      u = Attitude(est, Rz(course_) * Ry(pitch_sp_), w_d_B, thrust, airspeed, dt, weight);
      u.battery = 1;
      const double ground_speed = est.v_N.head<2>().norm();
      if (elevation >= kPi / 2 - kBackDoneTilt) {
        // Hold where a hover brake at the acceleration limit stops, at the reference height.
        hold_N_ = est.p_N;
        hold_N_.head<2>() += est.v_N.head<2>() * ground_speed / (2 * p_.accel_max_xy);
        hold_N_.z() = -h_ref_;
        hold_set_ = true;
        Enter(TailSitterMode::kHover, est);
      }
      break;
    }
  }
  return u;
}

}  // namespace uav::control
