// Failsafe state machines on the simulated clock: given / when / then, with the timings of
// resources/vehicles/x650.params (link 5 s hold, 20 s return; battery 25 % return, 10 % land;
// fence 500 m, 120 m, return).
#include <cmath>

#include <gtest/gtest.h>

#include "uav/control/failsafe.hpp"
#include "uav/control/position_attitude_controller.hpp"
#include "uav/control/task_manager.hpp"

namespace uav::control {
namespace {

using A = FailsafeAction;

ParameterSet Params() { return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema()); }

class Failsafes : public ::testing::Test {
 protected:
  Failsafes() : p_(FailsafeParams::FromParameters(Params())), monitor_(p_) {
    in_.airborne = true;
    in_.p_N = Eigen::Vector3d(10, 0, -10);
  }
  // Steps to time t; the last GCS heartbeat was at heard_ (< 0: never).
  A At(double t) {
    in_.t = t;
    in_.gcs_link_age_s = heard_ < 0 ? -1.0 : t - heard_;
    events_.clear();
    return monitor_.Update(in_, &events_);
  }
  FailsafeParams p_;
  FailsafeMonitor monitor_;
  FailsafeInputs in_;
  double heard_ = -1;
  std::vector<std::string> events_;
};

TEST_F(Failsafes, LinkLossHoldsThenReturnsAndTheLinkComingBackIsReported) {
  // Given a GCS heard at t = 0,
  heard_ = 0.0;
  // when nothing more arrives: nothing until 5 s, hold from 5 s, return from 20 s.
  EXPECT_EQ(At(4.99), A::kNone);
  EXPECT_EQ(At(5.0), A::kHold);
  ASSERT_EQ(events_.size(), 1u);
  EXPECT_NE(events_[0].find("GCS link lost: hold"), std::string::npos) << events_[0];
  EXPECT_EQ(At(19.99), A::kHold);
  EXPECT_TRUE(events_.empty());  // said once
  EXPECT_EQ(At(20.0), A::kReturn);
  EXPECT_NE(monitor_.reason().find("no GCS heartbeat for 20.0 s"), std::string::npos) << monitor_.reason();
  // When the link comes back, it is reported and the requirement clears (the task manager
  // keeps the action it took: see NoDowngradeWhenTheFailsafeClears).
  heard_ = 30.0;
  EXPECT_EQ(At(30.0), A::kNone);
  ASSERT_EQ(events_.size(), 1u);
  EXPECT_NE(events_[0].find("regained"), std::string::npos);
}

TEST_F(Failsafes, NoLinkFailsafeWithoutAGcsOrOnTheGround) {
  EXPECT_EQ(At(1000), A::kNone);  // never heard a GCS: flying autonomously is not "lost"
  heard_ = 0.0;
  in_.airborne = false;
  EXPECT_EQ(At(1000), A::kNone);  // on the ground nothing to do
}

TEST_F(Failsafes, LowBatteryReturnsThenLandsAndStaysLatched) {
  in_.battery_remaining = 0.2501;
  EXPECT_EQ(At(0), A::kNone);
  in_.battery_remaining = 0.2499;
  EXPECT_EQ(At(1), A::kReturn);
  in_.battery_remaining = 0.30;  // voltage recovers under less load: still return
  EXPECT_EQ(At(2), A::kReturn);
  in_.battery_remaining = 0.1001;
  EXPECT_EQ(At(3), A::kReturn);
  in_.battery_remaining = 0.0999;
  EXPECT_EQ(At(4), A::kLand);
  EXPECT_NE(monitor_.reason().find("below 10 %"), std::string::npos) << monitor_.reason();
}

// Without a position source (GPS lost, no visual odometry) the vehicle holds at once and lands
// after nav_land_s; the landing stays latched when a source comes back, and the reason says why.
TEST_F(Failsafes, PositionLostHoldsThenLandsAfterNavLandSecondsAndStaysLatched) {
  in_.position_lost = true;
  in_.position_lost_reason = "GPS lost; visual odometry: too few features";
  EXPECT_EQ(At(0), A::kHold);
  EXPECT_NE(monitor_.reason().find("too few features"), std::string::npos) << monitor_.reason();
  EXPECT_EQ(At(p_.nav_land_s - 0.1), A::kHold);
  EXPECT_EQ(At(p_.nav_land_s + 0.1), A::kLand);
  in_.position_lost = false;
  EXPECT_EQ(At(p_.nav_land_s + 1.0), A::kLand);
  // A short loss that ends before nav_land_s only held.
  FailsafeMonitor fresh(p_);
  in_.position_lost = true;
  in_.t = 0.0;
  EXPECT_EQ(fresh.Update(in_, &events_), A::kHold);
  in_.position_lost = false;
  in_.t = 1.0;
  EXPECT_EQ(fresh.Update(in_, &events_), A::kNone);
  in_.position_lost = true;
  in_.t = 1.0 + p_.nav_land_s - 0.5;  // the clock restarted with the new loss
  EXPECT_EQ(fresh.Update(in_, &events_), A::kHold);
}

TEST_F(Failsafes, ObstaclePerceptionLostReturnsOnTheMapAndStaysLatchedUntilLanding) {
  EXPECT_EQ(At(0), A::kNone);
  EXPECT_FALSE(monitor_.perception_lost());
  in_.perception_lost = true;
  in_.perception_lost_reason = "none for 3.1 s";
  EXPECT_EQ(At(1), A::kReturn);
  EXPECT_TRUE(monitor_.perception_lost());
  EXPECT_NE(monitor_.reason().find("obstacle perception lost: none for 3.1 s"), std::string::npos) << monitor_.reason();
  ASSERT_EQ(events_.size(), 1u);
  EXPECT_NE(events_[0].find("through space seen free"), std::string::npos) << events_[0];
  // The camera back: said once, and the return goes on.
  in_.perception_lost = false;
  EXPECT_EQ(At(2), A::kReturn);
  ASSERT_EQ(events_.size(), 1u);
  EXPECT_NE(events_[0].find("regained"), std::string::npos) << events_[0];
  EXPECT_EQ(At(3), A::kReturn);
  EXPECT_TRUE(events_.empty());
  // Landed: over.
  in_.airborne = false;
  EXPECT_EQ(At(4), A::kNone);
  EXPECT_FALSE(monitor_.perception_lost());
  // A stricter failsafe still wins over it.
  in_.airborne = true;
  in_.perception_lost = true;
  in_.battery_remaining = 0.05;
  EXPECT_EQ(At(5), A::kLand);
}

TEST_F(Failsafes, GeofenceOnBothSidesOfEachLimit) {
  in_.p_N = Eigen::Vector3d(499.9, 0, -10);
  EXPECT_EQ(At(0), A::kNone);
  in_.p_N = Eigen::Vector3d(300, 400.1, -10);  // 500.08 m
  EXPECT_EQ(At(1), A::kReturn);
  in_.p_N = Eigen::Vector3d(0, 0, -119.9);
  EXPECT_EQ(At(2), A::kNone);
  EXPECT_EQ(events_, std::vector<std::string>{"back inside the geofence"});
  in_.p_N = Eigen::Vector3d(0, 0, -120.1);
  EXPECT_EQ(At(3), A::kReturn);
  p_.fence_action = A::kHold;
  FailsafeMonitor hold(p_);
  EXPECT_EQ(hold.Update(in_, &events_), A::kHold);
}

TEST_F(Failsafes, ManualOverrideIsImmediateAndTheStrictestWins) {
  heard_ = 0.0;
  in_.battery_remaining = 0.05;
  EXPECT_EQ(At(25), A::kLand);  // link says return, battery says land: land
  in_.rc_manual = true;
  EXPECT_EQ(At(25.02), A::kManual);  // the very next step
  EXPECT_EQ(monitor_.reason(), "RC fail-safe switch");
  in_.rc_manual = false;
  EXPECT_EQ(At(25.04), A::kLand);
}

TEST(FailsafeParams, InconsistentThresholdsAreRefused) {
  const std::string base = "fs_link_hold_time 5\nfs_link_return_time 20\nfs_battery_return 0.25\n"
                           "fs_battery_land 0.1\nfs_fence_radius 500\nfs_fence_alt 120\nfs_nav_land_s 5\n";
  EXPECT_NO_THROW(FailsafeParams::FromParameters(ParameterSet::Parse(base + "fs_fence_action 2\n", "t", uav::VehicleParameterSchema())));
  EXPECT_THROW(FailsafeParams::FromParameters(ParameterSet::Parse(base + "fs_fence_action 1.5\n", "t", uav::VehicleParameterSchema())), std::invalid_argument);
  std::string swapped = base;
  swapped.replace(swapped.find("fs_battery_land 0.1"), 19, "fs_battery_land 0.3");
  EXPECT_THROW(FailsafeParams::FromParameters(ParameterSet::Parse(swapped + "fs_fence_action 2\n", "t", uav::VehicleParameterSchema())), std::invalid_argument);
}

// The refusal names what to change: the override (not the untouched vehicle file), and the file
// by its name only (a refusal reaches the GCS; the vehicle's directories are nobody's business).
TEST(FailsafeParams, ARefusedOverrideNamesTheOverride) {
  const ParameterSet file = ParameterSet::Parse("fs_battery_return 0.25\n", "/home/pilot/vehicles/quad.params",
                                                uav::VehicleParameterSchema());
  try {
    FailsafeParams::FromParameters(file.WithAssignment("fs_battery_land=0.3"));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "fs_battery_land 0.3 (--param fs_battery_land=0.3) must be below fs_battery_return 0.25 (quad.params)");
  }
  try {
    FailsafeParams::FromParameters(file.With("fs_battery_land", 0.3));
    ADD_FAILURE();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "fs_battery_land 0.3 (as asked) must be below fs_battery_return 0.25 (quad.params)");
  }
}

