#include "uav/sim/quadrotor_model.hpp"

#include <algorithm>
#include <cmath>

#include "uav/shared/frames.hpp"

namespace uav::sim {

QuadrotorModel::QuadrotorModel(const QuadrotorParams& params) : params_(params) {
  // Table 2.4: the airframe hovers without turning at the trim inputs, so with the mixer of
  // Eq. 2.11 its imbalance is the torque those inputs balance.
  const double k_rp = 4.0 * params_.thrust_gain * std::sqrt(2.0) / 2.0 * params_.arm_length;
  const double k_yaw = 4.0 * params_.induced_torque_coeff * params_.rotor_speed_gain;
  imbalance_torque_B_ = -Eigen::Vector3d(k_rp * params_.trim.x(), k_rp * params_.trim.y(), k_yaw * params_.trim.z());
}

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
  return imbalance_torque_B_ +
         Eigen::Vector3d(k * ((f2 + f3) - (f1 + f4)),                                  // Eq. 2.11 tau_phi
                         k * ((f1 + f2) - (f3 + f4)),                                  // Eq. 2.11 tau_theta
                         Q(s.rotor[0]) - Q(s.rotor[1]) + Q(s.rotor[2]) - Q(s.rotor[3]));  // Eq. 2.11 tau_psi
}

Eigen::Vector2d QuadrotorModel::HoverModeRates(const QuadrotorState& s) const {
  // Eq. 2.17-2.18: each angle is the second of two lags; Eq. 2.3 inverted gives p and q from the
  // angle rates and the yaw rate state r.
  const EulerAngles e = EulerFromRotationNB(s.q_NB.toRotationMatrix());
  const double phi_dot = (s.gyro_lag.x() - e.phi) / params_.gyro.roll_tau;
  const double theta_dot = (s.gyro_lag.y() - e.theta) / params_.gyro.pitch_tau;
  const double r = s.w_B.z();
  const double sp = std::sin(e.phi), cp = std::cos(e.phi), tt = std::tan(e.theta);
  const double q = (theta_dot + sp * r) / cp;
  const double p = phi_dot - sp * tt * q - cp * tt * r;
  return {p, q};
}

void QuadrotorModel::UpdateHoverModeRates(QuadrotorState& s) const {
  if (params_.attitude_mode == hal::AttitudeMode::kGyroHover) s.w_B.head<2>() = HoverModeRates(s);
}

QuadrotorModel::Derivative QuadrotorModel::Derive(const QuadrotorState& s,
                                                  const std::array<double, 4>& cmd,
                                                  const std::array<double, 4>& delayed,
                                                  const Eigen::Vector3d& wind_N) const {
  Derivative d;
  const Eigen::Vector3d F_B = ForceB(s, wind_N);
  // Eq. 2.1 translational part: m (dv + w x v) = F.
  d.dv = F_B / params_.mass - s.w_B.cross(s.v_B);
  d.dp = s.q_NB * s.v_B;  // xi_dot = R v_b (Eq. 2.2)
  Eigen::Vector3d w = s.w_B;
  const auto& g = params_.gyro;
  switch (params_.attitude_mode) {
    case hal::AttitudeMode::kDirect: {
      // Eq. 2.1 rotational part: J dw + w x (J w) = tau.
      const Eigen::Vector3d J = params_.inertia;
      d.dw = (TorqueB(s) - s.w_B.cross(J.cwiseProduct(s.w_B))).cwiseQuotient(J);
      for (int i = 0; i < 4; ++i) d.drotor[i] = (cmd[i] - s.rotor[i]) / params_.thrust_time_constant;
      break;
    }
    case hal::AttitudeMode::kGyroCruise:
    case hal::AttitudeMode::kGyroHover: {
      // Thesis 2.5: the gyro mixes; the rotors follow the throttle channel (the gyro does not
      // change the collective thrust), the attitude follows the identified closed loops.
      const double u_a = cmd[0] - params_.trim.x(), u_e = cmd[1] - params_.trim.y();
      const double u_r = cmd[3] - params_.trim.z();
      d.dw.z() = (g.yaw_rate_gain * u_r - s.w_B.z()) / g.yaw_rate_tau;  // Eq. 2.19, 2.22
      if (params_.attitude_mode == hal::AttitudeMode::kGyroCruise) {
        d.dw.x() = (g.roll_rate_gain * u_a - s.w_B.x()) / g.roll_rate_tau;     // Eq. 2.20
        d.dw.y() = (g.pitch_rate_gain * u_e - s.w_B.y()) / g.pitch_rate_tau;  // Eq. 2.21
      } else {
        d.dw.x() = d.dw.y() = 0.0;  // algebraic in hover mode (HoverModeRates)
        const double ud_a = delayed[0] - params_.trim.x(), ud_e = delayed[1] - params_.trim.y();
        d.dgyro_lag = {(g.roll_gain * ud_a - s.gyro_lag.x()) / g.roll_tau,       // Eq. 2.17
                       (g.pitch_gain * ud_e - s.gyro_lag.y()) / g.pitch_tau};    // Eq. 2.18
        w.head<2>() = HoverModeRates(s);
      }
      for (int i = 0; i < 4; ++i) d.drotor[i] = (cmd[2] - s.rotor[i]) / params_.thrust_time_constant;
      break;
    }
  }
  // Quaternion kinematics q_dot = 1/2 q (x) (0, w); used instead of Eq. 2.3 to avoid its
  // singularity at theta = +-90 deg.
  const Eigen::Quaterniond wq(0.0, w.x(), w.y(), w.z());
  const Eigen::Quaterniond qd = s.q_NB * wq;
  d.dq = 0.5 * Eigen::Vector4d(qd.w(), qd.x(), qd.y(), qd.z());
  return d;
}

