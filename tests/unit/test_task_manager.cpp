// Task manager logic on hand-made estimates: which commands are accepted in which state, what
// references they load, and how tasks complete (thesis 2.3.2).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <tuple>

#include "uav/control/position_attitude_controller.hpp"
#include "uav/control/task_manager.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/control/mixer.hpp"
#include "uav/sim/quadrotor_model.hpp"
#include "uav/shared/frames.hpp"

namespace uav::control {
namespace {

class TaskManagerTest : public ::testing::Test {
 protected:
  TaskManagerTest()
      : tm_(TaskParams::FromParameters(
            ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema()))) {}

  std::vector<CommandAck> Send(const std::string& text) {
    std::vector<CommandAck> r;
    tm_.Submit({"gcs", ++seq_, *ParseCommand(text).command}, est_, t_, &r);
    return r;
  }
  std::vector<CommandAck> Step(double dt = 0.02) {
    std::vector<CommandAck> r;
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
  std::vector<CommandAck> all;
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
  // The takeoff it replaced closes as replaced (not failed), then hover completes.
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].command, "takeoff");
  EXPECT_EQ(r[0].result, AckResult::kReplaced);
  EXPECT_EQ(r[0].reason, "replaced by hover");
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
  std::vector<CommandAck> all;
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
  EXPECT_EQ(r[0].result, AckResult::kReplaced);
  EXPECT_EQ(r[0].reason, "replaced by hover");
  Step();
  EXPECT_EQ(out_.chirp_channel, ServoChannel::kNone);
}