TEST(CheckSetpoint, NonFiniteAndOutOfEnvelopeAreRejectedOnBothSidesOfEachLimit) {
  const FailsafeParams p = FailsafeParams::FromParameters(Params());
  Setpoint sp;
  sp.p_N = Eigen::Vector3d(0, 509.9, -10);  // fence 500 m + 10 m margin
  EXPECT_EQ(CheckSetpoint(sp, p, 3.0), "");
  sp.p_N.y() = 510.1;
  EXPECT_NE(CheckSetpoint(sp, p, 3.0).find("geofence"), std::string::npos);
  sp.p_N = Eigen::Vector3d(0, 0, -129.9);
  EXPECT_EQ(CheckSetpoint(sp, p, 3.0), "");
  sp.p_N.z() = -130.1;
  EXPECT_NE(CheckSetpoint(sp, p, 3.0).find("altitude"), std::string::npos);
  sp.p_N = Eigen::Vector3d(NAN, 0, -10);
  EXPECT_EQ(CheckSetpoint(sp, p, 3.0), "p_N.x is not finite");
  sp.p_N = Eigen::Vector3d(0, 0, -10);
  sp.yaw = INFINITY;
  EXPECT_EQ(CheckSetpoint(sp, p, 3.0), "yaw is not finite");
  sp.yaw = 0;
  sp.v_ff_N = Eigen::Vector3d(3.0, 0, 0);
  EXPECT_EQ(CheckSetpoint(sp, p, 3.0), "");
  sp.v_ff_N.x() = 3.1;
  EXPECT_NE(CheckSetpoint(sp, p, 3.0).find("feed-forward"), std::string::npos);
  sp.v_ff_N.setZero();
  sp.descent_rate = NAN;
  EXPECT_NE(CheckSetpoint(sp, p, 3.0).find("descent"), std::string::npos);
}

