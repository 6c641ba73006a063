// Obstacle avoidance flown closed loop (the whole vehicle on the simulated clock, its own stereo
// pair and algorithms in the loop, never the scene's ground truth) through the scenarios that
// defeat simpler layers: a dead end, a textureless wall, wires across the way, a camera that
// fails mid-flight, and seeded obstacle fields of each density. Ground truth is the scene's own
// distance to the nearest surface (Scene::Clearance), which the flight stack never reads.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <set>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "uav/simflight/sim_flight.hpp"
#include "uav/shared/command_grammar.hpp"
#include "uav/world/scene.hpp"

namespace uav::runtime {
namespace {

using simflight::SimFlight;

constexpr double kAltitude = 4.0;  // [m] the flights'

ParameterSet AvoidanceParameters(bool wire_pair) {
  return ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", VehicleParameterSchema())
      .With("avd_enable", 1)
      .With("ctl_speed_max_xy", 3.0)
      .With("pwl_rig", wire_pair ? 1 : -1);
}

// A grass field with the forward stereo pair (15 Hz) and `objects` / `generate` entries. The
// pair is rolled by roll_deg about its axis: at 0 its baseline is horizontal and a horizontal
// wire, parallel to it, gives no disparity (the power-line scenes roll it 45 degrees, thesis 3.6).
// The pair carries the thesis's dot projector (4.2: 15 x 15 beams 2.5 degrees apart, the
// grating turned 16 degrees), as uav-avoid-bench's fields do: its dots are what the matcher
// finds on a plain wall. With wire_pair, a second pair 10 cm above, rolled 45 degrees, has the
// wires (pwl_rig 1) and the first the obstacles.
constexpr bool kWirePair = true;
world::Scene SceneWith(const std::string& objects, const std::string& generate = "[]", int seed = 1, int roll_deg = 0,
                       bool wire_pair = false, double stereo_rate_hz = 15) {
  const std::string second = R"(, {"name": "wires", "rate_hz": 15, "baseline_m": 0.12, "mount_xyz_m": [0.15, 0, -0.1], "mount_roll_deg": 45})";
  const std::string text = R"({"name": "avoidance scenario", "seed": )" + std::to_string(seed) + R"(,
    "sun": {"azimuth_deg": 200, "elevation_deg": 45, "ambient": 0.45},
    "ground": {"layout": "uniform", "material": "grass"},
    "objects": )" + objects + R"(, "generate": )" + generate + R"(,
    "cameras": {"stereo": [{"name": "stereo", "rate_hz": )" + std::to_string(stereo_rate_hz) + R"(, "baseline_m": 0.12, "mount_roll_deg": )" + std::to_string(roll_deg) + R"(, "preview_rate_hz": 0,
                            "laser": {"enabled": true, "rows": 15, "cols": 15, "pitch_deg": 2.5, "roll_deg": 16}})" +
                           (wire_pair ? second : "") + "]}}";
  // Named as a file of the scenes folder, so that its cameras are found beside it.
  return world::Scene::Parse(text, std::string(UAV_RESOURCE_DIR) + "/scenes/avoidance_scenario.scene.json");
}

struct Flown {
  bool reached = false;           // the goto completed, the truth within 3 m of the goal (GPS-grade navigation)
  double min_clearance = 1e9;     // [m] true, from the goto on
  Eigen::Vector3d nearest_at_N = Eigen::Vector3d::Zero();  // the truth where it was least
  double nearest_at_s = 0.0;      // [s] the scene's time then (its objects may move)
  double travel_s = 0.0;
  Eigen::Vector3d end_N = Eigen::Vector3d::Zero();  // the truth at the end
  double max_north = -1e9;        // [m] the farthest north the truth went
  std::set<AvoidState> states;    // the safety layer's, from the goto on
  std::set<Task> tasks;
  std::vector<std::string> said;  // every status text
  bool landed = false;
  std::vector<Eigen::Vector4d> track;  // t, truth N E D every second (printed when a test fails)
  std::string Track() const {
    std::string out;
    char buf[96];
    for (const auto& q : track) std::snprintf(buf, sizeof buf, " %.0fs(%.1f,%.1f,%.1f)", q[0], q[1], q[2], -q[3]), out += buf;
    return out;
  }
  bool Said(const std::string& part) const {
    return std::any_of(said.begin(), said.end(), [&](const std::string& s) { return s.find(part) != std::string::npos; });
  }
};

// Takes off to kAltitude, sends `goto goal`, and flies until the goto completes at the goal (or
// the vehicle has landed after a failsafe, or limit_s). `during(t_since_goto, flight)` runs each
// control period after the goto.
Flown FlyTo(const world::Scene& scene, const Eigen::Vector3d& goal_NEU, double limit_s,
            const std::function<void(double, SimFlight&)>& during = {}) {
  const GeodeticPoint home{1.3521, 103.8198, 10.0};
  const int64_t start = 1'700'000'000'000'000;
  // A scene with a second pair gives it the wires.
  SimFlight flight(AvoidanceParameters(scene.stereo_rigs().size() > 1), {home, start, 0.0, limit_s + 30.0, &scene, "", nullptr});
  Blackboard& board = flight.board();
  Flown f;
  int stage = 0, seq = 0;
  double goto_t = -1;
  char goto_text[80];
  std::snprintf(goto_text, sizeof goto_text, "goto %.1f %.1f %.1f", goal_NEU.x(), goal_NEU.y(), goal_NEU.z());
  auto send = [&](const std::string& text) { board.commands.Push({"test", ++seq, *ParseCommand(text).command}); };
  flight.Run([&](int64_t now) {
    const double t = (now - start) * 1e-6;
    for (const StatusText& s : board.status.TakeAll()) f.said.push_back(s.text);
    const BlackboardData d = board.Snapshot();
    const Eigen::Vector3d p = flight.vehicle().Truth().p_N;
    if (stage == 0 && t > 1.0) send("arm"), stage = 1;
    else if (stage == 1 && d.armed) send("takeoff " + std::to_string(kAltitude)), stage = 2;
    else if (stage == 2 && d.task == Task::kHover && -p.z() > kAltitude - 0.5) send(goto_text), stage = 3, goto_t = t;
    if (stage != 3) return;
    if (const double c = scene.Clearance(p, now * 1e-6); c < f.min_clearance)
      f.min_clearance = c, f.nearest_at_N = p, f.nearest_at_s = now * 1e-6;
    f.max_north = std::max(f.max_north, p.x());
    f.states.insert(d.avoid_state);
    f.tasks.insert(d.task);
    f.end_N = p;
    f.travel_s = t - goto_t;
    if (f.track.empty() || t - goto_t >= f.track.back()[0] + 1.0) f.track.emplace_back(t - goto_t, p.x(), p.y(), p.z());
    if (during) during(t - goto_t, flight);
    // UAV_AVOID_TRACE=1: every 0.25 s the truth, its velocity and true clearance, the safety
    // layer's state, speed limit and seen-free length, and the plan's points.
    if (std::getenv("UAV_AVOID_TRACE") && std::fmod(t - goto_t, 0.25) < 0.021) {
      const auto plan = d.avoid_plan;
      std::printf("TR %.2f p %.2f %.2f %.2f v %.2f %.2f %.2f c %.2f st %s lim %.2f sf %.2f path", t - goto_t, p.x(), p.y(), -p.z(),
                  flight.vehicle().Truth().v_N.x(), flight.vehicle().Truth().v_N.y(), -flight.vehicle().Truth().v_N.z(),
                  scene.Clearance(p, now * 1e-6), std::string(Name(d.avoid_state)).c_str(), d.avoid_speed_limit,
                  plan ? plan->seen_free_m : -1.0);
      if (plan) for (const auto& q : plan->path_N) std::printf(" (%.1f,%.1f,%.1f)", q.x(), q.y(), -q.z());
      std::printf(" | %s\n", d.avoid_reason.c_str());
    }
    const Eigen::Vector3d goal_N(goal_NEU.x(), goal_NEU.y(), -goal_NEU.z());
    if (t - goto_t > 1.0 && d.task == Task::kHover && (p - goal_N).norm() < 3.0) {
      f.reached = true;
      flight.Stop();
    }
    if (t - goto_t > 1.0 && !d.armed) {
      f.landed = true;
      flight.Stop();
    }
    if (t - goto_t > limit_s) flight.Stop();
  });
  // What it came nearest.
  int nearest_id = world::kNoObject;
  scene.Clearance(f.nearest_at_N, f.nearest_at_s, &nearest_id);
  const std::string nearest = scene.Describe(nearest_id);
  std::printf("nearest at (%.1f, %.1f, %.1f): %s\n", f.nearest_at_N.x(), f.nearest_at_N.y(), -f.nearest_at_N.z(), nearest.c_str());
  std::printf("flown %.1f s: %s, true clearance min %.2f m, end (%.1f, %.1f, %.1f), states:", f.travel_s,
              f.reached ? "reached" : f.landed ? "landed" : "not reached", f.min_clearance, f.end_N.x(), f.end_N.y(), -f.end_N.z());
  for (AvoidState s : f.states) std::printf(" %s", std::string(Name(s)).c_str());
  std::printf("\n");
  return f;
}

// A U of brick walls open toward the vehicle, 8 m wide and 6 m deep, 12 m high (above the
// planning window: no way over), across the straight line to the goal. The vehicle flies into
// the U's mouth, sees its bottom, and leaves it round a side (1.41 m of true clearance at least
// today; it once came within 0.23 m of a side wall while climbing inside the U).
TEST(AvoidanceFlight, LeavesAUShapedDeadEndAndReachesTheGoal) {
  const world::Scene scene = SceneWith(R"([
    {"type": "box", "kind": "wall", "center_ned": [16, 0, -6], "size": [0.4, 8.4, 12], "material": "brick"},
    {"type": "box", "kind": "wall", "center_ned": [13, -4, -6], "size": [6, 0.4, 12], "material": "brick"},
    {"type": "box", "kind": "wall", "center_ned": [13, 4, -6], "size": [6, 0.4, 12], "material": "brick"}])");
  const Flown f = FlyTo(scene, {30, 0, kAltitude}, 120);
  EXPECT_TRUE(f.reached) << f.Track();
  EXPECT_GE(f.min_clearance, 0.5) << "the body radius" << f.Track();
  EXPECT_TRUE(f.states.count(AvoidState::kAvoiding));
}

// The same U with the pair at 1.5 Hz (a loaded companion computer: the GCS window open at
// --speed 1 took the forest's pair to 1-1.9 Hz): the vehicle is never held for "no data" between
// frames, flies only as fast as it can stop on what it last saw, and arrives; the operator hears
// the avoidance state a few times, not every 0.3 s.
TEST(AvoidanceFlight, APairAtOneAndAHalfHertzStillArrivesWithoutFloodingTheMessages) {
  const world::Scene scene = SceneWith(R"([
    {"type": "box", "kind": "wall", "center_ned": [16, 0, -6], "size": [0.4, 8.4, 12], "material": "brick"},
    {"type": "box", "kind": "wall", "center_ned": [13, -4, -6], "size": [6, 0.4, 12], "material": "brick"},
    {"type": "box", "kind": "wall", "center_ned": [13, 4, -6], "size": [6, 0.4, 12], "material": "brick"}])",
                                       "[]", 1, 0, false, 1.5);
  const Flown f = FlyTo(scene, {30, 0, kAltitude}, 240);
  EXPECT_TRUE(f.reached) << f.Track();
  EXPECT_GE(f.min_clearance, 0.5) << "the body radius" << f.Track();
  const auto said = std::count_if(f.said.begin(), f.said.end(),
                                  [](const std::string& s) { return s.rfind("obstacle avoidance:", 0) == 0; });
  std::printf("at 1.5 Hz: %.1f s to the goal, %ld avoidance messages\n", f.travel_s, static_cast<long>(said));
  EXPECT_LE(said, 12);
}