TEST_F(TaskManagerTest, LandCompletesAfterStillOnGroundAndDisarms) {
  Send("arm");
  Send("takeoff 5");
  est_.p_N.z() = -5;
  Step();
  Send("land");
  est_.v_N.z() = 0.7;  // descending as commanded
  Step();
  EXPECT_EQ(*out_.setpoint.descent_rate, 0.7);
  est_.p_N.z() = -1.0;
  est_.v_N.z() = 0.7 / 3;
  Step();
  EXPECT_NEAR(*out_.setpoint.descent_rate, 0.7 / 3, 1e-12);
  est_.p_N.z() = -0.05;
  est_.v_N.z() = 0.0;  // on the ground
  std::vector<CommandAck> done;
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

// Armed on the ground without a takeoff: disarmed after task_disarm_preflight (10 s), saying so
// once; a takeoff before then keeps it armed. PX4's COM_DISARM_PRFLT.
TEST_F(TaskManagerTest, ArmedOnTheGroundWithoutATakeoffDisarmsAfterTenSeconds) {
  Send("arm");
  std::string note;
  for (int i = 0; i < 495; ++i) {
    Step();
    if (!out_.note.empty()) note = out_.note;
  }
  EXPECT_TRUE(out_.armed) << "disarmed before 10 s";
  for (int i = 0; i < 10 && note.empty(); ++i) {
    Step();
    note = out_.note;
  }
  EXPECT_FALSE(out_.armed);
  EXPECT_EQ(note, "disarmed: armed on the ground for 10 s without a takeoff");
  Step();
  EXPECT_TRUE(out_.note.empty()) << "said once";
  // Armed again, a takeoff within the time: it flies on.
  Send("arm");
  for (int i = 0; i < 100; ++i) Step();
  Send("takeoff 5");
  for (int i = 0; i < 1000; ++i) Step();
  EXPECT_TRUE(out_.armed);
  EXPECT_TRUE(out_.airborne);
}

// task_disarm_land: the rotors idle after the touchdown that long, then stop, saying so.
TEST_F(TaskManagerTest, ALandingDisarmsAfterTheLandDelay) {
  TaskParams p = tm_.params();
  p.disarm_land = 2.0;
  tm_.SetParams(p);
  Send("arm");
  Send("takeoff 5");
  est_.p_N.z() = -5;
  Step();
  Send("land");
  est_.p_N.z() = -0.05;
  est_.v_N.z() = 0.0;
  for (int i = 0; i < 40; ++i) Step();  // touchdown after 0.5 s still
  EXPECT_FALSE(out_.airborne);
  EXPECT_TRUE(out_.armed) << "idling after the touchdown";
  std::string note;
  for (int i = 0; i < 100 && out_.armed; ++i) {
    Step();
    note = out_.note;
  }
  EXPECT_FALSE(out_.armed);
  EXPECT_EQ(note, "disarmed 2 s after the landing");
}

// A crash stops the motors: the task being flown fails with the crash's cause.
TEST_F(TaskManagerTest, ACrashStopsTheMotorsAndFailsTheTask) {
  Send("arm");
  Send("takeoff 10");
  est_.p_N.z() = -10;
  Step();
  Send("goto 20 0 10");
  Step();
  std::vector<CommandAck> r;
  tm_.OnCrash("tipped 75 deg (limit 60) in flight", &r);
  ASSERT_FALSE(r.empty());
  EXPECT_EQ(r.back().result, AckResult::kFailed);
  EXPECT_EQ(r.back().reason, "crashed: tipped 75 deg (limit 60) in flight");
  Step();
  EXPECT_FALSE(out_.armed);
  EXPECT_FALSE(out_.airborne);
  EXPECT_EQ(out_.task, Task::kIdle);
  r.clear();
  tm_.OnCrash("again", &r);  // the motors are off already: nothing more
  EXPECT_TRUE(r.empty());
}

// A hold required while landing (the cameras lose the ground near it) does not stop the landing;
// the same hold during a goto stops the goto with the reason.
TEST_F(TaskManagerTest, AHoldFailsafeStopsAGotoButNotALanding) {
  Send("arm");
  Send("takeoff 5");
  est_.p_N.z() = -5;
  Step();
  ASSERT_EQ(Send("goto 20 0 5")[0].result, AckResult::kAccepted);
  Step();
  std::vector<CommandAck> r;
  tm_.EnforceFailsafe(FailsafeAction::kHold, "no position", est_, t_, &r);
  // The goto fails naming the failsafe; the hold is the vehicle's own row (accepted, completed).
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].result, AckResult::kFailed);
  EXPECT_EQ(r[0].reason, "failsafe hold: no position");
  EXPECT_EQ(r[1].source, kVehicleInitiatedSource);
  EXPECT_EQ(r[1].command, "failsafe_hold");
  EXPECT_EQ(r[1].result, AckResult::kAccepted);
  EXPECT_EQ(r[2].result, AckResult::kCompleted);
  EXPECT_EQ(r[2].reason, "no position; holding position");
  Step();
  EXPECT_EQ(out_.task, Task::kHover);
  EXPECT_EQ(out_.setpoint.p_N, est_.p_N);

  tm_.EnforceFailsafe(FailsafeAction::kNone, "", est_, t_, &r);
  ASSERT_EQ(Send("land")[0].result, AckResult::kAccepted);
  Step();
  est_.p_N.z() = -1.0;
  r.clear();
  tm_.EnforceFailsafe(FailsafeAction::kHold, "no position", est_, t_, &r);
  EXPECT_TRUE(r.empty());
  Step();
  EXPECT_EQ(out_.task, Task::kLand);
  ASSERT_TRUE(out_.setpoint.descent_rate.has_value());
  EXPECT_GT(*out_.setpoint.descent_rate, 0.0);
  // A command that would do less than the hold is still refused.
  EXPECT_EQ(Send("goto 20 0 5")[0].result, AckResult::kRejected);
}

// On the barometer alone the height estimate can sit 0.6 m above the ground after touchdown:
// the landing ends when the descent has stopped for 2 s, and never turns into a hover however
// long it takes.
TEST_F(TaskManagerTest, ALandingEndsWhenTheGroundStopsTheDescentWhateverTheHeightEstimate) {
  Send("arm");
  Send("takeoff 5");
  est_.p_N.z() = -5;
  Step();
  Send("land");
  est_.v_N.z() = 0.7;
  for (int i = 0; i < 100 * 50; ++i) {  // 100 s descending: longer than any deadline
    Step();
    ASSERT_EQ(out_.task, Task::kLand);
  }
  est_.p_N.z() = -3.0;  // the estimate 3 m up when the ground stops the vehicle
  est_.v_N.z() = 0.0;
  std::vector<CommandAck> done;
  while (done.empty() && t_ < 110)
    for (const auto& x : Step(0.1))
      if (x.result != AckResult::kInProgress) done.push_back(x);
  ASSERT_EQ(done.size(), 1u);
  EXPECT_EQ(done[0].result, AckResult::kCompleted);
  EXPECT_FALSE(out_.armed);
  EXPECT_NEAR(t_, 100.12 + 2.0, 0.11);  // still from the first step at 100.12 s
}

