// U-Lion flown by the whole onboard stack (uav-onboard's threads on the simulated clock, the INS
// on the simulated sensors, the task manager, failsafes and the tail-sitter's controller through
// the servo board's eight channels): take off vertically, transition onto the wing, goto on the
// wing and loiter there, land with the automatic back-transition; and the refusals. Ground truth
// is the simulator's; the flight stack never reads it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uav/runtime/mission_store.hpp"
#include "uav/simflight/sim_flight.hpp"
#include "uav/shared/command_grammar.hpp"

namespace uav::runtime {
namespace {

using simflight::SimFlight;

ParameterSet ULion() {
  return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/ulion.params", VehicleParameterSchema());
}

// Drives a SimFlight of `params` from the test: commands in, acknowledgements, messages and the
// truth out, one call of `step(t)` per control period until it returns false or `limit_s`.
struct Pilot {
  static constexpr int64_t kStart = 1'700'000'000'000'000;
  static GeodeticPoint Home() { return {1.3521, 103.8198, 10.0}; }
  explicit Pilot(const ParameterSet& params, double limit_s, MissionStore* missions = nullptr)
      : flight(params, {Home(), kStart, 0.0, limit_s, nullptr, "", missions}) {}
  SimFlight flight;
  std::vector<CommandAck> acks;
  std::vector<std::string> said;
  int seq = 0;
  int Send(const std::string& text) {
    flight.board().commands.Push({"test", ++seq, *ParseCommand(text).command});
    return seq;
  }
  // The last acknowledgement of command `n` (nullopt: none yet).
  std::optional<CommandAck> Ack(int n) const {
    for (auto it = acks.rbegin(); it != acks.rend(); ++it)
      if (it->command_seq == n) return *it;
    return std::nullopt;
  }
  bool Said(const std::string& part) const {
    return std::any_of(said.begin(), said.end(), [&](const std::string& s) { return s.find(part) != std::string::npos; });
  }
  void Run(const std::function<bool(double t, const BlackboardData& d)>& step) {
    flight.Run([&](int64_t now) {
      for (const CommandAck& a : flight.board().task_reports.TakeAll()) acks.push_back(a);
      for (const StatusText& s : flight.board().status.TakeAll()) said.push_back(s.text);
      if (!step((now - kStart) * 1e-6, flight.board().Snapshot())) flight.Stop();
    });
  }
};

double Altitude(const sim::BodyTruth& s) { return -s.p_N.z(); }

// The whole VTOL flight: takeoff 30 m, transition fw, goto 300 m north on the wing, loiter,
// land (circling down to 20 m on the wing, back-transition on its own), touchdown and disarm.
TEST(ULionOnboard, TakesOffTransitionsFliesToAPointOnTheWingLoitersAndLands) {
  Pilot pilot(ULion(), 400.0);
  enum Stage { kArm, kTakeoff, kTransition, kGoto, kLoiter, kLand, kDone } stage = kArm;
  int takeoff = 0, transition = 0, go = 0, land = 0;
  double stage_t = 0, min_wing_alt = 1e9, max_wing_alt = 0, loiter_min = 1e9, loiter_max = 0;
  double transition_done_t = -1, goto_done_t = -1;
  Eigen::Vector3d land_at = Eigen::Vector3d::Zero(), touchdown = Eigen::Vector3d::Zero();
  const Eigen::Vector3d goal(300, 0, -30);
  pilot.Run([&](double t, const BlackboardData& d) {
    const sim::BodyTruth truth = pilot.flight.vehicle().Truth();
    const bool wing = d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kCruise;
    if (wing && stage < kLand)
      min_wing_alt = std::min(min_wing_alt, Altitude(truth)), max_wing_alt = std::max(max_wing_alt, Altitude(truth));
    if (std::getenv("ULION_TRACE") && static_cast<int>(t * 50) % 50 == 0)
      std::printf("t %.0f stage %d task %s mode %s p %.1f %.1f alt %.1f v %.1f as %.1f\n", t, stage, std::string(Name(d.task)).c_str(),
                  d.tailsitter ? std::string(Name(d.tailsitter->mode)).c_str() : "-", truth.p_N.x(), truth.p_N.y(), Altitude(truth),
                  truth.v_N.norm(), d.tailsitter ? d.tailsitter->airspeed_mps : 0.0);
    switch (stage) {
      case kArm:
        if (t > 2.0) pilot.Send("arm"), stage = kTakeoff;
        break;
      case kTakeoff:
        if (d.armed && !takeoff) takeoff = pilot.Send("takeoff 30");
        if (takeoff && pilot.Ack(takeoff) && pilot.Ack(takeoff)->result == CommandResult::kCompleted)
          transition = pilot.Send("transition fw"), stage = kTransition, stage_t = t;
        break;
      case kTransition:
        if (const auto a = pilot.Ack(transition); a && a->result == CommandResult::kCompleted) {
          transition_done_t = t - stage_t;
          go = pilot.Send("goto 300 0 30"), stage = kGoto, stage_t = t;
        }
        if (t - stage_t > 20) return false;
        break;
      case kGoto:
        if (const auto a = pilot.Ack(go); a && a->result == CommandResult::kCompleted) goto_done_t = t - stage_t, stage = kLoiter, stage_t = t;
        if (t - stage_t > 90) return false;
        break;
      case kLoiter:
        if (t - stage_t > 15) {
          const double r = (truth.p_N - goal).head<2>().norm();
          loiter_min = std::min(loiter_min, r), loiter_max = std::max(loiter_max, r);
        }
        if (t - stage_t > 45) land = pilot.Send("land"), land_at = truth.p_N, stage = kLand, stage_t = t;
        break;
      case kLand:
        if (!d.armed) touchdown = truth.p_N, stage = kDone;
        if (t - stage_t > 120) return false;
        break;
      case kDone:
        return false;
    }
    return true;
  });
  std::printf("[ ulion ] transition %.1f s, goto %.1f s, wing altitude %.1f-%.1f m, loiter radius %.1f-%.1f m, "
              "touchdown %.1f m from where land was sent\n",
              transition_done_t, goto_done_t, min_wing_alt, max_wing_alt, loiter_min, loiter_max,
              (touchdown - land_at).head<2>().norm());
  ASSERT_EQ(stage, kDone) << "stopped at stage " << stage;
  EXPECT_LT(transition_done_t, 4.0);
  EXPECT_GT(min_wing_alt, 27.0);
  EXPECT_LT(max_wing_alt, 34.0);
  EXPECT_LT(goto_done_t, 40.0);  // 300 m at 12 m/s is 25 s
  // The loiter circle is 1.5 turn radii (40 m at 12 m/s and ts_bank_max).
  EXPECT_GT(loiter_min, 34.0);
  EXPECT_LT(loiter_max, 52.0);
  EXPECT_TRUE(pilot.Said("landing: circling down on the wing to 20 m"));
  EXPECT_TRUE(pilot.Said("transition to hover before landing"));
  EXPECT_LT((touchdown - land_at).head<2>().norm(), 3.0);
  EXPECT_NEAR(touchdown.z(), 0.0, 0.2);
}

// A mission uploaded as for the quadrotor: take-off to 40 m, a 400 x 200 m rectangle, return
// home. The vehicle turns its belly toward the first leg, transitions on its own, flies the legs
// on the wing through their corners, flies home on the wing, circles down to
// ts_land_approach_alt (20 m) and transitions back there to land.
TEST(ULionOnboard, FliesAMissionOnTheWingAndLandsAtHome) {
  const ParameterSet params = ULion();
  waypoints::VehicleLimits limits;
  limits.max_speed_m_s = 12.0;
  MissionStore missions(std::string(UAV_RESOURCE_DIR) + "/../waypoints/paths", Pilot::Home(), limits);
  const LocalNedFrame frame(Pilot::Home());
  waypoints::Mission m;
  m.home = Pilot::Home();
  m.cruise_speed_m_s = 12.0;
  auto item = [&](int command, double north, double east, double alt) {
    waypoints::MissionItem it;
    it.command = command;
    const GeodeticPoint g = frame.ToGeodetic(Eigen::Vector3d(north, east, -alt));
    it.latitude_deg = g.latitude_deg, it.longitude_deg = g.longitude_deg, it.altitude_m = alt;
    return it;
  };
  const std::vector<Eigen::Vector2d> corners = {{150, 0}, {150, 200}, {-250, 200}, {-250, 0}};
  m.items.push_back(item(waypoints::mav_cmd::kNavTakeoff, 0, 0, 40));
  for (const auto& c : corners) m.items.push_back(item(waypoints::mav_cmd::kNavWaypoint, c.x(), c.y(), 40));
  m.items.push_back(item(waypoints::mav_cmd::kNavReturnToLaunch, 0, 0, 0));
  ASSERT_EQ(missions.AcceptUpload(m), "");
  Pilot pilot(params, 600.0, &missions);
  int mission = 0;
  double worst_corner = 0, min_wing_alt = 1e9, wing_s = 0, flown_s = 0, back_transition_alt = -1;
  std::vector<double> nearest(corners.size(), 1e9);
  bool landed = false;
  Eigen::Vector3d touchdown = Eigen::Vector3d::Zero();
  pilot.Run([&](double t, const BlackboardData& d) {
    const sim::BodyTruth truth = pilot.flight.vehicle().Truth();
    if (t > 2.0 && pilot.seq == 0) pilot.Send("arm");
    if (d.armed && !mission) mission = pilot.Send("mission");
    if (!mission || !d.airborne) {
      if (mission && d.task == Task::kIdle && t > 20) touchdown = truth.p_N, landed = true;
      return !landed;
    }
    flown_s += 0.02;
    if (std::getenv("ULION_TRACE") && static_cast<int>(t * 50) % 100 == 0) {
      const Eigen::Vector3d belly = truth.q_NB * Eigen::Vector3d::UnitZ();
      std::printf("t %.0f task %s mode %s p %.1f %.1f alt %.1f belly %.0f deg item %d\n", t, std::string(Name(d.task)).c_str(),
                  d.tailsitter ? std::string(Name(d.tailsitter->mode)).c_str() : "-", truth.p_N.x(), truth.p_N.y(), Altitude(truth),
                  std::atan2(belly.y(), belly.x()) * 180 / M_PI, d.mission_item);
    }
    for (std::size_t i = 0; i < corners.size(); ++i) nearest[i] = std::min(nearest[i], (truth.p_N.head<2>() - corners[i]).norm());
    // On the legs (the landing's approach then circles down).
    if (d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kCruise) {
      wing_s += 0.02;
      if (d.task == Task::kMission) min_wing_alt = std::min(min_wing_alt, Altitude(truth));
    }
    if (d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kTransitionToHover && back_transition_alt < 0)
      back_transition_alt = Altitude(truth);
    return true;
  });
  for (double n : nearest) worst_corner = std::max(worst_corner, n);
  std::printf("[ ulion ] mission: %.0f s in the air, %.0f s on the wing, lowest on the legs %.1f m, corners passed within "
              "%.1f m at worst, back transition at %.1f m, touchdown %.1f m from home\n",
              flown_s, wing_s, min_wing_alt, worst_corner, back_transition_alt, touchdown.head<2>().norm());
  ASSERT_TRUE(landed);
  ASSERT_TRUE(pilot.Ack(mission));
  EXPECT_EQ(pilot.Ack(mission)->result, CommandResult::kCompleted) << pilot.Ack(mission)->reason;
  EXPECT_TRUE(pilot.Said("transition to the wing for the mission"));
  EXPECT_TRUE(pilot.Said("transition to hover before landing"));
  EXPECT_TRUE(pilot.Said("landing: circling down on the wing to 20 m"));
  EXPECT_FALSE(pilot.Said("setpoint rejected"));  // the reference runs at the cruise speed on the wing
  EXPECT_NEAR(back_transition_alt, 21.0, 2.0);  // ts_land_approach_alt and its 2 m tolerance
  EXPECT_GT(wing_s, 100.0);  // 1600 m of legs and the way home at 12 m/s
  EXPECT_GT(min_wing_alt, 35.0);
  EXPECT_LT(worst_corner, 15.0);  // within the acceptance radius (half a turn radius)
  EXPECT_LT(touchdown.head<2>().norm(), 3.0);
}

// The GCS link lost while circling 300 m out: the failsafe's return flies home on the wing (a
// return in hover at 3 m/s would take 100 s of a pack that hovers under 4 minutes), circles down
// over home, transitions back there and lands.
TEST(ULionOnboard, ALinkLossReturnFliesHomeOnTheWingAndLands) {
  Pilot pilot(ULion(), 400.0);
  int takeoff = 0, transition = 0, go = 0;
  double lost_t = -1, wing_after_loss_s = 0, hover_after_loss_s = 0, back_transition_from_home = -1;
  bool landed = false;
  Eigen::Vector3d touchdown = Eigen::Vector3d::Zero();
  pilot.Run([&](double t, const BlackboardData& d) {
    const sim::BodyTruth truth = pilot.flight.vehicle().Truth();
    if (t > 2.0 && pilot.seq == 0) pilot.Send("arm");
    if (d.armed && !takeoff) takeoff = pilot.Send("takeoff 30");
    if (takeoff && !transition && pilot.Ack(takeoff) && pilot.Ack(takeoff)->result == CommandResult::kCompleted)
      transition = pilot.Send("transition fw");
    if (transition && !go && pilot.Ack(transition) && pilot.Ack(transition)->result == CommandResult::kCompleted)
      go = pilot.Send("goto 300 0 30");
    if (go && lost_t < 0 && pilot.Ack(go) && pilot.Ack(go)->result == CommandResult::kCompleted) lost_t = t;
    if (lost_t >= 0) {
      // No heartbeat for 25 s: past fs_link_return_time.
      pilot.flight.board().Update([](BlackboardData& b) { b.gcs_link_age_s = 25.0; });
      if (d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kCruise) wing_after_loss_s += 0.02;
      if (d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kHover && d.airborne) hover_after_loss_s += 0.02;
      if (d.tailsitter && d.tailsitter->mode == control::TailSitterMode::kTransitionToHover && back_transition_from_home < 0)
        back_transition_from_home = truth.p_N.head<2>().norm();
      if (!d.armed) touchdown = truth.p_N, landed = true;
    }
    return !landed;
  });
  std::printf("[ ulion ] link loss at 300 m: %.0f s on the wing, %.0f s in hover, back transition %.0f m from home, "
              "touchdown %.1f m from home\n",
              wing_after_loss_s, hover_after_loss_s, back_transition_from_home, touchdown.head<2>().norm());
  ASSERT_TRUE(landed);
  EXPECT_TRUE(pilot.Said("failsafe"));
  EXPECT_GT(wing_after_loss_s, 20.0);          // 300 m home at 12 m/s, then the circle down
  EXPECT_LT(back_transition_from_home, 60.0);  // on the approach circle (40 m) over home
  EXPECT_LT(hover_after_loss_s, 45.0);
  EXPECT_LT(touchdown.head<2>().norm(), 3.0);
}

// The operator's `hover` is not a failsafe: the transition after it is carried out. During a
// failsafe (the GCS link lost) one is refused, naming it.
TEST(ULionOnboard, AHoverCommandLetsATransitionThroughAFailsafeDoesNot) {
  Pilot pilot(ULion(), 120.0);
  int takeoff = 0, hover = 0, transition = 0, during_failsafe = 0;
  pilot.Run([&](double t, const BlackboardData& d) {
    if (t > 1.0 && pilot.seq == 0) pilot.Send("arm");
    if (d.armed && !takeoff) takeoff = pilot.Send("takeoff 20");
    if (takeoff && !hover && pilot.Ack(takeoff) && pilot.Ack(takeoff)->result == CommandResult::kCompleted) {
      hover = pilot.Send("hover");
      transition = pilot.Send("transition fw");
    }
    if (transition && !during_failsafe && pilot.Ack(transition) && pilot.Ack(transition)->result == CommandResult::kCompleted)
      pilot.flight.board().Update([](BlackboardData& b) { b.gcs_link_age_s = 25.0; });
    if (transition && !during_failsafe && pilot.Said("failsafe")) during_failsafe = pilot.Send("transition mc");
    return !(during_failsafe && pilot.Ack(during_failsafe));
  });
  ASSERT_TRUE(pilot.Ack(transition));
  EXPECT_EQ(pilot.Ack(transition)->result, CommandResult::kCompleted) << pilot.Ack(transition)->reason;
  ASSERT_TRUE(pilot.Ack(during_failsafe));
  EXPECT_EQ(pilot.Ack(during_failsafe)->result, CommandResult::kRejected);
  EXPECT_NE(pilot.Ack(during_failsafe)->reason.find("failsafe return active"), std::string::npos) << pilot.Ack(during_failsafe)->reason;
}

TEST(ULionOnboard, TransitionsAreRefusedWithTheReason) {
  Pilot pilot(ULion(), 60.0);
  int on_ground = 0, to_hover = 0, low = 0, quad = 0;
  pilot.Run([&](double t, const BlackboardData& d) {
    if (t > 1.0 && !on_ground) on_ground = pilot.Send("transition fw"), pilot.Send("arm");
    if (d.armed && !low && pilot.seq == 2) pilot.Send("takeoff 3");
    if (d.task == Task::kHover && d.airborne && !low) low = pilot.Send("transition fw"), to_hover = pilot.Send("transition mc");
    return !(low && pilot.Ack(to_hover) && t < 60);
  });
  ASSERT_TRUE(pilot.Ack(on_ground));
  EXPECT_EQ(pilot.Ack(on_ground)->result, CommandResult::kRejected);
  EXPECT_EQ(pilot.Ack(on_ground)->reason, "not flying: take off first");
  ASSERT_TRUE(pilot.Ack(low));
  EXPECT_EQ(pilot.Ack(low)->result, CommandResult::kRejected);
  EXPECT_NE(pilot.Ack(low)->reason.find("below ts_trans_min_alt"), std::string::npos) << pilot.Ack(low)->reason;
  EXPECT_EQ(pilot.Ack(to_hover)->result, CommandResult::kRejected);
  EXPECT_EQ(pilot.Ack(to_hover)->reason, "not on the wing: already hovering");
  // The quadrotor has no wing.
  Pilot x650(ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", VehicleParameterSchema()), 5.0);
  x650.Run([&](double t, const BlackboardData&) {
    if (!quad) quad = x650.Send("transition fw");
    return t < 2.0;
  });
  ASSERT_TRUE(x650.Ack(quad));
  EXPECT_EQ(x650.Ack(quad)->reason, "this vehicle is a quadrotor: it has no wing to transition to");
}

}  // namespace
}  // namespace uav::runtime