// A wall of featureless plaster ("plain") across the way, 40 m wide and 15 m high: stereo finds
// only the projector's dots on it, and the space beside them stays unknown, never free. The
// vehicle stops short of it and says so (blocked, then avoiding as it looks for a way round); it
// never reaches the wall.
TEST(AvoidanceFlight, StopsShortOfATexturelessWall) {
  const world::Scene scene = SceneWith(R"([
    {"type": "box", "kind": "wall", "center_ned": [15, 0, -7.5], "size": [0.4, 40, 15], "material": "plain"}])");
  const Flown f = FlyTo(scene, {30, 0, kAltitude}, 20);
  EXPECT_FALSE(f.reached);
  EXPECT_LT(f.max_north, 15.0 - 0.2 - 0.5) << "the wall's face less the body radius";
  EXPECT_GE(f.min_clearance, 0.5);
  // Stopped short (blocked), or already looking for a way round through unknown space
  // (avoiding): either way the operator is told the way is not clear.
  EXPECT_TRUE(f.Said("obstacle avoidance: blocked") || f.Said("obstacle avoidance: avoiding"));
}

// Two poles either side of the way and a wire between their tops, sagging to the flight's
// altitude, straight across the line to the goal: the wire is passed (over, under or round a pole) with at least
// 1 m of true clearance.
// Measured 1.38 m with the map in the odometry frame (1.03, 0.73 and 1.35 m in earlier builds):
// the planner keeps its clearance on 0.4 m cells, and up to 0.7 m of it can be lost to where
// the wire and the vehicle fall in them (docs/modules/avoidance.md).
// Flown twice: with one pair rolled 45 degrees for obstacles and wires, and with a level pair for
// obstacles and a rolled one for the wires (the level pair alone sees this wire, parallel to its
// baseline, with no disparity).
TEST(AvoidanceFlight, PassesAWireAcrossTheWayWithAMetreToSpare) {
  const std::string wire = R"([
    {"type": "power_line", "poles_ne": [[15, -7], [15, 7]], "pole_height_m": 4.3, "sag_m": 0.3}])";
  for (const bool wire_pair : {false, true}) {
    SCOPED_TRACE(wire_pair ? "level pair and a rolled pair for wires" : "one rolled pair");
    const Flown f = FlyTo(SceneWith(wire, "[]", 1, wire_pair ? 0 : 45, wire_pair), {30, 0, kAltitude}, 90);
    EXPECT_TRUE(f.reached);
    EXPECT_GE(f.min_clearance, 1.0);
  }
}