TEST_F(TaskManagerTest, UnreachableTargetFailsAndHolds) {
  Send("arm");
  Send("takeoff 10");  // vehicle never climbs
  std::vector<CommandAck> r;
  for (int i = 0; i < 200; ++i) {
    auto s = Step(1.0);
    for (auto& x : s)
      if (x.result == AckResult::kFailed) r.push_back(x);
  }
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NE(r[0].reason.find("not reached in time"), std::string::npos);
  EXPECT_EQ(tm_.task(), Task::kHover);
}

// A goto slowed far below its speed limit (avoidance on a slow stereo pair: 0.25 m/s where 3 m/s
// was counted on) is not given up while it gets nearer: 50 m take 200 s, past the 80 s its
// deadline first gave; stopped short of it, it fails task_stall_time (60 s) after its last metre.
TEST_F(TaskManagerTest, AGotoIsNotGivenUpWhileItMakesProgress) {
  Send("arm");
  est_.p_N.z() = -5;
  Step();
  // Airborne: a take-off completed at 5 m.
  Send("takeoff 5");
  for (int i = 0; i < 50; ++i) Step(0.1);
  std::vector<CommandAck> failed;
  Send("goto 50 0 5");
  const double start = t_;
  while (t_ - start < 200.0 && est_.p_N.x() < 49.9) {
    est_.p_N.x() += 0.25 * 0.1;
    est_.v_N.x() = 0.25;
    for (auto& x : Step(0.1))
      if (x.result == AckResult::kFailed) failed.push_back(x);
  }
  EXPECT_TRUE(failed.empty()) << failed.front().reason;
  est_.v_N.setZero();
  // Stuck 10 m short of the next goal: given up after task_stall_time.
  Send("goto 0 0 5");
  for (int i = 0; i < 400; ++i) {
    if (i < 400 && est_.p_N.x() > 10) est_.p_N.x() -= 0.25 * 0.1;  // 40 m flown, then stuck
    for (auto& x : Step(0.1))
      if (x.result == AckResult::kFailed) failed.push_back(x);
  }
  while (failed.empty() && t_ < start + 1000)
    for (auto& x : Step(0.1))
      if (x.result == AckResult::kFailed) failed.push_back(x);
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_NE(failed[0].reason.find("not reached in time"), std::string::npos);
}

// A failsafe landing after a completed takeoff: its progress and touchdown are reported under
// its own vehicle-numbered row, never under the takeoff (which had closed at 100 %).
TEST_F(TaskManagerTest, AFailsafeLandingReportsAsItselfNotAsTheLastCommand) {
  Send("arm");
  const int64_t takeoff_seq = seq_ + 1;
  Send("takeoff 10");
  est_.p_N.z() = -10;
  std::vector<CommandAck> all;
  for (auto& x : Step()) all.push_back(x);
  ASSERT_EQ(all.back().result, AckResult::kCompleted);
  all.clear();
  tm_.EnforceFailsafe(FailsafeAction::kLand, "no GPS fix", est_, t_, &all);
  ASSERT_EQ(all.size(), 1u);  // the takeoff had ended: nothing more is said under it
  EXPECT_EQ(all[0].source, kVehicleInitiatedSource);
  EXPECT_EQ(all[0].command, "failsafe_land");
  EXPECT_EQ(all[0].result, AckResult::kAccepted);
  EXPECT_EQ(all[0].reason, "no GPS fix");
  const int64_t own_seq = all[0].command_seq;
  for (int i = 0; i < 400 && tm_.armed(); ++i) {
    est_.p_N.z() = std::min(0.0, est_.p_N.z() + 0.05);
    for (auto& x : Step(0.1)) all.push_back(x);
  }
  ASSERT_FALSE(tm_.armed());
  int progress = 0;
  for (const auto& x : all) {
    EXPECT_NE(x.command_seq, takeoff_seq) << Name(x.result) << " " << x.reason;
    EXPECT_EQ(x.command_seq, own_seq);
    progress += x.result == AckResult::kInProgress;
  }
  EXPECT_GT(progress, 0);
  EXPECT_EQ(all.back().result, AckResult::kCompleted);
  // A second failsafe is numbered anew.
  std::vector<CommandAck> cleared;
  tm_.EnforceFailsafe(FailsafeAction::kNone, "", est_, t_, &cleared);
  Send("arm");
  Send("takeoff 10");
  est_.p_N.z() = -10;
  Step();
  std::vector<CommandAck> again;
  tm_.EnforceFailsafe(FailsafeAction::kReturn, "battery low", est_, t_, &again);
  ASSERT_FALSE(again.empty());
  EXPECT_GT(again.back().command_seq, own_seq);
}

