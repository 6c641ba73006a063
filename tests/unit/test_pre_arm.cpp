// Pre-arm checks: each fails with a reason an operator can act on, and passes when it should;
// the task manager refuses `arm` naming the failures (the closed loop: test_closed_loop.cpp).
#include <gtest/gtest.h>

#include <cmath>

#include "uav/control/pre_arm.hpp"
#include "uav/control/task_manager.hpp"
#include "uav/shared/command_grammar.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::control {
namespace {

PreArmInputs Ready() {
  PreArmInputs in;
  in.gps_fix = 3;
  in.gps_satellites = 10;
  in.attitude_covariance_B = Eigen::Matrix3d::Identity() * std::pow(0.5 * M_PI / 180, 2);
  in.sensor_age_s = 0.004;
  in.battery_remaining = 0.95;
  return in;
}

const PreArmCheck& Check(const std::vector<PreArmCheck>& checks, const std::string& name) {
  for (const PreArmCheck& c : checks)
    if (c.name == name) return c;
  throw std::runtime_error("no check " + name);
}

TEST(PreArm, AReadyVehiclePassesEveryCheck) {
  const PreArmParams p = PreArmParams::FromParameters(
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", VehicleParameterSchema()));
  const auto checks = EvaluatePreArm(Ready(), p);
  ASSERT_EQ(checks.size(), 8u);
  for (const PreArmCheck& c : checks) EXPECT_TRUE(c.passed) << c.name << ": " << c.reason;
}

TEST(PreArm, EachCheckFailsWithItsReason) {
  const PreArmParams p;
  struct Case {
    const char* check;
    void (*spoil)(PreArmInputs&);
    const char* reason;
  };
  const Case cases[] = {
      {"gps", [](PreArmInputs& in) { in.gps_fix = 0, in.gps_satellites = 0; }, "no 3-D fix (fix 0, 0 satellites)"},
      {"gps", [](PreArmInputs& in) { in.gps_satellites = 4; }, "4 satellites, at least 6 needed"},
      {"gps", [](PreArmInputs& in) { in.position_source = PositionSource::kInertial; }, "no position source"},
      {"ins", [](PreArmInputs& in) { in.attitude_covariance_B(2, 2) = std::pow(11.5 * M_PI / 180, 2); },
       "attitude not converged: 11.5 deg 1-sigma, at most 5.0"},
      {"ins", [](PreArmInputs& in) { in.v_N.x() = NAN; }, "the estimate is not finite"},
      {"sensors", [](PreArmInputs& in) { in.sensor_age_s = 0.5; }, "no IMU sample for 0.50 s (at most 0.10)"},
      {"sensors", [](PreArmInputs& in) { in.sensors_finite = false; }, "not finite"},
      {"battery", [](PreArmInputs& in) { in.battery_remaining = 0.2; }, "20 % remaining, at or below the return threshold 25 %"},
      {"geofence", [](PreArmInputs& in) { in.p_N = {400, 400, 0}; }, "566 m from home, outside the 500 m geofence"},
      {"attitude", [](PreArmInputs& in) { in.rest_tilt_rad = 75 * M_PI / 180; }, "tilted 75 deg from upright, at most 20"},
      {"motion", [](PreArmInputs& in) { in.at_rest = false; }, "the vehicle is moving"},
      {"crash", [](PreArmInputs& in) { in.crash = "fell with its motors stopped (impact of 9.1 g)"; },
       "crashed (fell with its motors stopped (impact of 9.1 g)): stand it upright and still"},
  };
  for (const Case& c : cases) {
    PreArmInputs in = Ready();
    c.spoil(in);
    const auto checks = EvaluatePreArm(in, p);
    const PreArmCheck& failed = Check(checks, c.check);
    EXPECT_FALSE(failed.passed) << c.check << " " << c.reason;
    EXPECT_NE(failed.reason.find(c.reason), std::string::npos) << failed.reason;
    int failing = 0;
    for (const PreArmCheck& other : checks) failing += !other.passed;
    EXPECT_EQ(failing, 1) << "only " << c.check << " fails for: " << c.reason;
  }
  // A GPS-denied start on visual odometry needs no fix.
  PreArmInputs vision = Ready();
  vision.gps_fix = 0;
  vision.position_source = PositionSource::kVision;
  EXPECT_TRUE(Check(EvaluatePreArm(vision, p), "gps").passed);
  // Nor does one configured with visual odometry, on the ground before it has seen the floor.
  PreArmInputs indoors = Ready();
  indoors.gps_fix = 0;
  PreArmParams with_vo = p;
  with_vo.visual_odometry = true;
  EXPECT_FALSE(Check(EvaluatePreArm(indoors, p), "gps").passed);
  EXPECT_TRUE(Check(EvaluatePreArm(indoors, with_vo), "gps").passed);
}

TEST(PreArm, TheTaskManagerRefusesArmNamingTheFailures) {
  TaskManager tm(TaskParams{}, nullptr);
  PreArmReport report;
  report.checks = EvaluatePreArm([] {
    PreArmInputs in = Ready();
    in.gps_fix = 0;
    in.battery_remaining = 0.1;
    return in;
  }(), PreArmParams{});
  tm.ObservePreArm(report.Failing());
  std::vector<CommandAck> acks;
  tm.Submit({"gcs", 1, *ParseCommand("arm").command}, {}, 0.0, &acks);
  ASSERT_EQ(acks.size(), 1u);
  EXPECT_EQ(acks[0].result, AckResult::kRejected);
  EXPECT_EQ(acks[0].reason.rfind("pre-arm checks failed: gps: no 3-D fix", 0), 0u) << acks[0].reason;
  EXPECT_NE(acks[0].reason.find("; battery: 10 % remaining"), std::string::npos) << acks[0].reason;
  EXPECT_FALSE(tm.armed());
  tm.ObservePreArm("");
  acks.clear();
  tm.Submit({"gcs", 2, *ParseCommand("arm").command}, {}, 0.1, &acks);
  ASSERT_EQ(acks.size(), 2u);
  EXPECT_EQ(acks[1].result, AckResult::kCompleted);
  EXPECT_TRUE(tm.armed());
}

}  // namespace
}  // namespace uav::control
