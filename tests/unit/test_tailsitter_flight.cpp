// U-Lion flown closed loop on the simulated clock (thesis 2.6.6): hover, the transitions both
// ways against the targets (front: <= 4 s to >= 10 m/s, altitude within -1/+2 m; back: <= 3 s,
// altitude within +-2 m), cruise on the wing, an aborted transition, refusals, and hover in
// wind with gusts. The controller sees the true state; the plant differs from its model where
// a test says so.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "uav/simflight/tailsitter_flight.hpp"
#include "uav/waypoints/survey.hpp"

namespace uav::runtime {
namespace {

using simflight::TailSitterFlight;

using control::TailSitterMode;

ParameterSet ULion() {
  return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/ulion.params", VehicleParameterSchema());
}

control::TailSitterSetpoint At(const Eigen::Vector3d& p_N, double heading = 0.0) {
  control::TailSitterSetpoint sp;
  sp.p_N = p_N;
  sp.heading = heading;
  return sp;
}

struct Leg {
  bool done = false;
  double time_s = 0, alt_min = 0, alt_max = 0, airspeed_end = 0;
};

// Flies a transition from the present state until the controller is in `to` (at most 15 s);
// altitude relative to where it started.
Leg Transition(TailSitterFlight& f, bool to_wing, const control::TailSitterSetpoint& sp) {
  Leg leg;
  const double h0 = f.altitude(), t0 = f.time();
  EXPECT_EQ(f.StartTransition(to_wing), "");
  const TailSitterMode to = to_wing ? TailSitterMode::kCruise : TailSitterMode::kHover;
  leg.done = f.Fly(sp, 15.0, [&] {
    leg.alt_min = std::min(leg.alt_min, f.altitude() - h0);
    leg.alt_max = std::max(leg.alt_max, f.altitude() - h0);
    return f.controller().mode() == to;
  });
  leg.time_s = f.time() - t0;
  leg.airspeed_end = f.airspeed();
  return leg;
}

TEST(TailSitterFlight, TakesOffAndHoldsAHoverInCalmAir) {
  TailSitterFlight f(ULion());
  const Eigen::Vector3d target(0, 0, -10);
  f.Fly(At(target), 12.0);
  double sum2 = 0;
  int n = 0;
  f.Fly(At(target), 10.0, [&] {
    sum2 += (f.truth().p_N - target).squaredNorm();
    ++n;
    return false;
  });
  const double rms = std::sqrt(sum2 / n);
  std::printf("[ U-Lion ] hover at 10 m in calm air: %.3f m RMS from the target, nose %.1f deg above the horizon\n", rms,
              f.samples().back().pitch_deg);
  EXPECT_LT(rms, 0.1);
  EXPECT_EQ(f.controller().mode(), TailSitterMode::kHover);
}

TEST(TailSitterFlight, TransitionsToTheWingAndBackWithinTheTargets) {
  TailSitterFlight f(ULion());
  const Eigen::Vector3d hover(0, 0, -20);
  f.PlaceInHover(hover, 0.0);
  f.Fly(At(hover), 4.0);
  const Leg front = Transition(f, true, At(hover));
  std::printf("[ U-Lion ] front transition: %.2f s to %.1f m/s, altitude %+.2f/%+.2f m\n", front.time_s, front.airspeed_end,
              front.alt_min, front.alt_max);
  ASSERT_TRUE(front.done);
  EXPECT_LE(front.time_s, 4.0);
  EXPECT_GE(front.airspeed_end, 10.0);
  EXPECT_GE(front.alt_min, -1.0);
  EXPECT_LE(front.alt_max, 2.0);
  // Cruise: airspeed and altitude held on the wing.
  f.Fly(At(hover), 8.0);
  const Eigen::Vector3d v_N = f.truth().q_NB * f.truth().v_B;
  std::printf("[ U-Lion ] cruise after 8 s: %.1f m/s airspeed, altitude %.2f m, course %.1f deg\n", f.airspeed(),
              f.altitude(), std::atan2(v_N.y(), v_N.x()) * 180 / M_PI);
  EXPECT_NEAR(f.airspeed(), 12.0, 1.0);  // ts_cruise_speed
  EXPECT_NEAR(f.altitude(), 20.0, 1.5);
  const Leg back = Transition(f, false, At(hover));
  std::printf("[ U-Lion ] back transition: %.2f s, altitude %+.2f/%+.2f m, holding %.1f m ahead\n", back.time_s, back.alt_min,
              back.alt_max, f.controller().hold_N().x() - f.truth().p_N.x());
  ASSERT_TRUE(back.done);
  EXPECT_LE(back.time_s, 3.0);
  EXPECT_GE(back.alt_min, -2.0);
  EXPECT_LE(back.alt_max, 2.0);
  // Then a hover where it stopped.
  f.Fly(At(hover), 10.0);
  EXPECT_LT((f.truth().q_NB * f.truth().v_B).norm(), 0.3);
  EXPECT_LT((f.truth().p_N - f.controller().hold_N()).norm(), 0.5);
}

TEST(TailSitterFlight, TurnsOnTheWingToANewCourse) {
  TailSitterFlight f(ULion());
  const Eigen::Vector3d hover(0, 0, -30);
  f.PlaceInHover(hover, 0.0);
  f.Fly(At(hover), 3.0);
  ASSERT_TRUE(Transition(f, true, At(hover)).done);
  // Turn to the east (90 deg) at the same altitude.
  double alt_min = 1e9, alt_max = -1e9, bank_max = 0;
  f.Fly(At(hover, M_PI / 2), 20.0, [&] {
    alt_min = std::min(alt_min, f.altitude());
    alt_max = std::max(alt_max, f.altitude());
    const Eigen::Matrix3d R = f.truth().q_NB.toRotationMatrix();
    bank_max = std::max(bank_max, std::abs(std::atan2(R(2, 1), R(2, 2))));
    return false;
  });
  const Eigen::Vector3d v_N = f.truth().q_NB * f.truth().v_B;
  const double course = std::atan2(v_N.y(), v_N.x());
  std::printf("[ U-Lion ] turn to 90 deg: course %.1f deg after 20 s, altitude %.1f..%.1f m, bank up to %.0f deg, %.1f m/s\n",
              course * 180 / M_PI, alt_min, alt_max, bank_max * 180 / M_PI, f.airspeed());
  EXPECT_NEAR(course, M_PI / 2, 5 * M_PI / 180);
  EXPECT_GT(alt_min, 28.0);
  EXPECT_LT(alt_max, 32.0);
  EXPECT_LE(bank_max, 0.5 + 0.1);  // ts_bank_max, with the attitude loop's overshoot
  EXPECT_NEAR(f.airspeed(), 12.0, 1.0);
}

// Flies a closed route of legs on the wing from where the vehicle is, each leg ending
// `anticipate` before its end (the turn starts there); returns the largest cross-track error
// [m] along the legs away from the turns and the altitude band seen.
struct RouteResult {
  double cross_track_max = 0, cross_track_rms = 0, alt_min = 1e9, alt_max = -1e9;
};
RouteResult FlyRoute(TailSitterFlight& f, const std::vector<Eigen::Vector3d>& corners, int laps) {
  RouteResult r;
  double sum2 = 0;
  int n = 0;
  const double turn = 80.0;  // turn and settle: two turn diameters (54 m radius downwind in 5 m/s)
  for (int lap = 0; lap < laps; ++lap)
    for (std::size_t i = 0; i < corners.size(); ++i) {
      control::TailSitterSetpoint sp = At(corners[(i + 1) % corners.size()]);
      sp.leg_from_N = corners[i];
      const Eigen::Vector2d a = corners[i].head<2>(), b = sp.p_N.head<2>(), d = (b - a).normalized();
      const double length = (b - a).norm();
      f.Fly(sp, 120.0, [&] {
        const Eigen::Vector2d p = f.truth().p_N.head<2>();
        const double along = (p - a).dot(d), cross = std::abs(d.x() * (p - a).y() - d.y() * (p - a).x());
        r.alt_min = std::min(r.alt_min, f.altitude());
        r.alt_max = std::max(r.alt_max, f.altitude());
        if (lap > 0 && along > turn && along < length - turn) {
          r.cross_track_max = std::max(r.cross_track_max, cross);
          sum2 += cross * cross;
          ++n;
        }
        return along >= length - 0.5 * turn;
      });
    }
  r.cross_track_rms = std::sqrt(sum2 / std::max(1, n));
  return r;
}

// Two laps of a rectangle on the wing by L1 guidance, the legs scored after the first lap away
// from the turns.
TEST(TailSitterFlight, FollowsAClosedRouteOnTheWing) {
  for (const double wind : {0.0, 5.0}) {
    TailSitterFlight f(ULion().With("wind_speed", wind).With("wind_direction", 0.6));
    const Eigen::Vector3d hover(0, 0, -40);
    f.PlaceInHover(hover, 0.0);
    f.Fly(At(hover), 6.0);
    ASSERT_EQ(f.StartTransition(true), "");
    ASSERT_TRUE(f.Fly(At(hover), 10.0,
                      [&] { return f.controller().mode() == TailSitterMode::kCruise; }));
    // A 300 x 200 m rectangle at 40 m, clockwise from ahead of the vehicle.
    const Eigen::Vector3d start = f.truth().p_N + Eigen::Vector3d(60, 0, 0);
    const std::vector<Eigen::Vector3d> corners = {
        {start.x(), start.y(), -40}, {start.x() + 300, start.y(), -40}, {start.x() + 300, start.y() + 200, -40},
        {start.x(), start.y() + 200, -40}};
    const RouteResult r = FlyRoute(f, corners, 2);
    std::printf("[ U-Lion ] 300 x 200 m route on the wing, wind %.0f m/s: cross-track %.2f m RMS, %.2f m at worst on "
                "the legs; altitude %.1f..%.1f m\n",
                wind, r.cross_track_rms, r.cross_track_max, r.alt_min, r.alt_max);
    // Calm: within a metre. In 5 m/s with drafts to 8 m/s (the wind model's defaults) on a 12 m/s
    // wing, a few metres RMS, the worst just after a draft.
    EXPECT_LT(r.cross_track_rms, wind > 0 ? 3.0 : 0.7);
    EXPECT_LT(r.cross_track_max, wind > 0 ? 12.0 : 1.5);
    EXPECT_GT(r.alt_min, 37.0);
    EXPECT_LT(r.alt_max, 43.0);
    EXPECT_EQ(f.controller().mode(), TailSitterMode::kCruise);
  }
}

// The survey planner's zig-zag for a fixed wing (lines two turn radii apart, run-ins of two radii) over
// 300 x 200 m, flown on the wing from a transition: every capture line is followed, and the
// camera's lines are held to a few metres.
TEST(TailSitterFlight, FliesASurveyOnTheWing) {
  waypoints::SurveyParams p;
  p.camera = {4.8, 3.6, 3.6, 640, 480, true};  // the simulator's downward camera
  p.altitude_m = 40;
  p.speed_m_s = 12;
  p.turn_radius_m = 30;  // 12 m/s at ts_bank_max: 27 m
  p.turnaround_m = 2 * p.turn_radius_m;  // the run-in settles the turn onto the line
  const waypoints::SurveyPlan plan = waypoints::PlanSurvey(waypoints::Polygon2{{300, -100}, {600, -100}, {600, 100}, {300, 100}}, p);
  ASSERT_TRUE(plan.ok());
  ASSERT_EQ(plan.tight_turns, 0);
  TailSitterFlight f(ULion());
  const Eigen::Vector3d hover(0, 0, -40);
  f.PlaceInHover(hover, 0.0);
  f.Fly(At(hover), 6.0);
  ASSERT_EQ(f.StartTransition(true), "");
  ASSERT_TRUE(f.Fly(At(hover), 10.0, [&] { return f.controller().mode() == TailSitterMode::kCruise; }));
  // Each line is one straight leg from its run-in to its run-out (its waypoints are collinear);
  // from the end of one line L1 guidance turns straight onto the next, as a fixed-wing mission
  // does (a leg across to the next run-in would turn 90 degrees twice in two radii).
  double worst = 0, sum2 = 0, alt_lo = 1e9, alt_hi = -1e9;
  int n = 0, lines = 0;
  for (std::size_t i = 0; i < plan.waypoints.size();) {
    std::size_t j = i;
    while (j + 1 < plan.waypoints.size() && plan.waypoints[j + 1].line == plan.waypoints[i].line &&
           plan.waypoints[j + 1].pass == plan.waypoints[i].pass)
      ++j;
    const auto& first = plan.waypoints[i];
    const auto& last = plan.waypoints[j];
    control::TailSitterSetpoint sp = At(last.p_N);
    const Eigen::Vector2d d = (last.p_N - first.p_N).head<2>().normalized();
    // The first line is approached from four radii before its run-in (the area starts 300 m
    // north of the transition).
    const double approach = i == 0 ? 4 * p.turn_radius_m : 0.0;
    sp.leg_from_N = first.p_N - approach * Eigen::Vector3d(d.x(), d.y(), 0);
    const Eigen::Vector2d a = sp.leg_from_N->head<2>(), b = last.p_N.head<2>();
    double capture_from = 1e9, capture_to = -1e9;  // along the leg
    for (std::size_t k = i; k <= j; ++k) {
      const double along = (plan.waypoints[k].p_N.head<2>() - a).dot(d);
      if (plan.waypoints[k].kind == waypoints::SurveyWaypoint::Kind::kCaptureStart) capture_from = std::min(capture_from, along);
      if (plan.waypoints[k].kind == waypoints::SurveyWaypoint::Kind::kCaptureEnd) capture_to = std::max(capture_to, along);
    }
    ++lines;
    ASSERT_TRUE(f.Fly(sp, 200.0, [&] {
      const Eigen::Vector2d q = f.truth().p_N.head<2>();
      const double along = (q - a).dot(d);
      if (along >= capture_from && along <= capture_to) {
        const double cross = std::abs(d.x() * (q - a).y() - d.y() * (q - a).x());
        worst = std::max(worst, cross);
        sum2 += cross * cross;
        ++n;
        alt_lo = std::min(alt_lo, f.altitude());
        alt_hi = std::max(alt_hi, f.altitude());
      }
      return along >= (b - a).norm();
    })) << "never reached the end of line " << lines;
    i = j + 1;
  }
  std::printf("[ U-Lion ] survey on the wing: %d lines, %.0f m of path, flown in %.0f s; capture lines held to %.2f m RMS, "
              "%.2f m at worst; altitude %.1f..%.1f m\n",
              lines, plan.path_length_m, f.time(), std::sqrt(sum2 / std::max(1, n)), worst, alt_lo, alt_hi);
  EXPECT_EQ(lines, plan.lines);
  EXPECT_LT(worst, 2.0);
  EXPECT_GT(alt_lo, 38.0);
  EXPECT_LT(alt_hi, 42.0);
}

// Flies an abort: returns the height lost at worst from the transition's start to a settled hover.
double AbortAndRecover(TailSitterFlight& f, const Eigen::Vector3d& hover, const std::function<void()>& during = {}) {
  const double h0 = f.altitude(), t0 = f.time();
  EXPECT_EQ(f.StartTransition(true), "");
  double lowest = h0;
  const bool aborted = f.Fly(At(hover), 10.0, [&] {
    if (during) during();
    lowest = std::min(lowest, f.altitude());
    return f.controller().mode() == TailSitterMode::kTransitionToHover;
  });
  std::printf("[ U-Lion ] '%s' after %.1f s\n", f.controller().event().c_str(), f.time() - t0);
  EXPECT_TRUE(aborted);
  EXPECT_NE(f.controller().event().find("transition to wing aborted"), std::string::npos);
  f.Fly(At(hover), 15.0, [&] {
    lowest = std::min(lowest, f.altitude());
    return false;
  });
  std::printf("[ U-Lion ] recovered: %s, lost %.2f m at worst, %.2f m below the start now\n",
              std::string(Name(f.controller().mode())).c_str(), h0 - lowest, h0 - f.altitude());
  EXPECT_EQ(f.controller().mode(), TailSitterMode::kHover);
  EXPECT_LT((f.truth().q_NB * f.truth().v_B).norm(), 0.5);
  return h0 - lowest;
}

TEST(TailSitterFlight, ATransitionThatTakesTooLongAbortsToHover) {
  // ts_trans_timeout 1 s: shorter than the transition needs.
  TailSitterFlight f(ULion().With("ts_trans_timeout", 1.0));
  const Eigen::Vector3d hover(0, 0, -30);
  f.PlaceInHover(hover, 0.0);
  f.Fly(At(hover), 3.0);
  EXPECT_LT(AbortAndRecover(f, hover), 5.0);
  EXPECT_NE(f.controller().event().find("not complete in 1"), std::string::npos);
}

TEST(TailSitterFlight, ARotorFailingInTheTransitionAbortsAndRecoversHoverWithinFiveMetres) {
  // Half a second into the transition the rotor browns out for 2 s: half of what is commanded,
  // 20 N at most for 21.6 N of weight. (At 58 % or more throughout, the transition completes.)
  TailSitterFlight f(ULion());
  const Eigen::Vector3d hover(0, 0, -30);
  f.PlaceInHover(hover, 0.0);
  f.Fly(At(hover), 3.0);
  const double start = f.time();
  const double lost = AbortAndRecover(f, hover, [&] {
    f.SetRotorHealth(f.time() > start + 0.5 && f.time() < start + 2.5 ? 0.5 : 1.0);
  });
  EXPECT_LT(lost, 5.0);
  EXPECT_NE(f.controller().event().find("of height"), std::string::npos);
}

TEST(TailSitterFlight, RefusesATransitionBelowItsSafeHeightOrFromTheWrongMode) {
  TailSitterFlight f(ULion());
  f.PlaceInHover({0, 0, -3}, 0.0);
  f.Fly(At({0, 0, -3}), 2.0);
  EXPECT_NE(f.StartTransition(true).find("below ts_trans_min_alt 5"), std::string::npos) << f.StartTransition(true);
  EXPECT_NE(f.StartTransition(false).find("not on the wing"), std::string::npos);
  EXPECT_EQ(f.controller().mode(), TailSitterMode::kHover);
}

TEST(TailSitterFlight, HoldsAHoverInFiveMetresOfWindWithEightMetreGusts) {
  // Wind 5 m/s from the north with turbulence (15 %), and drafts to 8 m/s (5 + 0.6 x 5) every
  // 10 s or so.
  const ParameterSet windy = ULion().With("wind_speed", 5).With("wind_gust", 0.6).With("wind_gust_interval", 10);
  TailSitterFlight f(windy);
  const Eigen::Vector3d target(0, 0, -15);
  f.PlaceInHover(target, 0.0);  // belly north: into the wind
  f.Fly(At(target), 10.0);
  double sum2 = 0, worst = 0, gust = 0;
  int n = 0;
  f.Fly(At(target), 60.0, [&] {
    const double e = (f.truth().p_N - target).head<2>().norm();
    sum2 += e * e;
    worst = std::max(worst, e);
    gust = std::max(gust, f.wind_N().norm());
    ++n;
    return false;
  });
  const double rms = std::sqrt(sum2 / n);
  std::printf("[ U-Lion ] hover in 5 m/s wind, gusts to %.1f m/s: %.2f m RMS, %.2f m at worst\n", gust, rms, worst);
  EXPECT_GT(gust, 7.0);
  EXPECT_LT(rms, 0.5);
}

}  // namespace
}  // namespace uav::runtime