// Obstacle perception lost: the failsafe's return flies home at the altitude it is at (no climb
// into space never seen), then lands.
TEST_F(TaskManagerTest, AReturnAtAltitudeFliesHomeLevelAndLands) {
  Send("arm");
  Send("takeoff 4");
  est_.p_N = {20, 1, -4};
  Step();
  std::vector<CommandAck> r;
  tm_.EnforceFailsafe(FailsafeAction::kReturn, "obstacle perception lost", est_, t_, &r, /*return_at_altitude=*/true);
  double highest = 4.0;
  bool landing = false;
  for (int i = 0; i < 3000 && !landing; ++i) {
    Step(0.02);
    // A vehicle that follows its reference.
    est_.p_N = out_.setpoint.p_N;
    highest = std::max(highest, -est_.p_N.z());
    landing = out_.task == Task::kLand;
  }
  EXPECT_TRUE(landing) << Name(out_.task) << " at " << est_.p_N.transpose();
  EXPECT_LT(highest, 4.3);
  EXPECT_LT(est_.p_N.head<2>().norm(), 0.5);
}

// U-Lion's front transition outruns the hover's reference and passes wide of a corner it cannot
// stop at; once on the wing the runner counts the corner as passed (its finish line crossed) and
// goes on, rather than holding the reference short of it while the wing flies on along the leg.
TEST(MissionRunnerTest, AWingThatPassedACornerInItsTransitionGoesOnToTheNextLeg) {
  using Step = waypoints::MissionStep;
  std::vector<Step> steps;
  for (auto [n, e, item] : {std::tuple{40.0, 0.0, 1}, {60.0, -40.0, 2}, {60.0, -100.0, 3}}) {
    Step s{Step::Kind::kWaypoint};
    s.p_N = {n, e, -30};
    s.yaw_rad = NAN;
    s.item = static_cast<std::size_t>(item);
    steps.push_back(s);
  }
  const MissionRunnerParams p{1.0, 0.5, 3.0, 2.0, 1.0, 1.0, 5.0, 30.0};
  VehicleEstimate est;
  est.p_N = {0, 0, -30};
  MissionRunner runner(steps, p, est);
  // Hover's reference at 3 m/s; the vehicle transitions along the first leg at 12 m/s, through
  // the corner before it is on the wing, and 56 m past it when it is.
  MissionRunner::Output o;
  const double dt = 0.02;
  for (int i = 0; i < 400; ++i) {
    est.p_N += Eigen::Vector3d(12 * dt, 0, 0);
    est.v_N = {12, 0, 0};
    o = runner.Update(est, dt);
  }
  ASSERT_EQ(o.item, 1) << "the hover's runner waits at its corner for a vehicle that is not there";
  runner.SetWingBorne(WingBorne{13.5, 12.0, 40.0});
  // The wing flies each leg as a straight line from where it was when the leg began, as the
  // tail-sitter's L1 does, which goes on along the line past the leg's end.
  bool passed_first = false, reached_last = false;
  Eigen::Vector3d goal = steps[0].p_N, direction(1, 0, 0);
  for (int i = 0; i < 6000 && !reached_last; ++i) {
    o = runner.Update(est, dt);
    passed_first = passed_first || o.item >= 2;
    if (o.leg_end_N && !o.leg_end_N->isApprox(goal)) {
      goal = *o.leg_end_N;
      direction = (goal - est.p_N).normalized();
    }
    est.v_N = 12 * direction;
    est.p_N += est.v_N * dt;
    reached_last = o.done;
  }
  EXPECT_TRUE(passed_first);
  EXPECT_TRUE(reached_last) << "item " << o.item << " at " << est.p_N.transpose();
}