// The obstacles' stereo camera goes black half way: the vehicle brakes and holds ("no data"), then
// returns home at its altitude through the space its map has seen free (the way it came), and
// lands. The pair for wires works on: its wires alone do not stand for a look ahead.
TEST(AvoidanceFlight, ACameraThatFailsMidFlightBrakesHoldsAndReturnsOnTheMap) {
  const world::Scene scene = SceneWith(R"([
    {"type": "cylinder", "kind": "pole", "base_ned": [8, 2, 0], "radius_m": 0.3, "height_m": 8, "material": "concrete"},
    {"type": "tree", "at_ne": [14, -3], "height_m": 9, "crown_radius_m": 2}])", "[]", 1, 0, kWirePair);
  bool failed = false;
  double failed_at_north = 0;
  const Flown f = FlyTo(scene, {40, 0, kAltitude}, 120, [&](double, SimFlight& flight) {
    const Eigen::Vector3d p = flight.vehicle().Truth().p_N;
    if (!failed && p.x() > 18.0) {
      flight.rig()->SetStereoFailed(0, true);
      failed = true;
      failed_at_north = p.x();
    }
  });
  ASSERT_TRUE(failed);
  EXPECT_TRUE(f.states.count(AvoidState::kNoData));
  EXPECT_TRUE(f.Said("obstacle perception lost")) << "the failsafe said why";
  EXPECT_TRUE(f.Said("blank or flat")) << "and what the camera gave";
  EXPECT_TRUE(f.tasks.count(Task::kReturn));
  std::string said;
  for (const auto& t : f.said) said += "\n  " + t;
  EXPECT_TRUE(f.landed) << said << f.Track();
  EXPECT_LT(f.end_N.head<2>().norm(), 2.0) << "landed at home";
  EXPECT_LT(f.max_north, failed_at_north + 6.0) << "stopped soon after the failure";
  EXPECT_GE(f.min_clearance, 0.5);
}

