// U-Lion's 6-DOF model (thesis 2.6) checked against physics and the thesis: hover thrust against
// weight, the airframe broadside to the wind against published flat-plate values, level flight
// at the wing model's trim, every effector moving its own axis with the sign the controller
// expects, the sliding battery's 5-6 cm, and a vehicle file with a geometry that cannot be built
// refused naming the entry.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "uav/shared/parameters.hpp"
#include "uav/sim/tailsitter_model.hpp"

namespace uav::sim {
namespace {

constexpr double kDeg = M_PI / 180;

std::string ULionText() {
  std::ifstream in(std::string(UAV_RESOURCE_DIR) + "/vehicles/ulion.params");
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TailSitterParams ULion() {
  return TailSitterParams::FromParameters(ParameterSet::Parse(ULionText(), "ulion.params", VehicleParameterSchema()));
}

// The file with one entry's value replaced.
std::string Refusal(const std::string& name, const std::string& value) {
  std::string text = ULionText();
  const auto at = text.find("\n" + name + " ");
  EXPECT_NE(at, std::string::npos) << name;
  const auto end = text.find('\n', at + 1);
  text.replace(at + 1, end - at - 1, name + " " + value);
  try {
    TailSitterParams::FromParameters(ParameterSet::Parse(text, "ulion.params", VehicleParameterSchema()));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "accepted";
}

TEST(TailSitterModel, HoversOnItsRotorAtItsWeight) {
  const TailSitterModel model(ULion());
  TailSitterState s = TailSitterState::UprightOnGround(0.0);
  s.p_N.z() = -10;
  s.thrust_n = model.params().mass_kg * model.params().gravity;  // 21.6 N of the 40 N (Table 2.11)
  const TailSitterForces f = model.Forces(s, Eigen::Vector3d::Zero());
  const Eigen::Vector3d f_N = s.q_NB * f.force_B;
  std::printf("[ U-Lion ] hover: thrust %.1f N for %.1f N of weight (max 40 N), upward force %.2f N, propwash lift %.2f N\n",
              s.thrust_n, model.params().mass_kg * 9.80665, -f_N.z(), f.wing_lift_n);
  // Less the download: the profile drag of the strips, tail and canards in the slipstream.
  EXPECT_LT(-f_N.z(), model.params().mass_kg * model.params().gravity);
  EXPECT_GT(-f_N.z(), 0.95 * model.params().mass_kg * model.params().gravity);
  EXPECT_GT(model.params().thrust_max_n, 1.5 * model.params().mass_kg * model.params().gravity);
  // The cambered wing's strips in the slipstream lift toward the back (Clark Y lifts at zero
  // incidence): a real hover trim the controller feeds forward.
  EXPECT_GT(f.wing_lift_n, 2.0);
  EXPECT_LT(f.wing_lift_n, 8.0);
}

TEST(TailSitterModel, BroadsideToTheWindLikeAFlatPlate) {
  const TailSitterModel model(ULion());
  TailSitterState s = TailSitterState::UprightOnGround(0.0);  // belly north
  s.p_N.z() = -10;
  const double wind = 5.0, q = 0.5 * 1.225 * wind * wind;
  // Wind from the north blows toward the belly's opposite: onto the belly, 90 deg to the wing.
  const Eigen::Vector3d wind_N(-wind, 0, 0);
  const Eigen::Vector3d f_N = s.q_NB * model.Forces(s, wind_N).force_B;
  const double cd_wing = model.wing().At(90 * kDeg).drag;
  const double drag_area = -f_N.x() / q;
  std::printf("[ U-Lion ] broadside: wing C_D(90) %.2f (flat plates of aspect ratio 5-10: 1.2-1.3, 2-D 1.98); airframe "
              "drag area %.3f m^2 (wing alone %.3f), %.1f N in 5 m/s\n",
              cd_wing, drag_area, cd_wing * 0.36, -f_N.x());
  EXPECT_GE(cd_wing, 1.17);
  EXPECT_LE(cd_wing, 1.98);
  EXPECT_GT(drag_area, cd_wing * 0.36);                 // the fuselage and tail add to it
  EXPECT_LT(drag_area, cd_wing * 0.36 + 0.1 + 0.1);     // ... by about their own areas
  EXPECT_NEAR(f_N.y(), 0.0, 0.05 * -f_N.x());           // symmetric: no side force
}

// Forces along and across the path and the pitching moment in level flight north at `speed`
// with angle of attack, elevator and thrust x = (alpha, elevator, thrust).
Eigen::Vector3d LevelFlightResidual(const TailSitterModel& model, double speed, const Eigen::Vector3d& x) {
  TailSitterState s;
  s.p_N.z() = -20;
  s.q_NB = Eigen::AngleAxisd(x[0], Eigen::Vector3d::UnitY());
  s.v_B = s.q_NB.conjugate() * Eigen::Vector3d(speed, 0, 0);
  s.elevator_rad = x[1];
  s.thrust_n = x[2] / model.AvailableThrust(s.v_B.x());
  const TailSitterForces f = model.Forces(s, Eigen::Vector3d::Zero());
  const Eigen::Vector3d f_N = s.q_NB * f.force_B;
  return {f_N.x(), f_N.z() + model.params().mass_kg * model.params().gravity, f.torque_B.y()};
}

TEST(TailSitterModel, TrimsInLevelFlightNearTheWingModelsTrim) {
  const TailSitterParams p = ULion();
  const TailSitterModel model(p);
  airframe::PowerModel power;
  power.mass_kg = p.mass_kg;
  power.disk_area_m2 = M_PI / 4 * p.rotor_diameter_m * p.rotor_diameter_m;
  power.parasite_drag_area_m2 = p.fuselage_axial_m2;
  for (double speed : {10.0, 14.0}) {
    const airframe::CruiseTrim wing_only = airframe::TrimCruise(model.wing(), power, speed, p.air_density);
    ASSERT_TRUE(wing_only.found);
    // The whole airframe's trim (wing, tail, fin, canards, fuselage, propwash) by Newton's method.
    Eigen::Vector3d x(wing_only.alpha_rad, 0.0, wing_only.thrust_n);
    for (int it = 0; it < 30; ++it) {
      const Eigen::Vector3d r = LevelFlightResidual(model, speed, x);
      Eigen::Matrix3d J;
      for (int k = 0; k < 3; ++k) {
        Eigen::Vector3d dx = Eigen::Vector3d::Zero();
        dx[k] = 1e-5;
        J.col(k) = (LevelFlightResidual(model, speed, x + dx) - r) / 1e-5;
      }
      x -= J.colPivHouseholderQr().solve(r);
    }
    const Eigen::Vector3d r = LevelFlightResidual(model, speed, x);
    std::printf("[ U-Lion ] level flight at %.0f m/s: airframe trim alpha %.1f deg, elevator %.1f deg, thrust %.2f N; "
                "wing-alone trim alpha %.1f deg, thrust %.2f N, %.0f W\n",
                speed, x[0] / kDeg, x[1] / kDeg, x[2], wing_only.alpha_rad / kDeg, wing_only.thrust_n, wing_only.electric_w);
    EXPECT_LT(r.norm(), 1e-6);
    EXPECT_NEAR(x[0], wing_only.alpha_rad, 2.5 * kDeg);
    EXPECT_NEAR(x[2], wing_only.thrust_n, 1.0);
    EXPECT_GT(x[2], 0.0);
    EXPECT_LT(std::abs(x[1]), 0.5 * p.surface_max_rad);  // trimmed with half the elevator at most
  }
}

TEST(TailSitterModel, EveryEffectorMovesItsOwnAxis) {
  const TailSitterModel model(ULion());
  // Hover (propwash on the canards, elevator and inner wing) and cruise (free stream).
  TailSitterState hover = TailSitterState::UprightOnGround(0.0);
  hover.p_N.z() = -10;
  hover.thrust_n = 21.6;
  TailSitterState cruise;
  cruise.p_N.z() = -10;
  cruise.v_B = Eigen::Vector3d(10, 0, 1);
  cruise.thrust_n = 3;
  for (const TailSitterState* base : {&hover, &cruise}) {
    const Eigen::Vector3d m0 = model.Forces(*base, Eigen::Vector3d::Zero()).torque_B;
    // Returns the vector, not Eigen's expression: that would refer to the temporary forces.
    auto moment = [&](auto set) -> Eigen::Vector3d {
      TailSitterState s = *base;
      set(s);
      return model.Forces(s, Eigen::Vector3d::Zero()).torque_B - m0;
    };
    const Eigen::Vector3d gp = moment([](TailSitterState& s) { s.gimbal_pitch_rad = 0.2; });
    const Eigen::Vector3d gy = moment([](TailSitterState& s) { s.gimbal_yaw_rad = 0.2; });
    const Eigen::Vector3d el = moment([](TailSitterState& s) { s.elevator_rad = 0.2; });
    const Eigen::Vector3d ai = moment([](TailSitterState& s) { s.aileron_rad = 0.2; });
    const Eigen::Vector3d ca = moment([](TailSitterState& s) { s.canard_rad = 0.2; });
    const char* where = base == &hover ? "hover" : "cruise";
    std::printf("[ U-Lion ] %s, 0.2 rad: gimbal pitch %.2f, gimbal yaw %.2f, elevator %.2f, aileron %.2f, canard %.2f N m\n",
                where, gp.y(), gy.z(), el.y(), ai.x(), ca.x());
    EXPECT_GT(gp.y(), 0.1) << where;
    EXPECT_GT(gy.z(), 0.1) << where;
    EXPECT_GT(el.y(), 0.05) << where;
    EXPECT_GT(ai.x(), 0.01) << where;
    EXPECT_GT(ca.x(), 0.01) << where;
    // Each mostly about its own axis.
    EXPECT_LT(std::abs(gp.x()) + std::abs(gp.z()), 0.1 * gp.y()) << where;
    EXPECT_LT(std::abs(ca.y()) + std::abs(ca.z()), 0.3 * ca.x()) << where;
  }
  // The canards, in the propwash, steer the hover's heading; in cruise the ailerons roll.
  TailSitterState s = hover;
  s.canard_rad = 0.2;
  const double canard_hover = (model.Forces(s, Eigen::Vector3d::Zero()).torque_B -
                               model.Forces(hover, Eigen::Vector3d::Zero()).torque_B).x();
  EXPECT_GT(canard_hover, 0.15);
}

TEST(TailSitterModel, TheSlidingBatteryMovesTheCgFiveToSixCentimetres) {
  const TailSitterModel model(ULion());
  TailSitterState s;
  s.battery_m = model.params().battery_travel_m;
  const double shift = -model.CgShift(s);
  std::printf("[ U-Lion ] battery at the tail: CG %.1f cm aft (thesis 2.6.3: 5-6 cm)\n", 100 * shift);
  EXPECT_GE(shift, 0.05);
  EXPECT_LE(shift, 0.06);
  // The battery's belt is slow: it takes travel / speed to move, as the servo model limits it.
  TailSitterState t;
  airframe::TailSitterInputs in;
  in.battery = 1;
  t.p_N.z() = -100;
  for (int i = 0; i < 100; ++i) model.Step(t, in, Eigen::Vector3d::Zero(), 0.01);
  EXPECT_NEAR(t.battery_m, model.params().battery_speed_mps * 1.0, 0.01);
}

TEST(TailSitterModel, AVehicleFileThatCannotBeBuiltIsRefusedNamingTheEntry) {
  EXPECT_NE(Refusal("ts_canard_y", "0.2").find("ts_canard_y must lie inside the rotor's slipstream"), std::string::npos);
  EXPECT_NE(Refusal("ts_thrust_max", "20").find("ts_thrust_max must exceed 1.2 x the weight"), std::string::npos);
  EXPECT_NE(Refusal("ts_tail_x", "-0.1").find("ts_tail_x must lie behind the wing"), std::string::npos);
  EXPECT_NE(Refusal("ts_wing_area", "0.6").find("wing area_m2"), std::string::npos);
  EXPECT_NE(Refusal("inertia_zz", "0.5").find("triangle inequality"), std::string::npos);
  EXPECT_NE(Refusal("ts_canard_x", "0.6").find("ts_canard_x must lie behind the rotor"), std::string::npos);
  // Out of the declared limits: the parameter file names the line.
  EXPECT_NE(Refusal("ts_wing_stall_alpha", "0.6").find("ts_wing_stall_alpha"), std::string::npos);
  EXPECT_NE(Refusal("ts_wing_lift_slope", "nan").find("ts_wing_lift_slope"), std::string::npos);
  EXPECT_EQ(Refusal("ts_wing_x", "0.02"), "accepted");
}

}  // namespace
}  // namespace uav::sim