// ctl_speed_max_xy lowered in flight below the mission's own speed (DO_CHANGE_SPEED 3 m/s): the
// reference slows to the new limit at once (a setpoint above the limit is refused by the
// envelope check, and the vehicle would hold), and speeds back up to the mission's when the
// limit is raised again.
TEST(MissionRunnerTest, ALimitLoweredInFlightHoldsTheMissionsSpeedToIt) {
  using Step = waypoints::MissionStep;
  Step speed{Step::Kind::kSetSpeed};
  speed.value = 3.0;
  Step far{Step::Kind::kWaypoint};
  far.p_N = {500, 0, -20};
  far.yaw_rad = NAN;
  const MissionRunnerParams p{1.0, 0.5, 5.0, 2.0, 1.0, 1.0, 5.0, 30.0};
  VehicleEstimate est;
  est.p_N = {0, 0, -20};
  MissionRunner runner({speed, far}, p, est);
  auto fly = [&](int ticks) {
    double fastest = 0;
    MissionRunner::Output o;
    for (int i = 0; i < ticks; ++i) {
      o = runner.Update(est, 0.02);
      est.p_N = o.setpoint.p_N;  // a vehicle that follows its reference
      fastest = std::max(fastest, o.setpoint.v_ff_N.head<2>().norm());
    }
    return std::pair{fastest, *o.setpoint.speed_max_xy};
  };
  EXPECT_NEAR(fly(500).first, 3.0, 1e-6) << "the mission's 3 m/s under the 5 m/s limit";
  runner.SetSpeedLimits(2.5, 2.0, 1.0);
  fly(1);
  const auto [lowered, limit] = fly(500);
  EXPECT_LE(lowered, 2.5 + 1e-9);
  EXPECT_EQ(limit, 2.5);
  runner.SetSpeedLimits(5.0, 2.0, 1.0);
  EXPECT_NEAR(fly(500).first, 3.0, 1e-6) << "back to what the mission asked, not to the new limit";
}

// A goto replaced by hover closes as replaced and says nothing after.
TEST_F(TaskManagerTest, AReplacedCommandsRowClosesAndStaysClosed) {
  Send("arm");
  Send("takeoff 10");
  est_.p_N.z() = -10;
  Step();
  const int64_t goto_seq = seq_ + 1;
  Send("goto 50 0 10");
  Step(0.6);
  auto r = Send("hover");
  ASSERT_FALSE(r.empty());
  EXPECT_EQ(r[0].command_seq, goto_seq);
  EXPECT_EQ(r[0].result, AckResult::kReplaced);
  std::vector<CommandAck> after;
  tm_.EnforceFailsafe(FailsafeAction::kLand, "battery", est_, t_, &after);
  for (int i = 0; i < 50; ++i)
    for (auto& x : Step(0.1)) after.push_back(x);
  for (const auto& x : after) EXPECT_NE(x.command_seq, goto_seq);
}

// A goto whose goal lies nearer an obstacle than the clearance: avoidance stops short of it and
// says where. There the goto completes, saying how far short and why; at the same spot without
// the stand-in it is still flying; a new goto does not inherit the last one's stand-in.
TEST_F(TaskManagerTest, AGotoCompletesWhereAvoidanceStopsShortOfItsGoal) {
  Send("arm");
  Send("takeoff 10");
  est_.p_N = {0, 0, -10};
  Step();
  Send("goto 20 0 10");
  est_.p_N = {19.1, 0, -10};
  est_.v_N.setZero();
  for (int i = 0; i < 5; ++i) EXPECT_TRUE(Step().empty());
  EXPECT_EQ(out_.task, Task::kGoto);
  tm_.ObserveStandIn(Eigen::Vector3d(19.2, 0, -10), "the goal is 0.5 m from an obstacle");
  const auto r = Step();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].result, AckResult::kCompleted);
  EXPECT_EQ(r[0].reason, "stopped 0.9 m short: the goal is 0.5 m from an obstacle");
  EXPECT_EQ(out_.task, Task::kHover);
  EXPECT_EQ(out_.setpoint.p_N, Eigen::Vector3d(19.2, 0, -10)) << "holds where it stopped, not at the goal";
  // The next goto starts without it.
  Send("goto 40 0 10");
  est_.p_N = {19.2, 0, -10};
  EXPECT_TRUE(Step().empty());
  EXPECT_EQ(out_.task, Task::kGoto);
}

}  // namespace
}  // namespace uav::control