// The task manager carries the failsafe out.
class Enforcement : public ::testing::Test {
 protected:
  Enforcement() : tm_(TaskParams::FromParameters(Params())) {
    est_.p_N = Eigen::Vector3d(0, 0, 0);
    Run("arm");
    Run("takeoff 10");
    est_.p_N = Eigen::Vector3d(0, 0, -10);
    Run("goto 100 0 10");
  }
  CommandAck Run(const std::string& text) {
    reports_.clear();
    tm_.Submit({"test", ++seq_, *ParseCommand(text).command}, est_, t_, &reports_);
    for (const auto& r : reports_)
      if (r.command_seq == seq_) return r;  // this command's answer (a superseded one may come first)
    return CommandAck{};
  }
  void Enforce(A a, const std::string& why) {
    reports_.clear();
    tm_.EnforceFailsafe(a, why, est_, t_ += 0.02, &reports_);
    tm_.Update(est_, t_, &reports_);
  }
  TaskManager tm_;
  VehicleEstimate est_;
  std::vector<CommandAck> reports_;
  int64_t seq_ = 0;
  double t_ = 0;
};

TEST_F(Enforcement, AStricterActionTakesOverAndTheRunningCommandFails) {
  EXPECT_EQ(tm_.task(), Task::kGoto);
  Enforce(A::kHold, "no GCS heartbeat for 5.0 s");
  EXPECT_EQ(tm_.task(), Task::kHover);
  ASSERT_FALSE(reports_.empty());
  EXPECT_EQ(reports_[0].result, AckResult::kFailed);
  EXPECT_NE(reports_[0].reason.find("failsafe hold"), std::string::npos);
  Enforce(A::kReturn, "no GCS heartbeat for 20.0 s");
  EXPECT_EQ(tm_.task(), Task::kReturn);
  Enforce(A::kLand, "battery 9 % below 10 %");
  EXPECT_EQ(tm_.task(), Task::kLand);
}

