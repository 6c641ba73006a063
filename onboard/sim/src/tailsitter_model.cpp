#include "uav/sim/tailsitter_model.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace uav::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;

// A symmetric section of small aspect ratio (tail, fin, canards): NACA 0009-like, stalls later
// than the wing (Hoerner, Fluid-Dynamic Lift, low aspect ratio), a flat plate broadside.
airframe::WingCoefficients SymmetricSection() {
  airframe::WingCoefficients c;
  c.section_lift_slope_per_rad = 2 * kPi * 0.9;
  c.zero_lift_alpha_rad = 0.0;
  c.stall_alpha_rad = 0.26;
  c.profile_drag = 0.02;
  c.oswald = 0.8;
  c.normal_force_at_90 = 1.17;
  return c;
}

airframe::WingGeometry Rectangle(double area, double span) { return {area, span, area / span}; }

// First-order servo with a rate limit: the derivative toward `cmd`.
double Servo(double cmd, double x, double tau, double rate) { return std::clamp((cmd - x) / tau, -rate, rate); }

}  // namespace

TailSitterState TailSitterState::UprightOnGround(double heading) {
  TailSitterState s;
  // R = Rz(heading) Ry(90 deg): x_B up, z_B horizontal toward the heading.
  s.q_NB = Eigen::AngleAxisd(heading, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(kPi / 2, Eigen::Vector3d::UnitY());
  return s;
}

TailSitterModel::TailSitterModel(const TailSitterParams& params)
    : p_((params.Validate(), params)),
      wing_(params.wing, params.wing_coefficients),
      tail_(Rectangle(params.tail_area_m2, params.tail_span_m), SymmetricSection()),
      canard_(Rectangle(params.canard_area_m2, 2 * params.canard_y_m), SymmetricSection()) {}

double TailSitterModel::AvailableThrust(double axial) const {
  return std::max(0.0, 1.0 - std::max(0.0, axial) / p_.prop_pitch_speed_mps);
}

double TailSitterModel::CgShift(const TailSitterState& s) const { return -p_.battery_kg * s.battery_m / p_.mass_kg; }

TailSitterAirData TailSitterModel::AirData(const TailSitterState& s, const Eigen::Vector3d& wind_N) const {
  TailSitterAirData a;
  a.air_B = s.v_B - s.q_NB.conjugate() * wind_N;
  a.airspeed_mps = a.air_B.norm();
  a.alpha_rad = std::atan2(a.air_B.z(), a.air_B.x());
  const double axial = std::max(0.0, a.air_B.x());
  a.slipstream_mps = s.thrust_n > 0 ? airframe::SlipstreamSpeed(s.thrust_n, kPi / 4 * p_.rotor_diameter_m * p_.rotor_diameter_m,
                                                      p_.air_density, axial) - axial
                                    : 0.0;
  return a;
}

TailSitterForces TailSitterModel::Forces(const TailSitterState& s, const Eigen::Vector3d& wind_N) const {
  TailSitterForces out;
  const TailSitterAirData air = AirData(s, wind_N);
  const Eigen::Vector3d cg(CgShift(s), 0, 0);
  const double rho = p_.air_density;
  // One lifting part: at r (from the reference), span along `span_B`, chord toward +x_B, its
  // angle of attack shifted by `deflection` x tau; `washed` adds the slipstream to its flow.
  auto lifting = [&](const WingAerodynamics& aero, const Eigen::Vector3d& r, const Eigen::Vector3d& span_B,
                     double area, double deflection, bool washed) {
    const Eigen::Vector3d arm = r - cg;
    Eigen::Vector3d u = air.air_B + s.w_B.cross(arm);
    if (washed) u.x() += air.slipstream_mps;
    u -= u.dot(span_B) * span_B;  // the flow across the span
    const double speed = u.norm();
    if (speed < 1e-6) return 0.0;
    const Eigen::Vector3d normal = Eigen::Vector3d::UnitX().cross(span_B);
    const double alpha = std::atan2(u.dot(normal), u.x()) + p_.flap_effectiveness * deflection;
    const AeroCoefficients c = aero.At(alpha);
    const double q = 0.5 * rho * speed * speed * area;
    const Eigen::Vector3d lift_dir = span_B.cross(u / speed);  // perpendicular to the flow
    const Eigen::Vector3d f = q * (c.lift * lift_dir - c.drag * u / speed);
    out.force_B += f;
    out.torque_B += arm.cross(f);
    return q * c.lift;
  };
  const Eigen::Vector3d y = Eigen::Vector3d::UnitY(), z = Eigen::Vector3d::UnitZ();
  // Wing: the inner strips are in the slipstream, the outer ones in the free stream. Positive
  // aileron rolls right (+x_B): less lift on the right.
  const double ds = std::min(p_.SlipstreamDiameter(), p_.wing.span_m), chord = p_.wing.chord_m;
  const double half = 0.5 * p_.wing.span_m, inner = 0.5 * ds, outer = half - inner;
  const double da = s.aileron_rad;
  for (int side : {-1, 1}) {
    out.wing_lift_n += lifting(wing_, {p_.wing_x_m, side * 0.5 * inner, 0}, y, inner * chord, -side * da, true);
    out.wing_lift_n += lifting(wing_, {p_.wing_x_m, side * (inner + 0.5 * outer), 0}, y, outer * chord, -side * da, false);
  }
  // Horizontal tail: the middle in the slipstream. Positive elevator pitches the nose up.
  const double tail_washed = std::min(ds, p_.tail_span_m) / p_.tail_span_m;
  lifting(tail_, {p_.tail_x_m, 0, 0}, y, tail_washed * p_.tail_area_m2, -s.elevator_rad, true);
  if (tail_washed < 1) lifting(tail_, {p_.tail_x_m, 0, 0}, y, (1 - tail_washed) * p_.tail_area_m2, -s.elevator_rad, false);
  // Fin above the tail (span along -z_B), in the slipstream near its root.
  if (p_.fin_area_m2 > 0) lifting(tail_, {p_.tail_x_m, 0, -0.5 * p_.fin_height_m}, -z, p_.fin_area_m2, 0.0, false);
  // Canards: differential, like ailerons, in the slipstream.
  for (int side : {-1, 1})
    lifting(canard_, {p_.canard_x_m, side * p_.canard_y_m, 0}, y, p_.canard_area_m2, -side * s.canard_rad, true);
  // Fuselage: drag along each axis at the reference point.
  const Eigen::Vector3d& a = air.air_B;
  const Eigen::Vector3d fuselage =
      -0.5 * rho * a.norm() * Eigen::Vector3d(p_.fuselage_axial_m2 * a.x(), p_.fuselage_side_m2 * a.y(), p_.fuselage_side_m2 * a.z());
  out.force_B += fuselage;
  out.torque_B += (-cg).cross(fuselage);
  // The rotor: thrust along the gimballed axis at the pivot, and the pair's differential torque.
  const double gp = s.gimbal_pitch_rad, gy = s.gimbal_yaw_rad;
  const Eigen::Vector3d axis(std::cos(gp) * std::cos(gy), std::cos(gp) * std::sin(gy), -std::sin(gp));
  const double thrust = s.thrust_n * AvailableThrust(a.x());
  const Eigen::Vector3d f_rotor = thrust * axis;
  out.force_B += f_rotor;
  out.torque_B += (Eigen::Vector3d(p_.rotor_x_m, 0, 0) - cg).cross(f_rotor);
  return out;
}

struct TailSitterModel::Derivative {
  Eigen::Vector3d dp, dv, dw;
  Eigen::Vector4d dq;
  double dthrust, dgp, dgy, de, da, dc, db;
};

TailSitterModel::Derivative TailSitterModel::Derive(const TailSitterState& s, const TailSitterInputs& in,
                                                    const Eigen::Vector3d& wind_N) const {
  Derivative d;
  const TailSitterForces f = Forces(s, wind_N);
  const Eigen::Vector3d g_B = s.q_NB.conjugate() * Eigen::Vector3d(0, 0, p_.gravity);
  d.dv = f.force_B / p_.mass_kg + g_B - s.w_B.cross(s.v_B);
  d.dp = s.q_NB * s.v_B;
  const Eigen::Vector3d J = p_.inertia;
  const Eigen::Vector3d torque = f.torque_B + Eigen::Vector3d(p_.rotor_torque_max_nm * std::clamp(in.rotor_torque, -1.0, 1.0), 0, 0);
  d.dw = (torque - s.w_B.cross(J.cwiseProduct(s.w_B))).cwiseQuotient(J);
  const Eigen::Quaterniond qd = s.q_NB * Eigen::Quaterniond(0, s.w_B.x(), s.w_B.y(), s.w_B.z());
  d.dq = 0.5 * Eigen::Vector4d(qd.w(), qd.x(), qd.y(), qd.z());
  const double big = 1e9;
  d.dthrust = Servo(std::clamp(in.thrust, 0.0, 1.0) * p_.thrust_max_n, s.thrust_n, p_.thrust_tau_s, big);
  auto gimbal = [&](double cmd, double x) {
    return Servo(std::clamp(cmd, -1.0, 1.0) * p_.gimbal_max_rad, x, p_.servo_tau_s, p_.gimbal_rate_rad_s);
  };
  auto surface = [&](double cmd, double x) {
    return Servo(std::clamp(cmd, -1.0, 1.0) * p_.surface_max_rad, x, p_.servo_tau_s, p_.surface_rate_rad_s);
  };
  d.dgp = gimbal(in.gimbal_pitch, s.gimbal_pitch_rad);
  d.dgy = gimbal(in.gimbal_yaw, s.gimbal_yaw_rad);
  d.de = surface(in.elevator, s.elevator_rad);
  d.da = surface(in.aileron, s.aileron_rad);
  d.dc = surface(in.canard, s.canard_rad);
  d.db = Servo(std::clamp(in.battery, 0.0, 1.0) * p_.battery_travel_m, s.battery_m, p_.servo_tau_s, p_.battery_speed_mps);
  return d;
}

namespace {
TailSitterState Advance(const TailSitterState& s, const Eigen::Vector3d& dp, const Eigen::Vector3d& dv,
                        const Eigen::Vector4d& dq, const Eigen::Vector3d& dw, const double (&da)[7], double h) {
  TailSitterState o = s;
  o.p_N += h * dp;
  o.v_B += h * dv;
  o.w_B += h * dw;
  o.q_NB = Eigen::Quaterniond(s.q_NB.w() + h * dq[0], s.q_NB.x() + h * dq[1], s.q_NB.y() + h * dq[2], s.q_NB.z() + h * dq[3]);
  o.q_NB.normalize();
  o.thrust_n += h * da[0];
  o.gimbal_pitch_rad += h * da[1];
  o.gimbal_yaw_rad += h * da[2];
  o.elevator_rad += h * da[3];
  o.aileron_rad += h * da[4];
  o.canard_rad += h * da[5];
  o.battery_m += h * da[6];
  return o;
}
}  // namespace

bool TailSitterModel::Step(TailSitterState& s, const TailSitterInputs& in, const Eigen::Vector3d& wind_N, double dt) const {
  auto actuators = [](const Derivative& d, double (&a)[7]) {
    a[0] = d.dthrust, a[1] = d.dgp, a[2] = d.dgy, a[3] = d.de, a[4] = d.da, a[5] = d.dc, a[6] = d.db;
  };
  double a1[7], a2[7], a3[7], a4[7], am[7];
  const Derivative k1 = Derive(s, in, wind_N);
  actuators(k1, a1);
  const Derivative k2 = Derive(Advance(s, k1.dp, k1.dv, k1.dq, k1.dw, a1, dt / 2), in, wind_N);
  actuators(k2, a2);
  const Derivative k3 = Derive(Advance(s, k2.dp, k2.dv, k2.dq, k2.dw, a2, dt / 2), in, wind_N);
  actuators(k3, a3);
  const Derivative k4 = Derive(Advance(s, k3.dp, k3.dv, k3.dq, k3.dw, a3, dt), in, wind_N);
  actuators(k4, a4);
  for (int i = 0; i < 7; ++i) am[i] = (a1[i] + 2 * a2[i] + 2 * a3[i] + a4[i]) / 6;
  s = Advance(s, (k1.dp + 2 * k2.dp + 2 * k3.dp + k4.dp) / 6, (k1.dv + 2 * k2.dv + 2 * k3.dv + k4.dv) / 6,
              (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6, (k1.dw + 2 * k2.dw + 2 * k3.dw + k4.dw) / 6, am, dt);
  // Flat ground at z = 0. Standing on its tail, the vehicle stays upright and still until the
  // rotor lifts it; its heading (where the belly faces) is kept.
  if (s.p_N.z() >= 0.0) {
    s.p_N.z() = 0.0;
    const Eigen::Vector3d v_N = s.q_NB * s.v_B;
    const Eigen::Vector3d up_force_N = s.q_NB * Forces(s, wind_N).force_B;
    if (v_N.z() > 0.0 || -up_force_N.z() < p_.mass_kg * p_.gravity) {
      const Eigen::Vector3d belly_N = s.q_NB * Eigen::Vector3d::UnitZ();
      const Eigen::Vector3d nose_N = s.q_NB * Eigen::Vector3d::UnitX();
      // The belly's heading; lying nose-down or flat, the nose's opposite.
      const Eigen::Vector3d h = belly_N.head<2>().norm() > 0.3 ? belly_N : -nose_N;
      TailSitterState upright = TailSitterState::UprightOnGround(std::atan2(h.y(), h.x()));
      upright.p_N = s.p_N;
      upright.thrust_n = s.thrust_n;
      upright.gimbal_pitch_rad = s.gimbal_pitch_rad, upright.gimbal_yaw_rad = s.gimbal_yaw_rad;
      upright.elevator_rad = s.elevator_rad, upright.aileron_rad = s.aileron_rad, upright.canard_rad = s.canard_rad;
      upright.battery_m = s.battery_m;
      s = upright;
      return true;
    }
  }
  return false;
}

}  // namespace uav::sim