namespace uav::control {
namespace {

// Follow on hand-made targets: the reference trails the target along the line of sight at the
// follow distance and height, faces it (turn rate fed forward), holds on a loss and
// gives up after the timeout; hover ends it as the operator meant; the geofence wins.
class FollowTest : public TaskManagerTest {
 protected:
  FollowTest() {
    Send("arm");
    Send("takeoff 10");
    est_.p_N = {0, 0, -10};
    Step();
  }
  // A target seen now at (n, e) on the ground, from the vehicle's position.
  void See(double n, double e) {
    target_.locked = true;
    target_.on_ground = true;
    target_.utime = target_.last_seen_utime = static_cast<int64_t>(std::llround(t_ * 1e6));
    target_.p_N = {n, e, 0};
    target_.bearing_rad = std::atan2(e - est_.p_N.y(), n - est_.p_N.x());
    tm_.ObserveTarget(target_);
  }
  void Lose() {
    target_.locked = false;
    tm_.ObserveTarget(target_);
  }
  TrackedTarget target_;
  const FollowParams follow_ = TaskParams::FromParameters(
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema())).follow;
};

TEST_F(FollowTest, RefusedWithoutALockedTargetOnTheGround) {
  EXPECT_EQ(Send("follow")[0].reason, "no target locked: select one in the video first");
  See(20, 0);
  target_.on_ground = false;
  tm_.ObserveTarget(target_);
  EXPECT_EQ(Send("follow")[0].result, AckResult::kRejected);
  EXPECT_EQ(tm_.task(), Task::kHover);  // the take-off reached its height
}

TEST_F(FollowTest, TrailsAWalkingTargetAlongTheLineOfSightFacingIt) {
  See(20, 0);
  auto r = Send("follow");
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].result, AckResult::kAccepted);
  Step();
  EXPECT_EQ(out_.task, Task::kFollow);
  // Straight ahead at 20 m: the reference is the follow distance short of it, at the follow height.
  EXPECT_NEAR(out_.setpoint.p_N.x(), 20 - follow_.distance_m, 1e-9);
  EXPECT_NEAR(out_.setpoint.p_N.y(), 0, 1e-9);
  EXPECT_NEAR(out_.setpoint.p_N.z(), -follow_.height_m, 1e-9);
  EXPECT_NEAR(out_.setpoint.yaw, 0, 1e-9);
  // The target walks east at 1.5 m/s, seen at 10 Hz: the reference stays the follow distance
  // short of where it was seen, along the line of sight (no velocity fed forward).
  for (int i = 1; i <= 100; ++i) {
    See(20, 0.15 * i);
    Step(0.1);
  }
  EXPECT_EQ(out_.setpoint.v_ff_N, Eigen::Vector3d::Zero());
  const Eigen::Vector2d seen(20, 15);
  EXPECT_LT((out_.setpoint.p_N.head<2>() - (seen - follow_.distance_m * seen.normalized())).norm(), 1e-9);
  // It faces the target, carried on by the line of sight's turn rate (d/dt atan2(e, 20) at
  // 1.5 m/s east) over the frame's age (0.1 s); the rate is fed forward.
  EXPECT_NEAR(out_.setpoint.yaw_rate_ff, 20 * 1.5 / (20 * 20 + 15 * 15), 0.002);
  EXPECT_NEAR(out_.setpoint.yaw, std::atan2(15.15, 20.0), 0.001);
  // Hover ends it as the operator meant: completed, and the vehicle holds where it is.
  r = Send("hover");
  ASSERT_EQ(r.size(), 3u);
  EXPECT_EQ(r[0].command, "follow");
  EXPECT_EQ(r[0].result, AckResult::kCompleted);
  EXPECT_EQ(r[0].reason, "stopped by hover");
  Step();
  EXPECT_EQ(out_.task, Task::kHover);
  EXPECT_EQ(out_.setpoint.p_N, est_.p_N);
}

