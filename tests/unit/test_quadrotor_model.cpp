// The simulated quadrotor against hand-computed physics (thesis Eq. 2.1-2.13).
#include <gtest/gtest.h>

#include <cmath>

#include "uav/shared/parameters.hpp"
#include "uav/sim/quadrotor_model.hpp"

namespace uav::sim {
namespace {

QuadrotorParams Params() {
  return QuadrotorParams::FromParameters(
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params"));
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

}  // namespace
}  // namespace uav::sim
