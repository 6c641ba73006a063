// The simulated quadrotor against hand-computed physics (thesis Eq. 2.1-2.13).
#include <gtest/gtest.h>

#include <cmath>

#include "uav/shared/frames.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/quadrotor_model.hpp"

namespace uav::sim {
namespace {

ParameterSet VehicleFile() {
  return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema());
}

// The X650 with a perfectly balanced airframe (trims zero), for the rigid-body physics.
QuadrotorParams Params() {
  return QuadrotorParams::FromParameters(
      VehicleFile().With("trim_aileron", 0).With("trim_elevator", 0).With("trim_rudder", 0));
}

QuadrotorParams InMode(hal::AttitudeMode mode) {
  return QuadrotorParams::FromParameters(VehicleFile().With("attitude_mode", static_cast<int>(mode)));
}

QuadrotorState Airborne(double input) {
  QuadrotorState s;
  s.p_N = {0, 0, -50};
  s.rotor.fill(input);
  return s;
}

TEST(QuadrotorModel, HoverTrimOfTable24HoldsTheWeight) {
  const QuadrotorModel m(Params());
  // Throttle trim u_th0 = 0.18 (Table 2.4): total thrust equals m*g within 0.1 %.
  double thrust = 4 * m.RotorThrust(0.18);
  EXPECT_NEAR(thrust, 1.37 * 9.80665, 0.001 * 1.37 * 9.80665);
  QuadrotorState s = Airborne(0.18);
  const std::array<double, 4> cmd = {0.18, 0.18, 0.18, 0.18};
  for (int i = 0; i < 500; ++i) m.Step(s, cmd, Eigen::Vector3d::Zero(), 0.002);
  EXPECT_NEAR(s.p_N.z(), -50.0, 0.01);  // 1 s: drifts less than 1 cm
  EXPECT_NEAR(s.w_B.norm(), 0.0, 1e-9);
}

TEST(QuadrotorModel, FreeFallWithRotorsOff) {
  const QuadrotorModel m(Params());
  QuadrotorState s = Airborne(-1.0);
  const std::array<double, 4> off = {-1, -1, -1, -1};
  for (int i = 0; i < 500; ++i) m.Step(s, off, Eigen::Vector3d::Zero(), 0.002);
  // 1 s of fall: g/2 less what the drag of Eq. 2.6 takes. With k = rho*CdA/(2m) and v ~ g t
  // the drag deceleration is k g^2 t^2, which over 1 s removes about k g^2 / 12 of the distance
  // (first order in k; the second-order term is below 1 cm here).
  const auto p = Params();
  const double k = 0.5 * p.air_density * p.drag_area / p.mass;
  const double loss = k * 9.80665 * 9.80665 / 12.0;
  EXPECT_NEAR(s.p_N.z(), -50.0 + 9.80665 / 2 - loss, 0.1 * loss);
  EXPECT_LT(s.v_B.z(), 9.80665);
}

TEST(QuadrotorModel, RotorLagIsFirstOrderWithTauF) {
  const QuadrotorModel m(Params());
  QuadrotorState s = Airborne(0.0);
  const std::array<double, 4> step = {0.5, 0.5, 0.5, 0.5};
  const double tau = Params().thrust_time_constant;
  const int n = static_cast<int>(std::round(tau / 0.0005));
  for (int i = 0; i < n; ++i) m.Step(s, step, Eigen::Vector3d::Zero(), 0.0005);
  // After one time constant: 63.2 % of the step (Eq. 2.13).
  EXPECT_NEAR(s.rotor[0], 0.5 * (1 - std::exp(-1.0)), 0.002);
}

TEST(QuadrotorModel, TorqueSignsFollowEq211) {
  const QuadrotorModel m(Params());
  const auto p = Params();
  QuadrotorState s = Airborne(0.18);
  const double k = std::sqrt(2.0) / 2 * p.arm_length;
  // Left rotors (2, 3) stronger: positive roll torque (right side down).
  s.rotor = {0.18, 0.28, 0.28, 0.18};
  const double df = 2 * p.thrust_gain * 0.1;
  EXPECT_NEAR(m.TorqueB(s).x(), k * df, 1e-9);
  EXPECT_NEAR(m.TorqueB(s).y(), 0.0, 1e-9);
  // Front rotors (1, 2) stronger: positive pitch torque (nose up).
  s.rotor = {0.28, 0.28, 0.18, 0.18};
  EXPECT_NEAR(m.TorqueB(s).y(), k * df, 1e-9);
  // Rotors 1 and 3 stronger: positive yaw torque d*K_v*(v1 - v2 + v3 - v4) (Eq. 2.16).
  s.rotor = {0.28, 0.18, 0.28, 0.18};
  EXPECT_NEAR(m.TorqueB(s).z(), p.induced_torque_coeff * p.rotor_speed_gain * 0.2, 1e-12);
}

TEST(QuadrotorModel, RollTorqueAcceleratesAboutXWithJxx) {
  const QuadrotorModel m(Params());
  const auto p = Params();
  QuadrotorState s = Airborne(0.18);
  s.rotor = {0.18, 0.28, 0.28, 0.18};
  const std::array<double, 4> cmd = s.rotor;
  m.Step(s, cmd, Eigen::Vector3d::Zero(), 0.001);
  const double expected = std::sqrt(2.0) / 2 * p.arm_length * 2 * p.thrust_gain * 0.1 / p.inertia.x();
  EXPECT_NEAR(s.w_B.x() / 0.001, expected, 1e-3 * expected);
}

TEST(QuadrotorModel, GroundHoldsTheVehicleUntilThrustExceedsWeight) {
  const QuadrotorModel m(Params());
  QuadrotorState s;  // on the ground
  const std::array<double, 4> idle = {-0.8, -0.8, -0.8, -0.8};
  for (int i = 0; i < 500; ++i) m.Step(s, idle, Eigen::Vector3d::Zero(), 0.002);
  EXPECT_EQ(s.p_N.z(), 0.0);
  const std::array<double, 4> climb = {0.4, 0.4, 0.4, 0.4};
  for (int i = 0; i < 500; ++i) m.Step(s, climb, Eigen::Vector3d::Zero(), 0.002);
  EXPECT_LT(s.p_N.z(), -0.5);
}

TEST(QuadrotorModel, TheAirframeHoversLevelAtTheTrimOfTable24) {
  const auto p = QuadrotorParams::FromParameters(VehicleFile());
  const QuadrotorModel m(p);
  // The trims through the mixer of Eq. 2.11 (m = th -+ a +- e +- r) cancel the imbalance ...
  const double th = 0.18, a = p.trim.x(), e = p.trim.y(), r = p.trim.z();
  const std::array<double, 4> trimmed = {th - a + e + r, th + a + e - r, th + a - e + r, th - a - e - r};
  QuadrotorState s = Airborne(0.18);
  s.rotor = trimmed;
  EXPECT_NEAR(m.TorqueB(s).norm(), 0.0, 1e-12);
  for (int i = 0; i < 500; ++i) m.Step(s, trimmed, Eigen::Vector3d::Zero(), 0.002);
  EXPECT_LT(s.w_B.norm(), 1e-9);
  // ... while untrimmed inputs roll, pitch and yaw the airframe.
  QuadrotorState u = Airborne(0.18);
  const std::array<double, 4> level = {0.18, 0.18, 0.18, 0.18};
  for (int i = 0; i < 500; ++i) m.Step(u, level, Eigen::Vector3d::Zero(), 0.002);
  EXPECT_LT(u.w_B.x(), -0.5);  // negative trim torque about x: rolls left within 1 s
  EXPECT_LT(u.w_B.y(), -0.5);
  EXPECT_GT(u.w_B.z(), 0.0);
}

// Gyro in the loop, cruise mode: each body rate is first order in its channel (Eq. 2.20-2.22).
TEST(QuadrotorModel, GyroCruiseModeRatesAreFirstOrderWithTable26) {
  const auto p = InMode(hal::AttitudeMode::kGyroCruise);
  const QuadrotorModel m(p);
  QuadrotorState s = Airborne(0.18);
  const double du = 0.05, dt = 0.0005;
  const std::array<double, 4> cmd = {p.trim.x() + du, p.trim.y() - du, 0.18, p.trim.z() + du};
  const double t_end = 0.04;
  for (int i = 0; i < static_cast<int>(std::round(t_end / dt)); ++i) m.Step(s, cmd, Eigen::Vector3d::Zero(), dt);
  auto first_order = [&](double K, double tau, double u) { return K * u * (1 - std::exp(-t_end / tau)); };
  EXPECT_NEAR(s.w_B.x(), first_order(p.gyro.roll_rate_gain, p.gyro.roll_rate_tau, du), 2e-4);
  EXPECT_NEAR(s.w_B.y(), first_order(p.gyro.pitch_rate_gain, p.gyro.pitch_rate_tau, -du), 2e-4);
  EXPECT_NEAR(s.w_B.z(), first_order(p.gyro.yaw_rate_gain, p.gyro.yaw_rate_tau, du), 2e-4);
  // The gyro does not change the collective: the throttle trim still carries the weight.
  EXPECT_NEAR(s.v_B.z(), 0.0, 2e-3);
}

// Gyro in the loop, hover mode: roll is two lags after a dead time (Eq. 2.17).
TEST(QuadrotorModel, GyroHoverModeRollIsTwoLagsAfterTheDelay) {
  const auto p = InMode(hal::AttitudeMode::kGyroHover);
  const QuadrotorModel m(p);
  QuadrotorState s = Airborne(0.18);
  const double du = 0.05, dt = 0.0005, T = p.gyro.hover_delay, tau = p.gyro.roll_tau;
  const std::array<double, 4> trim = {p.trim.x(), p.trim.y(), 0.18, p.trim.z()};
  const std::array<double, 4> cmd = {p.trim.x() + du, p.trim.y(), 0.18, p.trim.z()};
  double t = 0;
  for (; t < T - 1e-9; t += dt) m.Step(s, cmd, trim, Eigen::Vector3d::Zero(), dt);  // the gyro has not seen it yet
  EXPECT_NEAR(EulerFromRotationNB(s.q_NB.toRotationMatrix()).phi, 0.0, 1e-12);
  const double t_after = 2 * tau;
  for (double u = 0; u < t_after - 1e-9; u += dt) m.Step(s, cmd, cmd, Eigen::Vector3d::Zero(), dt);
  const double expected = p.gyro.roll_gain * du * (1 - (1 + t_after / tau) * std::exp(-t_after / tau));
  EXPECT_NEAR(EulerFromRotationNB(s.q_NB.toRotationMatrix()).phi, expected, 5e-3 * std::abs(expected));
  EXPECT_LT(s.w_B.x(), 0.0);  // the gyro reports the roll rate that goes with it
}

}  // namespace
}  // namespace uav::sim