TEST_F(FollowTest, HoldsOnALossFollowsAgainOnReacquisitionAndGivesUpAfterTheTimeout) {
  See(20, 0);
  Send("follow");
  Step();
  est_.p_N = {5, 1, -6};
  Lose();
  auto r = Step();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].result, AckResult::kInProgress);
  EXPECT_EQ(r[0].reason, "target lost; holding position");
  EXPECT_EQ(out_.task, Task::kFollow);
  EXPECT_EQ(out_.setpoint.p_N, Eigen::Vector3d(5, 1, -6));
  See(20, 0);
  r = Step();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].reason, "following");
  Lose();
  const double lost_at = t_;
  std::vector<CommandAck> all;
  while (t_ - lost_at < follow_.lost_timeout_s + 0.5) {
    r = Step(0.1);
    all.insert(all.end(), r.begin(), r.end());
    if (out_.task != Task::kFollow) break;
  }
  EXPECT_NEAR(t_ - lost_at, follow_.lost_timeout_s, 0.15);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_EQ(all.back().result, AckResult::kFailed);
  EXPECT_EQ(all.back().reason, "target lost for 10 s; holding position");
  EXPECT_EQ(out_.task, Task::kHover);
}

TEST_F(FollowTest, TrackingStoppedEndsItAndTheGeofenceWins) {
  const double fence = TaskParams::FromParameters(
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema())).fence_radius;
  See(fence + 50, 0);  // the target walks out of the fence: watched from inside
  Send("follow");
  Step();
  EXPECT_LT(out_.setpoint.p_N.head<2>().norm(), fence);
  EXPECT_GT(out_.setpoint.p_N.x(), fence - 5);
  tm_.ObserveTarget(TrackedTarget{});  // the operator stopped tracking
  auto r = Step();
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].result, AckResult::kCompleted);  // the operator's own stop is not a failure
  EXPECT_EQ(r[0].reason, "tracking stopped by the operator; holding position");
  EXPECT_EQ(out_.task, Task::kHover);
}

TEST_F(FollowTest, AFailsafeTakesOverAndRefusesFollow) {
  See(20, 0);
  Send("follow");
  Step();
  std::vector<CommandAck> r;
  tm_.EnforceFailsafe(FailsafeAction::kReturn, "GCS link lost", est_, t_, &r);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].result, AckResult::kFailed);
  EXPECT_EQ(r[1].command, "failsafe_return");
  EXPECT_EQ(r[1].result, AckResult::kAccepted);
  Step();
  EXPECT_EQ(out_.task, Task::kReturn);
  EXPECT_EQ(Send("follow")[0].result, AckResult::kRejected);
}

// The 3-D speed limit (obstacle avoidance's) holds climbing: a vehicle climbing at the limit
// toward a setpoint far above is asked for no more speed, exactly as one following a reference
// that climbs at that rate; without the limit it is asked to climb faster.
TEST(PositionAttitudeController, TheThreeDimensionalSpeedLimitHoldsClimbing) {
  const ControllerParams params = ControllerParams::FromParameters(
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema()));
  ASSERT_GT(params.speed_max_up, 1.5);
  VehicleEstimate est;
  est.p_N = {0, 0, -4};
  est.v_N = {0, 0, -1.0};  // climbing at 1 m/s
  Setpoint far_above;
  far_above.p_N = {0, 0, -14};
  Setpoint limited = far_above;
  limited.speed_max = 1.0;
  Setpoint steady;  // a reference climbing with the vehicle
  steady.p_N = est.p_N;
  steady.v_ff_N = {0, 0, -1.0};
  auto throttle = [&](const Setpoint& sp) { return PositionAttitudeController(params).Update(est, sp, 0.01).throttle; };
  EXPECT_NEAR(throttle(limited), throttle(steady), 1e-9);
  EXPECT_GT(throttle(far_above), throttle(limited) + 0.01) << "the vehicle's own climb rate is above 1 m/s";
}


// The horizontal loops flown on the simulated airframe (thesis 2.4), the truth as the estimate.
class HorizontalFlight {
 public:
  explicit HorizontalFlight(const ParameterSet& params)
      : model_(hal::VehicleParams::FromParameters(params)), ctl_(ControllerParams::FromParameters(params)) {
    s_.p_N = {0, 0, -5};
  }
  // Flies `sp` for `seconds` (the controller at 50 Hz, the airframe at 500 Hz); `each` sees the
  // state after every step.
  template <typename Each>
  void Fly(const std::function<Setpoint(double)>& sp, double seconds, Each each) {
    constexpr double kDt = 0.002;
    for (int i = 0; i * kDt < seconds; ++i) {
      if (i % 10 == 0) channels_ = MixToRotors(ctl_.Update(Estimate(), sp(i * kDt), 10 * kDt));
      model_.Step(s_, channels_, Eigen::Vector3d::Zero(), kDt);
      each(s_.p_N, Eigen::Vector3d(s_.q_NB * s_.v_B));
    }
  }
  Eigen::Vector3d p_N() const { return s_.p_N; }