// Parameters as data: every parameter that may change in flight (its schema row says so) is
// changed over the link, one after another, on a vehicle whose obstacle pair sees a pole; after
// each, every reader has taken it (the IMU thread's land detector, every vision worker, the
// avoidance planner; the control thread is the writer), and obs_margin reaches both the
// obstacle worker (the clearance the GCS draws) and the planner (the clearance it keeps).
TEST(LiveParameters, EveryInFlightChangeReachesEveryReader) {
  const world::Scene scene = SceneWith(R"([
    {"type": "cylinder", "kind": "pole", "base_ned": [6, 0, 0], "radius_m": 0.3, "height_m": 8, "material": "concrete"}])");
  const ParameterSet params = AvoidanceParameters(false);
  std::vector<std::pair<std::string, double>> changes;
  for (const ParameterSpec& spec : VehicleParameterSchema().specs) {
    if (spec.apply != ParamApply::kInFlight) continue;
    const double v = params.Get(spec.name);
    const bool integral = v == std::floor(v) && spec.min == std::floor(spec.min) && spec.max == std::floor(spec.max);
    // A step toward the middle of its range: valid on its own, and small enough to keep the
    // cross-checks (a land threshold under the return one) true.
    const double mid = (spec.min + spec.max) / 2;
    double changed = integral ? v + (mid > v ? 1 : -1) : v + 0.05 * (mid - v);
    if (spec.name == "obs_margin") changed = 1.25;
    if (changed != v) changes.emplace_back(spec.name, changed);
  }
  ASSERT_GT(changes.size(), 50u);
  SimFlight flight(params, {{1.2966, 103.7764, 15}, 0, 0.0, 0.2 * static_cast<double>(changes.size() + 2), &scene, "", nullptr});
  flight.control().ServeParameters(params);
  Blackboard& board = flight.board();
  int64_t seq = 0;
  std::size_t next = 0;
  std::vector<std::string> missed, refused;
  std::map<int64_t, std::string> sent;  // seq -> name
  double obstacle_margin_reported = -1;
  flight.Run([&](int64_t utime) {
    for (const CommandAck& a : board.task_reports.TakeAll())
      if (a.result == CommandResult::kRejected) refused.push_back(sent[a.command_seq] + ": " + a.reason);
    if (auto o = board.reports.Take<Obstacles>(); o && !o->obstacles.empty())
      obstacle_margin_reported = o->obstacles[0].safety_radius_m - o->obstacles[0].radius_m;
    if (utime % 200'000 != 0) return;
    // The last change, 0.2 s on: every reader has its version.
    const int64_t version = board.Snapshot().params_version;
    if (next > 0) {
      const std::string& name = changes[next - 1].first;
      if (flight.imu().params_version() != version) missed.push_back(name + " (IMU)");
      for (const auto& [worker, v] : flight.sensing()->ParameterVersions())
        if (v != version) missed.push_back(name + " (" + worker + " has " + std::to_string(v) + " of " + std::to_string(version) + ")");
    }
    if (next < changes.size()) {
      char text[128];
      std::snprintf(text, sizeof text, "param %s %.6g", changes[next].first.c_str(), changes[next].second);
      const ParseResult cmd = ParseCommand(text);
      ASSERT_TRUE(cmd.ok()) << text << ": " << cmd.error;
      sent[++seq] = changes[next].first;
      board.commands.Push({"test", seq, *cmd.command});
      ++next;
    }
  });
  EXPECT_EQ(next, changes.size());
  EXPECT_TRUE(refused.empty()) << ::testing::PrintToString(refused);
  EXPECT_TRUE(missed.empty()) << ::testing::PrintToString(missed);
  EXPECT_EQ(board.Snapshot().params_version, static_cast<int64_t>(changes.size()));
  EXPECT_DOUBLE_EQ(flight.sensing()->ObstacleMargin(), 1.25);
  EXPECT_DOUBLE_EQ(flight.sensing()->PlannerMargin(), 1.25);
  EXPECT_NEAR(obstacle_margin_reported, 1.25, 1e-9) << "the obstacles the GCS draws carry the new margin";
}