TEST_F(Enforcement, NoDowngradeWhenTheFailsafeClearsAndCommandsThatDoLessAreRefused) {
  Enforce(A::kReturn, "no GCS heartbeat for 20.0 s");
  EXPECT_EQ(tm_.task(), Task::kReturn);
  // Still required: only return or land are accepted.
  const CommandAck r = Run("hover");
  EXPECT_EQ(r.result, AckResult::kRejected);
  EXPECT_NE(r.reason.find("failsafe return active"), std::string::npos) << r.reason;
  EXPECT_EQ(Run("goto 10 0 10").result, AckResult::kRejected);
  // The link comes back: the return continues...
  Enforce(A::kNone, "");
  EXPECT_EQ(tm_.task(), Task::kReturn);
  // ...until the operator decides.
  EXPECT_EQ(Run("hover").result, AckResult::kAccepted);
  EXPECT_EQ(tm_.task(), Task::kHover);
  // A battery land refuses return (less strict) and accepts land.
  Enforce(A::kLand, "battery 9 % below 10 %");
  EXPECT_EQ(Run("return").result, AckResult::kRejected);
  EXPECT_EQ(Run("land").result, AckResult::kAccepted);
}

TEST_F(Enforcement, GeofenceTargetsAreRefusedBeforeAnythingMoves) {
  EXPECT_EQ(Run("goto 499 0 10").result, AckResult::kAccepted);
  const CommandAck r = Run("goto 400 301 10");  // 500.6 m from home
  EXPECT_EQ(r.result, AckResult::kRejected);
  EXPECT_EQ(r.reason, "target is outside the geofence: 500.6 m from home, beyond the 500 m circle");
}

TEST_F(Enforcement, PilotOverrideRefusesAutopilotCommands) {
  Enforce(A::kManual, "RC fail-safe switch");
  const CommandAck r = Run("land");
  EXPECT_EQ(r.result, AckResult::kRejected);
  EXPECT_EQ(r.reason, "pilot has control (RC fail-safe switch)");
  Enforce(A::kNone, "");  // switch back: the autopilot holds where the pilot left it
  EXPECT_EQ(tm_.task(), Task::kHover);
  EXPECT_EQ(Run("land").result, AckResult::kAccepted);
}

}  // namespace
}  // namespace uav::control
