#include "uav/sim/quadrotor_model.hpp"

#include <algorithm>
#include <cmath>

namespace uav::sim {

QuadrotorModel::QuadrotorModel(const QuadrotorParams& params) : params_(params) {}

double QuadrotorModel::RotorThrust(double input) const {
  // Eq. 2.13 (static part): thrust linear in the input around trim, never negative.
  return params_.thrust_gain * std::max(0.0, input - params_.rotor_input_zero_thrust);
}

Eigen::Vector3d QuadrotorModel::SpecificForceB(const QuadrotorState& s,
                                               const Eigen::Vector3d& wind_N) const {
  // Aerodynamic and rotor forces only; the accelerometer does not feel gravity.
  const Eigen::Vector3d air_B = s.v_B - s.q_NB.conjugate() * wind_N;
  const Eigen::Vector3d drag_B =
      -0.5 * params_.air_density * params_.drag_area * air_B.norm() * air_B;  // Eq. 2.6
  double thrust = 0.0;
  for (double r : s.rotor) thrust += RotorThrust(r);
  return (drag_B - thrust * Eigen::Vector3d::UnitZ()) / params_.mass;
}

Eigen::Vector3d QuadrotorModel::ForceB(const QuadrotorState& s, const Eigen::Vector3d& wind_N) const {
  // Eq. 2.9: drag + gravity (Eq. 2.8, R^T m g e_z) - sum of rotor thrusts along e_z.
  const Eigen::Vector3d gravity_B =
      s.q_NB.conjugate() * Eigen::Vector3d(0.0, 0.0, params_.mass * params_.gravity);
  return params_.mass * SpecificForceB(s, wind_N) + gravity_B;
}

Eigen::Vector3d QuadrotorModel::TorqueB(const QuadrotorState& s) const {
  const double f1 = RotorThrust(s.rotor[0]), f2 = RotorThrust(s.rotor[1]);
  const double f3 = RotorThrust(s.rotor[2]), f4 = RotorThrust(s.rotor[3]);
  const double k = std::sqrt(2.0) / 2.0 * params_.arm_length;
  // Eq. 2.10: Q_i = d * Omega_i with Omega_i = K_v * v_i (Eq. 2.5, lag shared with thrust).
  auto Q = [&](double v) { return params_.induced_torque_coeff * params_.rotor_speed_gain * v; };
  return {k * ((f2 + f3) - (f1 + f4)),                                  // Eq. 2.11 tau_phi
          k * ((f1 + f2) - (f3 + f4)),                                  // Eq. 2.11 tau_theta
          Q(s.rotor[0]) - Q(s.rotor[1]) + Q(s.rotor[2]) - Q(s.rotor[3])};  // Eq. 2.11 tau_psi
}

QuadrotorModel::Derivative QuadrotorModel::Derive(const QuadrotorState& s,
                                                  const std::array<double, 4>& cmd,
                                                  const Eigen::Vector3d& wind_N) const {
  Derivative d;
  const Eigen::Vector3d F_B = ForceB(s, wind_N);
  const Eigen::Vector3d tau_B = TorqueB(s);
  const Eigen::Vector3d J = params_.inertia;
  // Eq. 2.1: m (dv + w x v) = F ;  J dw + w x (J w) = tau.
  d.dv = F_B / params_.mass - s.w_B.cross(s.v_B);
  d.dw = (tau_B - s.w_B.cross(J.cwiseProduct(s.w_B))).cwiseQuotient(J);
  d.dp = s.q_NB * s.v_B;  // xi_dot = R v_b (Eq. 2.2)
  // Quaternion kinematics q_dot = 1/2 q (x) (0, w); used instead of Eq. 2.3 to avoid its
  // singularity at theta = +-90 deg.
  const Eigen::Quaterniond wq(0.0, s.w_B.x(), s.w_B.y(), s.w_B.z());
  const Eigen::Quaterniond qd = s.q_NB * wq;
  d.dq = 0.5 * Eigen::Vector4d(qd.w(), qd.x(), qd.y(), qd.z());
  for (int i = 0; i < 4; ++i) d.drotor[i] = (cmd[i] - s.rotor[i]) / params_.thrust_time_constant;
  return d;
}

namespace {
QuadrotorState Advance(const QuadrotorState& s, const Eigen::Vector3d& dp, const Eigen::Vector3d& dv,
                       const Eigen::Vector4d& dq, const Eigen::Vector3d& dw,
                       const std::array<double, 4>& dr, double h) {
  QuadrotorState o = s;
  o.p_N += h * dp;
  o.v_B += h * dv;
  o.w_B += h * dw;
  o.q_NB = Eigen::Quaterniond(s.q_NB.w() + h * dq[0], s.q_NB.x() + h * dq[1],
                              s.q_NB.y() + h * dq[2], s.q_NB.z() + h * dq[3]);
  o.q_NB.normalize();
  for (int i = 0; i < 4; ++i) o.rotor[i] += h * dr[i];
  return o;
}
}  // namespace

void QuadrotorModel::Step(QuadrotorState& s, const std::array<double, 4>& cmd,
                          const Eigen::Vector3d& wind_N, double dt) const {
  std::array<double, 4> c = cmd;
  for (double& v : c) v = std::clamp(v, -1.0, 1.0);
  const Derivative k1 = Derive(s, c, wind_N);
  const Derivative k2 = Derive(Advance(s, k1.dp, k1.dv, k1.dq, k1.dw, k1.drotor, dt / 2), c, wind_N);
  const Derivative k3 = Derive(Advance(s, k2.dp, k2.dv, k2.dq, k2.dw, k2.drotor, dt / 2), c, wind_N);
  const Derivative k4 = Derive(Advance(s, k3.dp, k3.dv, k3.dq, k3.dw, k3.drotor, dt), c, wind_N);
  auto avg3 = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c3,
                 const Eigen::Vector3d& d) -> Eigen::Vector3d { return (a + 2 * b + 2 * c3 + d) / 6.0; };
  std::array<double, 4> dr;
  for (int i = 0; i < 4; ++i)
    dr[i] = (k1.drotor[i] + 2 * k2.drotor[i] + 2 * k3.drotor[i] + k4.drotor[i]) / 6.0;
  s = Advance(s, avg3(k1.dp, k2.dp, k3.dp, k4.dp), avg3(k1.dv, k2.dv, k3.dv, k4.dv),
              (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6.0, avg3(k1.dw, k2.dw, k3.dw, k4.dw), dr, dt);

  // Flat ground at z = 0 (N is NED, so below ground is z > 0). Contact stops the fall and,
  // while the rotors cannot lift the vehicle, holds it level and still: the legs carry it.
  if (s.p_N.z() >= 0.0) {
    s.p_N.z() = 0.0;
    const Eigen::Vector3d v_N = s.q_NB * s.v_B;
    const double lift = -SpecificForceB(s, wind_N).z() * params_.mass;
    if (v_N.z() > 0.0 || lift < params_.mass * params_.gravity) {
      const double yaw = std::atan2(2 * (s.q_NB.w() * s.q_NB.z() + s.q_NB.x() * s.q_NB.y()),
                                    1 - 2 * (s.q_NB.y() * s.q_NB.y() + s.q_NB.z() * s.q_NB.z()));
      s.q_NB = Eigen::Quaterniond(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
      s.v_B.setZero();
      s.w_B.setZero();
    }
  }
}

}  // namespace uav::sim
