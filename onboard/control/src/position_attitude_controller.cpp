#include "uav/control/position_attitude_controller.hpp"

#include <algorithm>
#include <cmath>

namespace uav::control {
namespace {

Eigen::Vector2d ClampNorm(const Eigen::Vector2d& v, double max) {
  const double n = v.norm();
  return n > max ? Eigen::Vector2d(v * (max / n)) : v;
}
Eigen::Vector3d ClampNorm3(const Eigen::Vector3d& v, double max) {
  const double n = v.norm();
  return n > max ? Eigen::Vector3d(v * (max / n)) : v;
}

}  // namespace

ControllerParams ControllerParams::FromParameters(const ParameterSet& p) {
  ControllerParams c;
  static_cast<PositionLoopParams&>(c) = PositionLoopParams::FromParameters(p);
  c.vehicle = hal::VehicleParams::FromParameters(p);
  c.tilt_max = p.Get("ctl_tilt_max");
  c.vel_lead = p.Get("ctl_vel_lead");
  c.att_gain = p.Get("ctl_att_gain");
  c.rate_gain = p.Get("ctl_rate_gain");
  c.yaw_gain = p.Get("ctl_yaw_gain");
  c.yaw_rate_gain = p.Get("ctl_yaw_rate_gain");
  c.trim = {p.Get("ctl_trim_aileron"), p.Get("ctl_trim_elevator"), p.Get("ctl_trim_rudder")};
  c.gyro_att_gain = p.Get("ctl_gyro_att_gain");
  c.gyro_yaw_gain = p.Get("ctl_gyro_yaw_gain");
  c.att_int = p.Get("ctl_att_int");
  c.att_int_limit = p.Get("ctl_att_int_limit");
  return c;
}

PositionAttitudeController::PositionAttitudeController(const ControllerParams& params) : p_(params) {}

void PositionAttitudeController::Reset() {
  int_xy_.setZero();
  int_z_ = 0.0;
  int_att_.setZero();
}

ServoCommand PositionAttitudeController::Update(const VehicleEstimate& est, const Setpoint& sp,
                                                double dt) {
  // ---- Outer loop: position -> velocity setpoint (saturated: the vehicle flies at bounded speed).
  const Eigen::Vector3d e_p = sp.p_N - est.p_N;
  Eigen::Vector3d v_sp;
  const double speed_xy = sp.speed_max_xy ? std::min(*sp.speed_max_xy, p_.speed_max_xy) : p_.speed_max_xy;
  v_sp.head<2>() = ClampNorm(sp.v_ff_N.head<2>() + p_.pos_gain_xy * e_p.head<2>(), speed_xy);
  v_sp.z() = sp.descent_rate ? *sp.descent_rate : sp.v_ff_N.z() + p_.pos_gain_z * e_p.z();
  v_sp.z() = std::clamp(v_sp.z(), -p_.speed_max_up, p_.speed_max_down);
  if (sp.speed_max) v_sp = ClampNorm3(v_sp, *sp.speed_max);

  // ---- Velocity -> acceleration setpoint, PI with clamped integrators (anti-windup).
  // Horizontally, against the velocity the present acceleration (measured: the specific force
  // in N plus gravity, which is vertical) reaches vel_lead ahead: the tilt the loop asks for
  // arrives 0.3-0.4 s late, so a loop that waits for the velocity itself keeps pushing after the
  // setpoint is reached (a reversed detour came back at twice its speed limit).
  Eigen::Vector3d e_v = v_sp - est.v_N;
  e_v.head<2>() -= p_.vel_lead * (est.q_NB * est.f_B).head<2>();
  // Horizontally the integrator only learns while the acceleration asked for is within the
  // limit: while it is saturated (accelerating to or braking from cruise speed) the error is the
  // manoeuvre, not a steady push such as wind, and learning it would carry the vehicle past the
  // target (conditional integration, the usual anti-windup).
  const Eigen::Vector2d a_xy = p_.vel_gain_xy * e_v.head<2>() + int_xy_;
  if (a_xy.norm() < p_.accel_max_xy) int_xy_ = ClampNorm(int_xy_ + p_.vel_int_xy * e_v.head<2>() * dt, p_.vel_int_limit);
  int_z_ = std::clamp(int_z_ + p_.vel_int_z * e_v.z() * dt, -p_.vel_int_limit, p_.vel_int_limit);
  Eigen::Vector3d a_sp;
  a_sp.head<2>() = ClampNorm(p_.vel_gain_xy * e_v.head<2>() + int_xy_, p_.accel_max_xy);
  // Never ask for a downward acceleration beyond 0.7 g: the rotors cannot push down.
  a_sp.z() = std::clamp(p_.vel_gain_z * e_v.z() + int_z_, -p_.vehicle.gravity, 0.7 * p_.vehicle.gravity);

  // ---- Thrust vector: desired specific force f = a - g e_z (N is NED).
  const Eigen::Vector3d f_N = a_sp - Eigen::Vector3d(0, 0, p_.vehicle.gravity);
  const double psi = est.euler.psi;
  const double c = std::cos(psi), s = std::sin(psi);
  const Eigen::Vector3d f_H(c * f_N.x() + s * f_N.y(), -s * f_N.x() + c * f_N.y(), f_N.z());
  // Body z axis must point along -f: in the yaw-aligned frame z_B = (c_phi s_theta, -s_phi,
  // c_phi c_theta) (Eq. 5.51), so:
  const double fn = f_H.norm();
  double phi_sp = std::asin(std::clamp(f_H.y() / fn, -1.0, 1.0));
  double theta_sp = std::atan2(-f_H.x(), -f_H.z());
  phi_sp = std::clamp(phi_sp, -p_.tilt_max, p_.tilt_max);
  theta_sp = std::clamp(theta_sp, -p_.tilt_max, p_.tilt_max);
  // Collective thrust: the component of the wanted force along the current thrust axis.
  const Eigen::Vector3d z_B = est.q_NB * Eigen::Vector3d::UnitZ();
  const double thrust = std::max(0.0, -p_.vehicle.mass * f_N.dot(z_B));

  ServoCommand out;
  out.throttle =
      std::clamp(p_.vehicle.rotor_input_zero_thrust + thrust / (4.0 * p_.vehicle.thrust_gain), -1.0, 1.0);
  const double yaw_error = WrapAngle(sp.yaw - psi);
  const auto& g = p_.vehicle.gyro;
  switch (p_.vehicle.attitude_mode) {
    case hal::AttitudeMode::kDirect: {
      // ---- Inner loop: attitude PD to angular acceleration, then torque (Eq. 2.1 rotational part).
      const Eigen::Vector3d alpha(p_.att_gain * (phi_sp - est.euler.phi) - p_.rate_gain * est.w_B.x(),
                                  p_.att_gain * (theta_sp - est.euler.theta) - p_.rate_gain * est.w_B.y(),
                                  p_.yaw_gain * yaw_error + p_.yaw_rate_gain * (sp.yaw_rate_ff - est.w_B.z()));
      const Eigen::Vector3d tau =
          p_.vehicle.inertia.cwiseProduct(alpha) + est.w_B.cross(p_.vehicle.inertia.cwiseProduct(est.w_B));
      // To servo channels (inverse of the mixer's torque gains, see mixer.hpp).
      const double k_rp = 4.0 * p_.vehicle.thrust_gain * std::sqrt(2.0) / 2.0 * p_.vehicle.arm_length;
      const double k_yaw = 4.0 * p_.vehicle.induced_torque_coeff * p_.vehicle.rotor_speed_gain;
      out.aileron = p_.trim.x() + tau.x() / k_rp;
      out.elevator = p_.trim.y() + tau.y() / k_rp;
      out.rudder = p_.trim.z() + tau.z() / k_yaw;
      break;
    }
    case hal::AttitudeMode::kGyroHover:
      // The gyro holds the angle: command it through the static gain of Eq. 2.17-2.18.
      out.aileron = p_.trim.x() + phi_sp / g.roll_gain;
      out.elevator = p_.trim.y() + theta_sp / g.pitch_gain;
      out.rudder = p_.trim.z() + (p_.gyro_yaw_gain * yaw_error + sp.yaw_rate_ff) / g.yaw_rate_gain;  // Eq. 2.19
      break;
    case hal::AttitudeMode::kGyroCruise:
      // The gyro holds the body rates: angle error to rate command through Eq. 2.20-2.22.
      out.aileron = p_.trim.x() + p_.gyro_att_gain * (phi_sp - est.euler.phi) / g.roll_rate_gain;
      out.elevator = p_.trim.y() + p_.gyro_att_gain * (theta_sp - est.euler.theta) / g.pitch_rate_gain;
      out.rudder = p_.trim.z() + (p_.gyro_yaw_gain * yaw_error + sp.yaw_rate_ff) / g.yaw_rate_gain;
      break;
  }
  // Attitude integrator (anti-windup by clamping): takes up what the trims do not, so that an
  // untrimmed airframe still flies level and its trim can be measured (Table 2.4). Its sign
  // follows the channel's effect: the gyro's identified gains are negative (Table 2.6).
  Eigen::Vector3d sign = Eigen::Vector3d::Ones();
  if (p_.vehicle.attitude_mode == hal::AttitudeMode::kGyroHover)
    sign = {g.roll_gain > 0 ? 1.0 : -1.0, g.pitch_gain > 0 ? 1.0 : -1.0, g.yaw_rate_gain > 0 ? 1.0 : -1.0};
  if (p_.vehicle.attitude_mode == hal::AttitudeMode::kGyroCruise)
    sign = {g.roll_rate_gain > 0 ? 1.0 : -1.0, g.pitch_rate_gain > 0 ? 1.0 : -1.0, g.yaw_rate_gain > 0 ? 1.0 : -1.0};
  const Eigen::Vector3d e_att(phi_sp - est.euler.phi, theta_sp - est.euler.theta, yaw_error);
  int_att_ = (int_att_ + p_.att_int * dt * sign.cwiseProduct(e_att)).cwiseMax(-p_.att_int_limit).cwiseMin(p_.att_int_limit);
  out.aileron += int_att_.x();
  out.elevator += int_att_.y();
  out.rudder += int_att_.z();
  out.aileron = std::clamp(out.aileron, -0.5, 0.5);
  out.elevator = std::clamp(out.elevator, -0.5, 0.5);
  out.rudder = std::clamp(out.rudder, -0.3, 0.3);
  return out;
}

}  // namespace uav::control