 private:
  VehicleEstimate Estimate() const {
    VehicleEstimate e;
    e.p_N = s_.p_N;
    e.q_NB = s_.q_NB;
    e.v_N = s_.q_NB * s_.v_B;
    e.w_B = s_.w_B;
    e.f_B = model_.SpecificForceB(s_, Eigen::Vector3d::Zero());
    e.euler = EulerFromRotationNB(s_.q_NB.toRotationMatrix());
    return e;
  }
  sim::QuadrotorModel model_;
  PositionAttitudeController ctl_;
  sim::QuadrotorState s_;
  std::array<double, 4> channels_{};
};

ParameterSet X650() {
  return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema());
}

// A detour that turns round under obstacle avoidance's speed limit (0.6 m/s) while the vehicle
// flies at 2 m/s: it brakes, and comes back no faster than a fifth over the limit. Without the
// velocity loop's lead the tilt it braked with was still there when the velocity reversed, and it
// came back at 1.35 m/s: the braking distance the safety layer counts on assumes its limit holds.
TEST(PositionAttitudeController, AReversedDetourComesBackAtItsSpeedLimit) {
  for (const double lead : {0.0, X650().Get("ctl_vel_lead")}) {
    HorizontalFlight flight(X650().With("ctl_vel_lead", lead));
    flight.Fly([](double t) {  // hover, then north at 2 m/s
      Setpoint sp;
      sp.p_N = {2.0 * std::max(0.0, t - 2.0), 0, -5};
      sp.v_ff_N = {t > 2 ? 2.0 : 0.0, 0, 0};
      return sp;
    }, 8.0, [](const Eigen::Vector3d&, const Eigen::Vector3d&) {});
    Setpoint back;
    back.p_N = flight.p_N() - Eigen::Vector3d(3, 0, 0);
    back.speed_max = 0.6;
    double furthest = flight.p_N().x(), back_speed = 0.0;
    flight.Fly([&](double) { return back; }, 6.0, [&](const Eigen::Vector3d& p, const Eigen::Vector3d& v) {
      furthest = std::max(furthest, p.x());
      back_speed = std::max(back_speed, -v.x());
    });
    if (lead > 0) {
      EXPECT_LT(back_speed, 1.2 * 0.6) << "lead " << lead;
    } else {
      EXPECT_GT(back_speed, 2.0 * 0.6) << "without the lead the reversal overshoots (the test's premise)";
    }
    // The braking distance holds the safety layer's figure: v^2 / (2 * 2.5 m/s^2) + 0.4 s * v.
    EXPECT_LT(furthest - (back.p_N.x() + 3), 2.0 * 2.0 / 5.0 + 0.4 * 2.0) << "lead " << lead;
  }
}

// A 10 m goto from a hover flies at the vehicle's speed limit, not over it, and stops on its
// target without passing it.
TEST(PositionAttitudeController, AGotoHoldsItsSpeedLimitAndStopsOnItsTarget) {
  for (const double lead : {0.0, X650().Get("ctl_vel_lead")}) {
    HorizontalFlight flight(X650().With("ctl_vel_lead", lead));
    flight.Fly([](double) { Setpoint sp; sp.p_N = {0, 0, -5}; return sp; }, 2.0,
               [](const Eigen::Vector3d&, const Eigen::Vector3d&) {});
    Setpoint go;
    go.p_N = flight.p_N() + Eigen::Vector3d(10, 0, 0);
    double fastest = 0.0, past = -1e9;
    flight.Fly([&](double) { return go; }, 12.0, [&](const Eigen::Vector3d& p, const Eigen::Vector3d& v) {
      fastest = std::max(fastest, v.x());
      past = std::max(past, p.x() - go.p_N.x());
    });
    const double limit = X650().Get("ctl_speed_max_xy");
    if (lead > 0) {
      EXPECT_LT(fastest, 1.05 * limit);
    } else {
      EXPECT_GT(fastest, 1.15 * limit) << "without the lead the goto passes its speed limit (the test's premise)";
    }
    EXPECT_LT(past, 0.1) << "lead " << lead;
    EXPECT_LT((flight.p_N() - go.p_N).norm(), 0.1) << "lead " << lead;
  }
}

}  // namespace
}  // namespace uav::control
