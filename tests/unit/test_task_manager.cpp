// Task manager logic on hand-made estimates: which commands are accepted in which state, what
// references they load, and how tasks complete (thesis 2.3.2).
#include <gtest/gtest.h>

#include <cmath>

#include "uav/control/task_manager.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::control {
namespace {

class TaskManagerTest : public ::testing::Test {
 protected:
  TaskManagerTest()
      : tm_(TaskParams::FromParameters(
            ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params"))) {}

  std::vector<TaskReport> Send(const std::string& text) {
    std::vector<TaskReport> r;
    tm_.Submit({"gcs", ++seq_, *ParseCommand(text).command}, est_, t_, &r);
    return r;
  }
  std::vector<TaskReport> Step(double dt = 0.02) {
    std::vector<TaskReport> r;
    t_ += dt;
    out_ = tm_.Update(est_, t_, &r);
    return r;
  }

  TaskManager tm_;
  VehicleEstimate est_;
  TaskManager::Output out_;
  double t_ = 0;
  int64_t seq_ = 0;
};

TEST_F(TaskManagerTest, ArmThenTakeoffLoadsTheClimbReference) {
  auto r = Send("arm");
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].result, AckResult::kAccepted);
  EXPECT_EQ(r[1].result, AckResult::kCompleted);
  est_.p_N = {3, 4, 0};
  r = Send("takeoff 10");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].result, AckResult::kAccepted);
  Step();
  EXPECT_EQ(out_.task, Task::kTakeoff);
  EXPECT_TRUE(out_.airborne);
  EXPECT_EQ(out_.setpoint.p_N, Eigen::Vector3d(3, 4, -10));
}

TEST_F(TaskManagerTest, StateChecksRejectWithReasons) {
  EXPECT_EQ(Send("takeoff 10")[0].reason, "not armed: arm first");
  EXPECT_EQ(Send("hover")[0].reason, "not flying");
  EXPECT_EQ(Send("goto 1 2 3")[0].reason, "not flying: take off first");
  EXPECT_EQ(Send("disarm")[0].reason, "already disarmed");
  Send("arm");
  EXPECT_EQ(Send("arm")[0].reason, "already armed");
  Send("takeoff 10");
  EXPECT_EQ(Send("disarm")[0].reason, "vehicle is flying: land first");
  EXPECT_EQ(Send("takeoff 20")[0].result, AckResult::kRejected);
  EXPECT_TRUE(tm_.armed());
  EXPECT_EQ(tm_.task(), Task::kTakeoff);  // rejected commands changed nothing
}

TEST_F(TaskManagerTest, TakeoffReportsProgressThenCompletesIntoHover) {
  Send("arm");
  Send("takeoff 10");
  std::vector<TaskReport> all;
  for (int i = 0; i <= 10; ++i) {
    est_.p_N.z() = -i;  // climb 1 m per step of 1 s
    auto r = Step(1.0);
    all.insert(all.end(), r.begin(), r.end());
  }
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.front().result, AckResult::kInProgress);
  EXPECT_EQ(all.front().percent, 10);
  EXPECT_EQ(all.back().result, AckResult::kCompleted);
  EXPECT_EQ(all.back().percent, 100);
  EXPECT_EQ(tm_.task(), Task::kHover);
}

TEST_F(TaskManagerTest, HoverTakesTheCurrentPositionAsReference) {
  Send("arm");
  Send("takeoff 10");
  est_.p_N = {1.5, -2.0, -7.0};
  est_.euler.psi = 0.5;
  auto r = Send("hover");
  // The takeoff it replaced is reported failed (superseded), then hover completes.
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].command, "takeoff");
  EXPECT_EQ(r[0].result, AckResult::kFailed);
  EXPECT_EQ(r[0].reason, "superseded by hover");
  EXPECT_EQ(r[2].result, AckResult::kCompleted);
  Step();
  EXPECT_EQ(out_.setpoint.p_N, est_.p_N);
  EXPECT_EQ(out_.setpoint.yaw, 0.5);
}