// Seeded obstacle fields (the scene generator obstacle_field, as uav-avoid-bench flies them, 60 m
// at 3 m/s, a level pair for obstacles and a rolled one for wires), one per density: reached
// with the true clearance never under the body radius.
class AvoidanceField : public ::testing::TestWithParam<std::pair<double, int>> {};

TEST_P(AvoidanceField, CrossesTheFieldWithItsClearance) {
  const auto [density, seed] = GetParam();
  const int count = static_cast<int>(std::lround(density * 20 * 60));
  const world::Scene scene = SceneWith("[]", R"([{"type": "obstacle_field", "count": )" + std::to_string(count) +
                                                 R"(, "region_ne": [0, -10, 60, 10], "clear_radius_m": 3, "keep_clear_ne": [60, 0],
                                                 "wires": 4, "wire_height_m": [3, 8]}])",
                                       seed, 0, kWirePair);
  const Flown f = FlyTo(scene, {60, 0, kAltitude}, 100);
  std::string said;
  for (const auto& t : f.said) said += "\n  " + t;
  EXPECT_TRUE(f.reached) << said << f.Track();
  EXPECT_GE(f.min_clearance, 0.5) << said << f.Track();
}

// 1/49 (seed 1): a plaster wall 5.7 m long stands slanted across the way 8 m out. Without the dot
// projector stereo found almost nothing on it, the plan ran "clear" through it (0.4 m cells
// part seen free in front of it count as free) and the vehicle came within 0.15-0.26 m; with the
// dots the wall is mapped and passed (1.81 m today). 1/25 (seed 1): its goal is 2 m from a
// pole's surface as the vehicle's own navigation places it, and the map draws the pole nearer
// (0.6-0.7 m). Refused as too close, it held the vehicle 7 m short to the end; now the vehicle
// goes as near as its clearance lets and the goto completes there, 0.9 m short (1.49 m; seed 2,
// flown here meanwhile: 1.65 m). 1/12 (seed 1):
// 1.00 m, since the safety layer stops cutting the detour's corners and the thickest poles
// (read 0.61-0.67 m wide) enter the map as cylinders; before that it passed a pole at 0.14 m
// and was disabled.
INSTANTIATE_TEST_SUITE_P(Densities, AvoidanceField,
                         ::testing::Values(std::make_pair(1.0 / 49, 1), std::make_pair(1.0 / 25, 1), std::make_pair(1.0 / 12, 1)),
                         [](const auto& info) { return "per_m2_1_in_" + std::to_string(std::lround(1.0 / info.param.first)); });

}  // namespace
}  // namespace uav::runtime