namespace {
QuadrotorState Advance(const QuadrotorState& s, const Eigen::Vector3d& dp, const Eigen::Vector3d& dv,
                       const Eigen::Vector4d& dq, const Eigen::Vector3d& dw,
                       const std::array<double, 4>& dr, const Eigen::Vector2d& dlag, double h) {
  QuadrotorState o = s;
  o.gyro_lag += h * dlag;
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

bool QuadrotorModel::Step(QuadrotorState& s, const std::array<double, 4>& cmd,
                          const std::array<double, 4>& delayed_cmd, const Eigen::Vector3d& wind_N,
                          double dt) const {
  std::array<double, 4> c = cmd, dc = delayed_cmd;
  for (double& v : c) v = std::clamp(v, -1.0, 1.0);
  for (double& v : dc) v = std::clamp(v, -1.0, 1.0);
  const Derivative k1 = Derive(s, c, dc, wind_N);
  const Derivative k2 = Derive(Advance(s, k1.dp, k1.dv, k1.dq, k1.dw, k1.drotor, k1.dgyro_lag, dt / 2), c, dc, wind_N);
  const Derivative k3 = Derive(Advance(s, k2.dp, k2.dv, k2.dq, k2.dw, k2.drotor, k2.dgyro_lag, dt / 2), c, dc, wind_N);
  const Derivative k4 = Derive(Advance(s, k3.dp, k3.dv, k3.dq, k3.dw, k3.drotor, k3.dgyro_lag, dt), c, dc, wind_N);
  auto avg3 = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c3,
                 const Eigen::Vector3d& d) -> Eigen::Vector3d { return (a + 2 * b + 2 * c3 + d) / 6.0; };
  std::array<double, 4> dr;
  for (int i = 0; i < 4; ++i)
    dr[i] = (k1.drotor[i] + 2 * k2.drotor[i] + 2 * k3.drotor[i] + k4.drotor[i]) / 6.0;
  const Eigen::Vector2d dlag = (k1.dgyro_lag + 2 * k2.dgyro_lag + 2 * k3.dgyro_lag + k4.dgyro_lag) / 6.0;
  s = Advance(s, avg3(k1.dp, k2.dp, k3.dp, k4.dp), avg3(k1.dv, k2.dv, k3.dv, k4.dv),
              (k1.dq + 2 * k2.dq + 2 * k3.dq + k4.dq) / 6.0, avg3(k1.dw, k2.dw, k3.dw, k4.dw), dr, dlag, dt);
  UpdateHoverModeRates(s);

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
      s.gyro_lag.setZero();
      return true;
    }
  }
  return false;
}

}  // namespace uav::sim
