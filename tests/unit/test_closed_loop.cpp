// Closed-loop flight on the simulated clock: the real worker classes, the lockstep scheduler
// and the simulated quadrotor, commands injected where the CMM thread would put them.
#include <gtest/gtest.h>

#include "uav/app/lockstep_scheduler.hpp"
#include "uav/app/workers.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/sim_vehicle.hpp"

namespace uav::app {
namespace {

class ClosedLoop : public ::testing::Test {
 protected:
  static constexpr int64_t kStep = 2000, kPeriod = 20000;
  ClosedLoop()
      : params_(ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params")),
        vehicle_(params_, GeodeticPoint{1.3, 103.8, 10.0}, 0),
        imu_(vehicle_, board_),
        ctl_(control::TaskParams::FromParameters(params_),
             control::ControllerParams::FromParameters(params_), kPeriod * 1e-6, board_),
        svo_(vehicle_, board_, params_.Get("rotor_input_idle")) {}

  // Sends `text` and flies until its completion (or failure) report, at most `limit_s`.
  // Returns the final report; records the worst attitude seen on the way.
  control::TaskReport Fly(const std::string& text, double limit_s) {
    const auto parsed = ParseCommand(text);
    EXPECT_TRUE(parsed.ok()) << parsed.error;
    board_.PushCommand({"test", ++seq_, *parsed.command});
    control::TaskReport last;
    bool done = false;
    LockstepScheduler s({vehicle_.utime(), kStep, 0.0, static_cast<int64_t>(limit_s * 1e6)});
    s.AddWorker("IMU", 0, kPeriod, [&](int64_t t) { imu_.Tick(t); });
    s.AddWorker("CTL", 1, kPeriod, [&](int64_t t) { ctl_.Tick(t); });
    s.AddWorker("SVO", 2, kPeriod, [&](int64_t t) {
      svo_.Tick(t);
      for (const auto& r : board_.TakeReports()) {
        if (r.seq != seq_) continue;
        last = r;
        if (r.result == control::AckResult::kCompleted || r.result == control::AckResult::kFailed ||
            r.result == control::AckResult::kRejected)
          done = true;
      }
      const auto truth = vehicle_.TruthState();
      const auto e = EulerFromRotationNB(truth.q_NB.toRotationMatrix());
      max_tilt_ = std::max({max_tilt_, std::abs(e.phi), std::abs(e.theta)});
      if (done) s.Stop();
    });
    s.Run([&](int64_t dt) { vehicle_.Step(dt); });
    elapsed_s_ = (s.now() - start_utime_) * 1e-6;
    start_utime_ = s.now();
    return last;
  }

  Eigen::Vector3d TruthPosition() const { return vehicle_.TruthState().p_N; }

  ParameterSet params_;
  sim::SimVehicle vehicle_;
  Blackboard board_;
  ImuWorker imu_;
  ControlWorker ctl_;
  ServoWorker svo_;
  int64_t seq_ = 0;
  int64_t start_utime_ = 0;
  double elapsed_s_ = 0.0;
  double max_tilt_ = 0.0;
};

TEST_F(ClosedLoop, ArmTakeoffGotoLandReachesEachTarget) {
  EXPECT_EQ(Fly("arm", 1).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("takeoff 10", 40).result, control::AckResult::kCompleted);
  EXPECT_NEAR(-TruthPosition().z(), 10.0, 0.3);
  EXPECT_NEAR(TruthPosition().head<2>().norm(), 0.0, 0.3);
  const double takeoff_s = elapsed_s_;

  EXPECT_EQ(Fly("goto 20 10 15", 60).result, control::AckResult::kCompleted);
  EXPECT_LT((TruthPosition() - Eigen::Vector3d(20, 10, -15)).norm(), 0.3);
  const double goto_s = elapsed_s_;

  // Hover holds the position it is given.
  EXPECT_EQ(Fly("hover", 1).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("land", 60).result, control::AckResult::kCompleted);
  EXPECT_NEAR(TruthPosition().z(), 0.0, 0.05);
  EXPECT_LT((TruthPosition().head<2>() - Eigen::Vector2d(20, 10)).norm(), 0.5);
  EXPECT_FALSE(board_.Snapshot().armed);
  EXPECT_LT(max_tilt_, params_.Get("ctl_tilt_max") + 0.05);
  RecordProperty("takeoff_s", std::to_string(takeoff_s));
  RecordProperty("goto_s", std::to_string(goto_s));
  std::printf("takeoff %.1f s, goto %.1f s, max tilt %.3f rad\n", takeoff_s, goto_s, max_tilt_);
}

TEST_F(ClosedLoop, RejectedCommandsChangeNothing) {
  EXPECT_EQ(Fly("takeoff 10", 1).result, control::AckResult::kRejected);  // not armed
  EXPECT_EQ(Fly("goto 1 1 5", 1).result, control::AckResult::kRejected);  // not flying
  EXPECT_EQ(Fly("arm", 1).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("disarm", 1).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("land", 1).result, control::AckResult::kRejected);
  EXPECT_NEAR(TruthPosition().norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace uav::app
