// Closed-loop flight on the simulated clock: the real worker classes, the lockstep scheduler
// and the simulated quadrotor, commands injected where the CMM thread would put them.
#include <gtest/gtest.h>

#include <functional>

#include "uav/app/lockstep_scheduler.hpp"
#include "uav/app/mission_store.hpp"
#include "uav/app/workers.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/sim_vehicle.hpp"
#include "uav/waypoints/stored_paths.hpp"

namespace uav::app {
namespace {

class ClosedLoop : public ::testing::Test {
 protected:
  static constexpr int64_t kStep = 2000, kPeriod = 20000;
  static constexpr GeodeticPoint kHome{1.2966, 103.7764, 15.0};  // the stored paths are laid out here
  ClosedLoop()
      : params_(ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params")),
        vehicle_(params_, kHome, 0),
        missions_(waypoints::kStoredPathsDir, kHome, params_.Get("ctl_speed_max_xy")),
        imu_(vehicle_, board_),
        ctl_(control::TaskParams::FromParameters(params_),
             control::ControllerParams::FromParameters(params_),
             control::FailsafeParams::FromParameters(params_), kPeriod * 1e-6, board_, &missions_),
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
      if (on_step_) on_step_();
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
  MissionStore missions_;
  std::function<void()> on_step_;  // called every control period while flying
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

// Flies a path and records, for every waypoint, the closest the vehicle came to it.
std::vector<double> ClosestApproaches(const std::vector<waypoints::MissionStep>& steps,
                                      std::vector<double>* closest, const Eigen::Vector3d& p) {
  for (std::size_t i = 0; i < steps.size(); ++i)
    if (steps[i].kind == waypoints::MissionStep::Kind::kWaypoint)
      (*closest)[i] = std::min((*closest)[i], (steps[i].p_N - p).norm());
  return *closest;
}

TEST_F(ClosedLoop, TrackFliesTheStoredPathThroughEveryWaypoint) {
  std::string error;
  const auto steps = missions_.StoredPath(1, &error);
  ASSERT_TRUE(steps) << error;
  std::vector<double> closest(steps->size(), 1e9);
  EXPECT_EQ(Fly("track 1", 5).result, control::AckResult::kRejected);  // not armed
  EXPECT_EQ(Fly("arm", 1).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("track 1", 5).result, control::AckResult::kRejected);  // path has no take-off
  EXPECT_EQ(Fly("takeoff 10", 40).result, control::AckResult::kCompleted);
  EXPECT_EQ(Fly("track 99", 5).result, control::AckResult::kRejected);  // no such file
  on_step_ = [&] { ClosestApproaches(*steps, &closest, TruthPosition()); };
  EXPECT_EQ(Fly("track 1", 200).result, control::AckResult::kCompleted);
  on_step_ = nullptr;
  int waypoints = 0;
  for (std::size_t i = 0; i < steps->size(); ++i) {
    if ((*steps)[i].kind != waypoints::MissionStep::Kind::kWaypoint) continue;
    ++waypoints;
    EXPECT_LT(closest[i], 0.3) << "waypoint at step " << i;
  }
  EXPECT_EQ(waypoints, 5);
  std::printf("track 1: %.1f s, closest approaches", elapsed_s_);
  for (double c : closest)
    if (c < 1e8) std::printf(" %.2f", c);
  std::printf(" m\n");
}

TEST_F(ClosedLoop, SurveyMissionFromTheGroundCapturesOnTheLinesAndLandsHome) {
  // A 40 m x 30 m field next to home, surveyed at 10 m with the simulator's camera.
  waypoints::SurveyParams p;
  p.camera = {4.8, 3.6, 3.6, 640, 480, true};
  p.altitude_m = 10.0;
  p.speed_m_s = 3.0;
  p.turnaround_m = 3.0;
  const LocalNedFrame frame(kHome);
  std::vector<GeodeticPoint> area;
  for (const Eigen::Vector2d& v : {Eigen::Vector2d(10, 5), Eigen::Vector2d(50, 5), Eigen::Vector2d(50, 35), Eigen::Vector2d(10, 35)})
    area.push_back(frame.ToGeodetic(Eigen::Vector3d(v.x(), v.y(), 0)));
  const waypoints::SurveyPlan plan = waypoints::PlanSurvey(area, kHome, p);
  ASSERT_TRUE(plan.ok());
  ASSERT_EQ(missions_.AcceptUpload(waypoints::MissionFromSurvey(area, kHome, p, plan)), "");

  // While capturing, the vehicle is on a survey line: its cross-track distance to the nearest
  // line and its speed along it are what the plan assumed.
  double worst_cross = 0, speed_sum = 0;
  int capturing_steps = 0;
  on_step_ = [&] {
    const auto d = board_.Snapshot();
    if (!(d.capture_interval_s || d.capture_distance_m)) return;
    ++capturing_steps;
    const auto truth = vehicle_.TruthState();
    double cross = 1e9;
    for (const auto& w : plan.waypoints) cross = std::min(cross, std::abs(truth.p_N.y() - w.p_N.y()));
    worst_cross = std::max(worst_cross, cross);
    speed_sum += (truth.q_NB * truth.v_B).head<2>().norm();
  };
  EXPECT_EQ(Fly("arm", 1).result, control::AckResult::kCompleted);
  const auto last = Fly("mission", 400);
  on_step_ = nullptr;
  EXPECT_EQ(last.result, control::AckResult::kCompleted) << last.reason;
  EXPECT_LT(TruthPosition().head<2>().norm(), 0.5);  // landed at home
  EXPECT_NEAR(TruthPosition().z(), 0.0, 0.05);
  EXPECT_FALSE(board_.Snapshot().armed);
  ASSERT_GT(capturing_steps, 100);
  EXPECT_LT(worst_cross, 0.3);
  const double mean_speed = speed_sum / capturing_steps;
  EXPECT_NEAR(mean_speed, p.speed_m_s, 0.3);
  std::printf("survey mission: %.1f s, %d lines, worst cross-track %.2f m, mean capture speed %.2f m/s\n",
              elapsed_s_, plan.lines, worst_cross, mean_speed);
}

}  // namespace
}  // namespace uav::app