TEST_F(TaskManagerTest, ChirpOnlyWhileHoveringFollowsEq214AndEndsItself) {
  EXPECT_EQ(Send("chirp 1 0.05 0.2 3 30")[0].reason, "not hovering: hover first, then chirp");
  Send("arm");
  Send("takeoff 10");
  EXPECT_EQ(Send("chirp 1 0.05 0.2 3 30").back().reason, "not hovering: hover first, then chirp");
  est_.p_N = {0, 0, -10};
  Send("hover");
  EXPECT_EQ(Send("chirp 1 0.05 3 3 30")[0].reason, "f1_hz must be above f0_hz");
  auto r = Send("chirp 3 0.05 0.2 3 10");
  EXPECT_EQ(r.back().result, AckResult::kAccepted);
  // u(t) = A sin(2 pi (f0 + k/2 t) t), k = (f1 - f0) / T (Eq. 2.14), on the throttle channel.
  const double k = (3.0 - 0.2) / 10.0;
  std::vector<TaskReport> all;
  for (int i = 1; i <= 400; ++i) {
    for (auto& rep : Step()) all.push_back(rep);
    const double t = 0.02 * i;
    EXPECT_EQ(out_.chirp_channel, ServoChannel::kThrottle);
    EXPECT_NEAR(out_.chirp_value, 0.05 * std::sin(2 * M_PI * (0.2 + k / 2 * t) * t), 1e-9) << t;
    EXPECT_EQ(out_.task, Task::kHover);
  }
  ASSERT_FALSE(all.empty());
  EXPECT_EQ(all.back().result, AckResult::kInProgress);
  EXPECT_NEAR(all.back().percent, 80, 5);
  for (int i = 0; i < 110; ++i)
    for (auto& rep : Step()) all.push_back(rep);
  EXPECT_EQ(all.back().result, AckResult::kCompleted);
  EXPECT_EQ(out_.chirp_channel, ServoChannel::kNone);
  EXPECT_EQ(out_.chirp_value, 0.0);
  // Any other command ends a chirp at once.
  Send("chirp 2 0.05 0.2 3 10");
  Step();
  EXPECT_EQ(out_.chirp_channel, ServoChannel::kElevator);
  r = Send("hover");
  EXPECT_EQ(r[0].result, AckResult::kFailed);
  EXPECT_EQ(r[0].reason, "superseded by hover");
  Step();
  EXPECT_EQ(out_.chirp_channel, ServoChannel::kNone);
}

TEST_F(TaskManagerTest, LandCompletesAfterStillOnGroundAndDisarms) {
  Send("arm");
  Send("takeoff 5");
  est_.p_N.z() = -5;
  Step();
  Send("land");
  Step();
  EXPECT_EQ(*out_.setpoint.descent_rate, 0.7);
  est_.p_N.z() = -1.0;
  Step();
  EXPECT_NEAR(*out_.setpoint.descent_rate, 0.7 / 3, 1e-12);
  est_.p_N.z() = -0.05;
  std::vector<TaskReport> done;
  for (int i = 0; i < 20 && done.empty(); ++i)  // landed_time 0.5 s
    for (const auto& x : Step(0.1))
      if (x.result != AckResult::kInProgress) done.push_back(x);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].result, AckResult::kCompleted);
  EXPECT_FALSE(out_.armed);
  EXPECT_FALSE(out_.airborne);
  // Still from t = 0.16 s; landed once 0.5 s have passed, i.e. at the first step from 0.66 s.
  EXPECT_GE(t_, 0.66 - 1e-9);
  EXPECT_LT(t_, 0.77);
}

TEST_F(TaskManagerTest, UnreachableTargetFailsAndHolds) {
  Send("arm");
  Send("takeoff 10");  // vehicle never climbs
  std::vector<TaskReport> r;
  for (int i = 0; i < 200; ++i) {
    auto s = Step(1.0);
    for (auto& x : s)
      if (x.result == AckResult::kFailed) r.push_back(x);
  }
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NE(r[0].reason.find("not reached in time"), std::string::npos);
  EXPECT_EQ(tm_.task(), Task::kHover);
}

}  // namespace
}  // namespace uav::control
