// uav-avoid-bench: obstacle avoidance measured closed loop, with the vehicle's own perception in
// the loop (the planner sees only what the stereo pairs and their algorithms report, never the
// scene). Per cell (density, speed) it generates seeded obstacle fields, 20 m wide and 60 m
// long, of trees, poles, walls, boxes and wires between poles, flies each one on the simulated
// clock from one end to the other, and prints per cell: success (goal reached, the true
// clearance never under the body radius), true clearance p5 and minimum, path length against
// the shortest collision-free path on the true field, mean speed against cruise, replanning
// time p50/p99 (wall, and the planning thread's CPU), left/right reversals per obstacle passed,
// stops over 3 s, and how far the navigation's error moves in 3 s. The vehicle carries a level
// pair for obstacles and, 10 cm above it, a pair rolled 45 degrees for wires (--wire-rig-roll).
// Any scene file (an obstacle layout of one's own) is flown the same way with --scene and --to.
//   uav-avoid-bench --density 1/25 --speed 3 --seeds 1-10 [--json OUT] [--picture DIR]
//   uav-avoid-bench --scene FILE --to N,E [--altitude M] --speed 3 --seeds 1
// Many seeds: --jobs N flies N at once in processes of their own; --slurm DIR submits them to a
// Slurm cluster as a job array (--wait merges the tasks' results when they end).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <optional>
#include <queue>
#include <random>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "seed_runs.hpp"
#include "uav/simflight/sim_flight.hpp"
#include "uav/shared/command_grammar.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/process_memory.hpp"
#include "uav/sim/sim_vehicle.hpp"
#include "uav/world/scene.hpp"

namespace {

constexpr double kWidth = 20.0, kLength = 60.0;  // the corridor [m]: north 0..60, east -10..10
constexpr double kAltitude = 4.0;                // [m] the flight's
constexpr double kClearStart = 3.0;              // [m] nothing this near the start or the goal
constexpr double kMargin = 15.0;                 // [m] the truth kept this far round a scene's home and goal

// What is flown: the scene (made per seed), the goal, the altitude, and the rectangle the truth
// is kept on.
struct Course {
  std::string scene_path;  // "": the generated corridor at `density`
  nlohmann::json scene;    // the scene file's content (its cameras replaced by the bench's pairs)
  double density = 0;
  Eigen::Vector2d goal_NE{kLength, 0};
  double altitude_m = kAltitude;
  Eigen::Vector2d lo_NE{-5, -kWidth / 2 - 5}, hi_NE{kLength + 5, kWidth / 2 + 5};
  double rig_roll_deg = 0;
  std::optional<double> wire_rig_roll_deg;  // the second pair, for wires alone
};

// The pairs the vehicle carries: a level pair for obstacles with the laser grid of thesis 4.2
// and, with wire_rig_roll_deg, a second pair 10 cm above it, rolled about its axis, for wires
// alone (pwl_rig 1: a rolled baseline ranges level wires, thesis 3.6).
nlohmann::json Rigs(const Course& c) {
  const std::string camera = uav::ResourcePath("cameras/sim_stereo_640x480.camera");
  nlohmann::json stereo = nlohmann::json::array();
  stereo.push_back({{"name", "stereo"}, {"file", camera}, {"rate_hz", 15}, {"baseline_m", 0.12}, {"mount_roll_deg", c.rig_roll_deg},
                    {"preview_rate_hz", 0},
                    {"laser", {{"enabled", true}, {"rows", 15}, {"cols", 15}, {"pitch_deg", 2.5}, {"roll_deg", 16}}}});
  if (c.wire_rig_roll_deg)
    stereo.push_back({{"name", "wires"}, {"file", camera}, {"rate_hz", 15}, {"baseline_m", 0.12}, {"mount_xyz_m", {0.15, 0, -0.1}},
                      {"mount_roll_deg", *c.wire_rig_roll_deg}});
  return {{"stereo", stereo}};
}

// The scene of one seed. The generated corridor: the seeded field of the scene generator
// `obstacle_field` at `density` obstacles per square metre, with one wire between two poles
// per 200 m^2 (fewer in sparse fields), on grass under a sun and drifting cloud shadows. A
// scene file: its content with the seed (its generators' and the sensors' noise) and the
// bench's pairs; the light and the ground it does not give are the corridor's (a scene without
// a ground has none: nothing below the horizon for the pairs to see).
uav::world::Scene MakeScene(const Course& c, int seed) {
  nlohmann::json j = c.scene;
  const nlohmann::json outdoors = {{"sun", {{"azimuth_deg", 200}, {"elevation_deg", 45}, {"ambient", 0.45}}},
                                   {"ground", {{"layout", "uniform"}, {"material", "grass"}}},
                                   {"clouds", {{"coverage", 0.25}, {"darkness", 0.3}, {"scale_m", 60}}}};
  if (c.scene_path.empty()) {
    const int count = static_cast<int>(std::lround(c.density * kWidth * kLength));
    const int wires = static_cast<int>(std::lround(kWidth * kLength / 200.0 * std::min(1.0, c.density * 25)));
    j = {{"name", "avoidance field"},
         {"objects", nlohmann::json::array()},
         {"generate", {{{"type", "obstacle_field"}, {"count", count}, {"region_ne", {0, -kWidth / 2, kLength, kWidth / 2}},
                        {"clear_radius_m", kClearStart}, {"keep_clear_ne", {kLength, 0}}, {"wires", wires},
                        {"wire_height_m", {3, 8}}}}}};
  }
  if (!j.contains("sky") || j["sky"] != false)
    for (const auto& [key, value] : outdoors.items())
      if (!j.contains(key)) j[key] = value;
  j["seed"] = seed;
  j["cameras"] = Rigs(c);
  return uav::world::Scene::Parse(j.dump(), c.scene_path.empty() ? "avoidance field" : c.scene_path);
}

// The true field at the flight's altitude on a grid over the course's rectangle: each cell's
// distance to the nearest true surface (the scene's, cables included).
struct TrueField {
  static constexpr double kRes = 0.1;
  Eigen::Vector2d lo;
  int nx = 0, ny = 0;
  std::vector<float> clearance;
  Eigen::Vector2d At(int x, int y) const { return lo + Eigen::Vector2d(x + 0.5, y + 0.5) * kRes; }
  // The cell holding p_NE.
  int X(double n) const { return static_cast<int>(std::floor((n - lo.x()) / kRes + 1e-9)); }
  int Y(double e) const { return static_cast<int>(std::floor((e - lo.y()) / kRes + 1e-9)); }
  TrueField(const uav::world::Scene& scene, const Course& c)
      : lo(c.lo_NE), nx(X(c.hi_NE.x())), ny(Y(c.hi_NE.y())), clearance(static_cast<std::size_t>(nx) * ny) {
    for (int y = 0; y < ny; ++y)
      for (int x = 0; x < nx; ++x) {
        const Eigen::Vector2d p = At(x, y);
        clearance[static_cast<std::size_t>(y) * nx + x] = static_cast<float>(scene.Clearance({p.x(), p.y(), -c.altitude_m}));
      }
  }
};

// Shortest path from home to the goal keeping `clearance` from the true field at the flight's
// altitude (8-connected A* on the 0.1 m grid; such paths are ~4 % long, corrected below). NaN
// when there is no level way: the flight must climb or dive (a cable or a wall across the whole
// course at that height), and its path is not scored against a level one.
double ShortestPath(const TrueField& field, const Eigen::Vector2d& goal_NE, double clearance) {
  const int nx = field.nx, ny = field.ny;
  const double res = TrueField::kRes;
  std::vector<float> g(static_cast<std::size_t>(nx) * ny, 1e30f);
  using E = std::pair<float, int>;
  std::priority_queue<E, std::vector<E>, std::greater<E>> open;
  const int sx = field.X(0), sy = field.Y(0), gx = field.X(goal_NE.x()), gy = field.Y(goal_NE.y());
  g[sy * nx + sx] = 0;
  open.push({0, sy * nx + sx});
  while (!open.empty()) {
    auto [f, i] = open.top();
    open.pop();
    const int x = i % nx, y = i / nx;
    if (x == gx && y == gy) return g[i] * 0.96;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int mx = x + dx, my = y + dy;
        if ((!dx && !dy) || mx < 0 || my < 0 || mx >= nx || my >= ny || field.clearance[my * nx + mx] < clearance) continue;
        const float c = g[i] + static_cast<float>(res * std::hypot(dx, dy));
        if (c < g[my * nx + mx]) {
          g[my * nx + mx] = c;
          open.push({c + static_cast<float>(res * std::hypot(gx - mx, gy - my)), my * nx + mx});
        }
      }
  }
  return NAN;
}

// Horizontal distance from p to an obstacle's footprint (its circle, or its turned box).
double FootprintDistance(const uav::world::Obstacle& o, const Eigen::Vector2d& p) {
  if (!(o.size.x() > 0 && o.size.y() > 0)) return (p - o.base_N.head<2>()).norm() - o.radius;
  const Eigen::Vector2d d = p - o.base_N.head<2>();
  const Eigen::Vector2d local(std::cos(o.yaw) * d.x() + std::sin(o.yaw) * d.y(), -std::sin(o.yaw) * d.x() + std::cos(o.yaw) * d.y());
  const Eigen::Vector2d out = (local.cwiseAbs() - 0.5 * o.size.head<2>());
  return out.maxCoeff() > 0 ? out.cwiseMax(0.0).norm() : out.maxCoeff();
}

// The shortest path's length for the operator: metres, or why there is none.
std::string ShortestText(double shortest_m) {
  if (!std::isfinite(shortest_m)) return "no level way at the flight's altitude";
  char text[32];
  std::snprintf(text, sizeof text, "%.1f m", shortest_m);
  return text;
}

// A CSV field: in double quotes, its own quotes doubled.
std::string Quoted(const std::string& text) {
  std::string out = "\"";
  for (char ch : text) out += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return out + "\"";
}

struct FlightResult {
  int seed = 0;
  bool reached = false, success = false;
  std::string why;
  double min_clearance = 1e9, clearance_p5 = 0, path_m = 0, shortest_m = 0, mean_speed = 0, time_s = 0;
  std::vector<double> replan_ms, replan_cpu_ms;  // each plan once (empty for a flight read back with --merge)
  double replan_cpu_p99_ms = NAN;                 // this flight's own p99 of replan_cpu_ms
  int reversals = 0, stops_over_3s = 0, obstacles_passed = 0;
  // How far the navigation's error moves in 3 s (RMS, horizontal), in N and in the odometry
  // frame the map is kept in: a wall seen 3 s ago is off by this much relative to the vehicle.
  double error_drift_3s_N = 0, error_drift_3s_O = 0;
  std::vector<Eigen::Vector3d> track;  // truth, every 0.1 s
  Eigen::Vector3d closest_N = Eigen::Vector3d::Zero();  // where the true clearance was least
  double closest_t = 0;                                  // and when [s after the goto]
  int closest_id = uav::world::kNoObject;                // and to what
  // Wires: the least true clearance to each cable the vehicle came within kWirePassed of (the
  // target is 1 m from every wire, whatever the body radius).
  std::vector<double> wire_clearances;
  // and each such cable's angle to the corridor's axis [deg]: 90 across the way, 0 along it
  // (a cable along the way is seen end-on, as a line from the vanishing point, and is ranged
  // poorly by any rolled pair; the target is set for cables across the corridor).
  std::vector<double> wire_angles_deg;
  // Where the time lost against cruise went: each 0.1 s sample's dt * (1 - horizontal speed /
  // cruise), when slower than cruise, given to the first cause that holds. The figure explains
  // "speed / cruise": flown time minus path / cruise is at most their sum.
  struct TimeLost {
    double blocked = 0;          // the avoidance state was "blocked" (stopped short, no way seen)
    double last_4m = 0;          // within 4 m of the goal: the stop at it
    double start = 0;            // from the goto until first at 0.9 of what it may fly
    double seen_free_limit = 0;  // under a speed limit below cruise: the space seen free
    double other = 0;            // the limit at cruise: turns, climbs, the controller's lag
    double Total() const { return blocked + last_4m + start + seen_free_limit + other; }
  };
  TimeLost lost;
  double flown_s = 0;              // from the goto to the end of the flight, sampled
  bool has_time_lost = false;      // false for a flight read back from a file written before it
  std::vector<Eigen::Vector3f> occupied;  // the vehicle's map at the end, in the flight's band
  std::shared_ptr<const TrueField> truth;  // the field at the flight's altitude
  std::ostringstream trace;               // every 0.1 s after the goto: truth, estimate, avoidance
};

// A cable counts as passed when the track came this near it [m].
constexpr double kWirePassed = 3.0;
// A cable runs across the corridor when at least this far from its axis [deg].
constexpr double kAcross = 45.0;

// The least clearance to a cable across the corridor this flight passed (NaN: none).
double LeastAcross(const FlightResult& r) {
  double least = NAN;
  for (std::size_t i = 0; i < r.wire_clearances.size(); ++i)
    if (r.wire_angles_deg[i] >= kAcross && !(r.wire_clearances[i] >= least)) least = r.wire_clearances[i];
  return least;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

FlightResult Fly(const uav::ParameterSet& params, const Course& course, int seed, double speed, bool progress) {
  FlightResult r;
  r.seed = seed;
  const uav::world::Scene scene = MakeScene(course, seed);
  const auto avd = uav::avoid::AvoidanceParams::FromParameters(params);
  const Eigen::Vector3d goal_N(course.goal_NE.x(), course.goal_NE.y(), -course.altitude_m);
  // Home (the climb) and the goal must leave the body room on the true field: a flight that
  // cannot succeed is refused, not flown.
  for (const auto& [what, p] : {std::pair<const char*, Eigen::Vector3d>{"home", {0, 0, -course.altitude_m}},
                                {"home", {0, 0, -1.0}}, {"the goal", goal_N}}) {
    int nearest = uav::world::kNoObject;
    const double c = scene.Clearance(p, 0.0, &nearest);
    if (c < avd.body_radius_m) {
      char text[300];
      char how[40] = "inside";
      if (c > 0) std::snprintf(how, sizeof how, "%.2f m from", c);
      std::snprintf(text, sizeof text, "%s (%.1f, %.1f) at %.1f m up is %s %s, within the body radius %.2f m (seed %d)", what, p.x(),
                    p.y(), -p.z(), how, scene.Describe(nearest).c_str(), avd.body_radius_m, seed);
      throw std::invalid_argument(text);
    }
  }
  r.truth = std::make_shared<const TrueField>(scene, course);
  r.shortest_m = ShortestPath(*r.truth, course.goal_NE, avd.body_radius_m);
  const uav::GeodeticPoint home{1.3521, 103.8198, 10.0};
  const int64_t start = 1'700'000'000'000'000;
  const double limit_s = 40.0 + 3.0 * course.goal_NE.norm() / speed;
  uav::simflight::SimFlight flight(params, {home, start, 0.0, limit_s, &scene, "", nullptr});
  uav::runtime::Blackboard& board = flight.board();
  const uav::sim::SimulatedVehicle& vehicle = flight.vehicle();
  // The operator's side: arm, take off, go to the far end; the flight ends at the goal.
  int stage = 0, seq = 0;
  auto send = [&](const std::string& text) {
    board.commands.Push({"bench", ++seq, *uav::ParseCommand(text).command});
  };
  char goto_text[64];
  std::snprintf(goto_text, sizeof goto_text, "goto %.2f %.2f %.2f", course.goal_NE.x(), course.goal_NE.y(), course.altitude_m);
  double last_sample_t = -1, still_since = -1, travel_start_t = -1;
  bool started = false;  // reached 0.9 of what the vehicle may fly since the goto
  r.has_time_lost = true;
  int64_t last_plan_utime = -1;
  int last_side = 0;
  std::vector<double> clearances;
  std::vector<double> cable_least(scene.cables().size(), 1e9);
  std::vector<Eigen::Vector2d> error_N, error_O;  // estimate minus truth, every 0.1 s
  flight.Run([&](int64_t now) {
    const double t = (now - start) * 1e-6;
    const uav::runtime::BlackboardData d = board.Snapshot();
    const Eigen::Vector3d p = vehicle.Truth().p_N;
    if (stage == 0 && t > 1.0) send("arm"), stage = 1;
    else if (stage == 1 && d.armed) send("takeoff " + std::to_string(course.altitude_m)), stage = 2;
    else if (stage == 2 && d.task == uav::Task::kHover && -p.z() > course.altitude_m - 0.5) send(goto_text), stage = 3, travel_start_t = t;
    // The vehicle's messages to the operator, as the GCS would show them.
    for (const uav::runtime::StatusText& m : board.status.TakeAll())
      if (progress) std::fprintf(stderr, "  seed %d t %.1f s: %s\n", seed, t, m.text.c_str());
    // A command the vehicle refuses, or a goto it gives up (no path), ends the flight with its reason.
    for (const uav::CommandAck& a : board.task_reports.TakeAll())
      if (a.source == "bench" && uav::IsFailure(a.result)) {
        r.why = a.command + (a.result == uav::CommandResult::kRejected ? " refused: " : " failed: ") + a.reason;
        flight.Stop();
      }
    if (stage != 3) return;
    if (d.avoid_plan && d.avoid_plan->utime != last_plan_utime) {
      last_plan_utime = d.avoid_plan->utime;
      r.replan_ms.push_back(d.avoid_plan->planning_ms);
      r.replan_cpu_ms.push_back(d.avoid_plan->planning_cpu_ms);
    }
    if (t - last_sample_t >= 0.1) {
      const double dt = last_sample_t < 0 ? 0.0 : t - last_sample_t;
      last_sample_t = t;
      int nearest = uav::world::kNoObject;
      const double c = scene.Clearance(p, now * 1e-6, &nearest);
      clearances.push_back(c);
      for (std::size_t i = 0; i < cable_least.size(); ++i)
        cable_least[i] = std::min(cable_least[i], scene.cables()[i].Distance(p));
      if (c < r.min_clearance) r.min_clearance = c, r.closest_N = p, r.closest_t = t - travel_start_t, r.closest_id = nearest;
      if (!r.track.empty()) r.path_m += (p - r.track.back()).head<2>().norm();
      r.track.push_back(p);
      error_N.push_back((d.estimate.p_N - p).head<2>());
      error_O.push_back((d.estimate.p_O - p).head<2>());
      // Reversals: the side the detour takes (left/right of the line to the goal), counted when
      // it changes while avoiding.
      if (d.avoid_state == uav::AvoidState::kAvoiding && d.avoid_plan && d.avoid_plan->path_N.size() >= 2) {
        const Eigen::Vector2d to_goal = course.goal_NE - p.head<2>();
        const Eigen::Vector2d ahead = uav::avoid::PointAt(d.avoid_plan->path_N, 3.0).head<2>() - p.head<2>();
        const double cross = to_goal.x() * ahead.y() - to_goal.y() * ahead.x();
        const int side = std::abs(cross) / std::max(to_goal.norm(), 1e-6) > 0.5 ? (cross > 0 ? 1 : -1) : 0;
        if (side != 0 && last_side != 0 && side != last_side) ++r.reversals;
        if (side != 0) last_side = side;
      } else if (d.avoid_state == uav::AvoidState::kClear) {
        last_side = 0;
      }
      const double v = vehicle.Truth().v_N.head<2>().norm();
      {
        // The time lost against cruise in this sample, and its cause.
        const double limit = d.avoid_speed_limit > 0 ? std::min(speed, d.avoid_speed_limit) : speed;
        if (v >= 0.9 * limit) started = true;
        const double lost = dt * std::max(0.0, 1.0 - v / speed);
        r.flown_s += dt;
        if (d.avoid_state == uav::AvoidState::kBlocked) r.lost.blocked += lost;
        else if ((course.goal_NE - p.head<2>()).norm() < 4.0) r.lost.last_4m += lost;
        else if (!started) r.lost.start += lost;
        else if (limit < 0.99 * speed) r.lost.seen_free_limit += lost;
        else r.lost.other += lost;
      }
      if (v < 0.2) {
        if (still_since < 0) still_since = t;
      } else {
        if (still_since >= 0 && t - still_since > 3.0) ++r.stops_over_3s;
        still_since = -1;
      }
      // The heading the cameras look along and the course flown [deg], and the climb rate [m/s].
      const Eigen::Vector3d v_N = vehicle.Truth().v_N;
      char row[400];
      std::snprintf(row, sizeof row, "%.1f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.0f,%.1f,%.1f,%.0f,%.2f,%.2f,%d,%.2f,%.2f,%s,%.2f,%zu,%s",
                    t - travel_start_t, p.x(), p.y(), -p.z(), d.estimate.p_N.x(), d.estimate.p_N.y(), -d.estimate.p_N.z(), v_N.norm(),
                    d.estimate.euler.psi * 180 / M_PI, d.estimate.euler.theta * 180 / M_PI, d.estimate.euler.phi * 180 / M_PI,
                    std::atan2(v_N.y(), v_N.x()) * 180 / M_PI, -v_N.z(), c,
                    nearest, d.obstacle_range_m, d.nearest_wire_m, std::string(uav::Name(d.avoid_state)).c_str(), d.avoid_speed_limit,
                    d.avoid_plan ? d.avoid_plan->path_N.size() : 0, Quoted(d.avoid_reason).c_str());
      r.trace << row;
      // The planned path itself, north:east:altitude per point, so a detour can be read off.
      r.trace << ",\"";
      if (d.avoid_plan)
        for (std::size_t i = 0; i < d.avoid_plan->path_N.size(); ++i) {
          const Eigen::Vector3d& q = d.avoid_plan->path_N[i];
          char point[64];
          std::snprintf(point, sizeof point, "%s%.1f:%.1f:%.1f", i ? " " : "", q.x(), q.y(), -q.z());
          r.trace << point;
        }
      r.trace << "\"\n";
      if (progress && static_cast<int>(t * 10) % 50 == 0)
        std::fprintf(stderr, "  seed %d t %.0f s at (%.1f, %.1f) %s\n", seed, t, p.x(), p.y(), std::string(uav::Name(d.avoid_state)).c_str());
    }
    // Reached: the goto completed (the vehicle holds at its goal, as its estimate has it) with
    // the truth within the GPS-grade navigation's few metres of it.
    if (t - travel_start_t > 1.0 && d.task == uav::Task::kHover && (p - goal_N).head<2>().norm() < 3.0) {
      r.reached = true;
      r.time_s = t - travel_start_t;
      flight.Stop();
    }
  });
  if (const auto* map = flight.sensing()->avoidance_map()) {
    // The map is kept in the odometry frame: drawn in N where the navigation puts it at the end.
    const Eigen::Vector3d p_NO = board.Snapshot().estimate.p_NO();
    r.occupied = map->OccupiedCentres(Eigen::Vector3d(course.lo_NE.x(), course.lo_NE.y(), -course.altitude_m - 1.5) - p_NO,
                                      Eigen::Vector3d(course.hi_NE.x(), course.hi_NE.y(), -course.altitude_m + 1.5) - p_NO);
    for (Eigen::Vector3f& c : r.occupied) c += p_NO.cast<float>();
  }
  for (const auto& o : scene.obstacles()) {
    double nearest = 1e9;
    for (const auto& q : r.track) nearest = std::min(nearest, FootprintDistance(o, q.head<2>()));
    if (nearest < 3.0) ++r.obstacles_passed;
  }
  auto drift_rms = [](const std::vector<Eigen::Vector2d>& e) {
    constexpr std::size_t kLag = 30;  // 3 s of 0.1 s samples
    double sq = 0;
    for (std::size_t i = 0; i + kLag < e.size(); ++i) sq += (e[i + kLag] - e[i]).squaredNorm();
    return e.size() > kLag ? std::sqrt(sq / (e.size() - kLag)) : NAN;
  };
  r.error_drift_3s_N = drift_rms(error_N);
  r.error_drift_3s_O = drift_rms(error_O);
  r.clearance_p5 = Percentile(clearances, 0.05);
  for (std::size_t i = 0; i < cable_least.size(); ++i) {
    if (cable_least[i] >= kWirePassed) continue;
    r.wire_clearances.push_back(cable_least[i]);
    const Eigen::Vector2d ab = (scene.cables()[i].b_N - scene.cables()[i].a_N).head<2>();
    const Eigen::Vector2d axis = course.goal_NE.normalized();
    r.wire_angles_deg.push_back(std::atan2(std::abs(ab.x() * axis.y() - ab.y() * axis.x()), std::abs(ab.dot(axis))) * 180.0 / M_PI);
  }
  r.mean_speed = r.reached && r.time_s > 0 ? r.path_m / r.time_s : 0.0;
  r.replan_cpu_p99_ms = Percentile(r.replan_cpu_ms, 0.99);
  r.success = r.reached && r.min_clearance >= avd.body_radius_m;
  if (!r.reached) {
    if (r.why.empty()) r.why = "goal not reached in " + std::to_string(static_cast<int>(limit_s)) + " s";
  } else if (!r.success) {
    char why[320];
    std::snprintf(why, sizeof why, "true clearance fell to %.2f m at (%.1f, %.1f), %.1f m up, %.1f s after the goto, by %s",
                  r.min_clearance, r.closest_N.x(), r.closest_N.y(), -r.closest_N.z(), r.closest_t, scene.Describe(r.closest_id).c_str());
    r.why = why;
  }
  return r;
}

// Seen from above, north to the right and east down (a map turned a quarter to the right).
void Picture(const std::string& path, const FlightResult& r, const Course& course) {
  const TrueField& truth = *r.truth;
  const Eigen::Vector2d extent = course.hi_NE - course.lo_NE;
  const double px = std::min(12.0, 2400.0 / extent.maxCoeff());  // pixels per metre
  cv::Mat img(static_cast<int>(extent.y() * px), static_cast<int>(extent.x() * px), CV_8UC3, cv::Scalar(235, 240, 235));
  auto P = [&](const Eigen::Vector2d& p) {
    return cv::Point(static_cast<int>((p.x() - course.lo_NE.x()) * px), static_cast<int>((p.y() - course.lo_NE.y()) * px));
  };
  // The true field at the flight's altitude: inside a surface dark green, within the body radius
  // light green (where the body centre must not go).
  for (int y = 0; y < truth.ny; ++y)
    for (int x = 0; x < truth.nx; ++x) {
      const float c = truth.clearance[y * truth.nx + x];
      if (c < 0.5f && c >= 0.0f)
        cv::rectangle(img, P(truth.At(x, y)), P(truth.At(x, y)) + cv::Point(1, 1),
                      c < 0.02f ? cv::Scalar(40, 100, 40) : cv::Scalar(170, 210, 170), cv::FILLED);
    }
  // The vehicle's map in the flight's band (altitude +-1.5 m), as it ended: occupied cells.
  for (const auto& c : r.occupied) {
    const cv::Point q = P(c.head<2>().cast<double>());
    cv::rectangle(img, q - cv::Point(1, 1), q + cv::Point(1, 1), cv::Scalar(0, 140, 255), cv::FILLED);
  }
  // The track, blue at the flight's altitude turning red as it goes 2.5 m or more below it.
  for (std::size_t i = 1; i < r.track.size(); ++i) {
    const double below = std::clamp((course.altitude_m + r.track[i].z()) / 2.5, 0.0, 1.0);
    cv::line(img, P(r.track[i - 1].head<2>()), P(r.track[i].head<2>()), cv::Scalar(200 * (1 - below), 80 * (1 - below), 230 * below), 2,
             cv::LINE_AA);
  }
  cv::circle(img, P({0, 0}), 6, cv::Scalar(0, 160, 0), 2);
  // The closest approach to a true surface.
  if (!r.track.empty()) cv::circle(img, P(r.closest_N.head<2>()), 9, cv::Scalar(0, 0, 255), 1, cv::LINE_AA);
  cv::circle(img, P(course.goal_NE), 6, cv::Scalar(0, 0, 200), 2);
  char field[120];
  if (course.scene_path.empty()) std::snprintf(field, sizeof field, "density %.3f/m^2", course.density);
  else std::snprintf(field, sizeof field, "%s", std::filesystem::path(course.scene_path).filename().c_str());
  char text[400];
  std::snprintf(text, sizeof text, "%s seed %d: %s, min clearance %.2f m, path %.1f m (shortest %s)", field, r.seed,
                r.success ? "success" : r.why.c_str(), r.min_clearance, r.path_m, ShortestText(r.shortest_m).c_str());
  cv::putText(img, text, {8, 18}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  if (!cv::imwrite(path, img)) throw std::runtime_error("could not write the picture " + path);
}

// The cell's figures over its flights (the targets are on these).
nlohmann::json TimeLostJson(const FlightResult::TimeLost& l) {
  return {{"total", l.Total()}, {"blocked", l.blocked}, {"last_4m", l.last_4m}, {"start", l.start},
          {"seen_free_limit", l.seen_free_limit}, {"other", l.other}};
}

nlohmann::json Cell(const std::vector<FlightResult>& results, double speed) {
  std::vector<double> p5, mins, ratio, speeds, replans, replans_cpu, flight_cpu_p99, wires, across;
  std::vector<int> failed;
  int successes = 0, reversals = 0, passed = 0, stops = 0;
  for (const auto& r : results) {
    successes += r.success;
    if (!r.success) failed.push_back(r.seed);
    if (std::isfinite(r.replan_cpu_p99_ms)) flight_cpu_p99.push_back(r.replan_cpu_p99_ms);
    reversals += r.reversals, passed += r.obstacles_passed, stops += r.stops_over_3s;
    mins.push_back(r.min_clearance);
    p5.push_back(r.clearance_p5);
    if (r.reached && r.shortest_m > 0) ratio.push_back(r.path_m / r.shortest_m);
    if (r.reached) speeds.push_back(r.mean_speed / speed);
    replans.insert(replans.end(), r.replan_ms.begin(), r.replan_ms.end());
    replans_cpu.insert(replans_cpu.end(), r.replan_cpu_ms.begin(), r.replan_cpu_ms.end());
    wires.insert(wires.end(), r.wire_clearances.begin(), r.wire_clearances.end());
    for (std::size_t i = 0; i < r.wire_clearances.size(); ++i)
      if (r.wire_angles_deg[i] >= kAcross) across.push_back(r.wire_clearances[i]);
  }
  FlightResult::TimeLost lost;
  double flown = 0;
  int with_lost = 0;
  for (const auto& r : results) {
    if (!r.has_time_lost) continue;
    ++with_lost, flown += r.flown_s;
    lost.blocked += r.lost.blocked, lost.last_4m += r.lost.last_4m, lost.start += r.lost.start;
    lost.seen_free_limit += r.lost.seen_free_limit, lost.other += r.lost.other;
  }
  const auto at_1m = [](const std::vector<double>& c) { return std::count_if(c.begin(), c.end(), [](double x) { return x >= 1.0; }); };
  return {{"flights", results.size()},
          {"success_rate", results.empty() ? 0.0 : double(successes) / results.size()},
          {"clearance_p5_m", Percentile(p5, 0.5)},
          {"clearance_min_m", mins.empty() ? NAN : *std::min_element(mins.begin(), mins.end())},
          {"path_over_shortest", Percentile(ratio, 0.5)},
          {"speed_over_cruise", Percentile(speeds, 0.5)},
          {"replan_p50_ms", Percentile(replans, 0.5)},
          {"replan_p99_ms", Percentile(replans, 0.99)},
          {"replan_cpu_p50_ms", Percentile(replans_cpu, 0.5)},
          {"replan_cpu_p99_ms", Percentile(replans_cpu, 0.99)},
          // Per flight: the median and the worst of the flights' own p99 (what --merge can
          // give, as the JSON files keep no single plans).
          {"replan_cpu_p99_median_flight_ms", Percentile(flight_cpu_p99, 0.5)},
          {"replan_cpu_p99_worst_flight_ms", flight_cpu_p99.empty() ? NAN : *std::max_element(flight_cpu_p99.begin(), flight_cpu_p99.end())},
          {"reversals_per_obstacle", passed ? double(reversals) / passed : 0.0},
          {"stops_over_3s", stops},
          {"wires_passed", wires.size()},
          {"wires_passed_at_1m", at_1m(wires)},
          {"wire_clearance_min_m", wires.empty() ? NAN : *std::min_element(wires.begin(), wires.end())},
          {"wires_across_passed", across.size()},
          {"wires_across_passed_at_1m", at_1m(across)},
          {"wire_across_clearance_min_m", across.empty() ? NAN : *std::min_element(across.begin(), across.end())},
          {"failed_seeds", failed},
          // Summed over the flights that carry it (files written before it was kept do not).
          {"time_lost_flights", with_lost},
          {"time_flown_s", flown},
          {"time_lost_s", TimeLostJson(lost)}};
}

// A flight read back from an earlier run's --json file (--merge): what the cell is made of.
// `where` names the file and the flight in errors.
FlightResult FlightFromJson(const nlohmann::json& f, const std::string& where) {
  if (!f.is_object()) throw std::invalid_argument(where + " is not a JSON object");
  auto field = [&](const char* key) -> const nlohmann::json& {
    if (!f.contains(key)) throw std::invalid_argument(where + " has no '" + key + "'");
    return f[key];
  };
  auto number = [&](const char* key) {
    const nlohmann::json& v = field(key);
    if (v.is_null()) return double{NAN};  // the bench writes NaN as null
    if (!v.is_number()) throw std::invalid_argument(where + ": '" + key + "' is not a number");
    return v.get<double>();
  };
  auto count = [&](const char* key) {
    const double v = number(key);
    if (!(v >= 0 && v <= 1e6 && v == std::floor(v))) throw std::invalid_argument(where + ": '" + key + "' is not a count");
    return static_cast<int>(v);
  };
  auto numbers = [&](const char* key) {
    const nlohmann::json& v = field(key);
    if (!v.is_array()) throw std::invalid_argument(where + ": '" + key + "' is not a list");
    std::vector<double> out;
    for (const auto& x : v) {
      if (!x.is_number()) throw std::invalid_argument(where + ": '" + key + "' holds something that is not a number");
      out.push_back(x.get<double>());
    }
    return out;
  };
  FlightResult r;
  r.seed = count("seed");
  if (!field("success").is_boolean()) throw std::invalid_argument(where + ": 'success' is not true or false");
  r.success = f["success"].get<bool>();
  r.why = f.value("why", "");
  r.min_clearance = number("min_clearance_m");
  r.clearance_p5 = number("clearance_p5_m");
  r.path_m = number("path_m");
  r.shortest_m = number("shortest_m");
  r.mean_speed = number("mean_speed");
  // Files from before "reached" was written: the mean speed is kept only for a flight that arrived.
  r.reached = f.contains("reached") ? f["reached"].get<bool>() : r.mean_speed > 0;
  r.replan_cpu_p99_ms = number("replan_cpu_p99_ms");
  r.reversals = count("reversals");
  r.obstacles_passed = count("obstacles_passed");
  r.stops_over_3s = count("stops_over_3s");
  r.wire_clearances = numbers("wire_clearances_m");
  r.wire_angles_deg = numbers("wire_angles_deg");
  if (r.wire_angles_deg.size() != r.wire_clearances.size())
    throw std::invalid_argument(where + ": 'wire_angles_deg' and 'wire_clearances_m' differ in length");
  if (f.contains("time_lost_s")) {
    const nlohmann::json& l = f["time_lost_s"];
    auto part = [&](const char* key) {
      if (!l.is_object() || !l.contains(key) || !l[key].is_number() || !(l[key].get<double>() >= 0))
        throw std::invalid_argument(where + ": 'time_lost_s' has no time '" + key + "'");
      return l[key].get<double>();
    };
    r.lost.blocked = part("blocked"), r.lost.last_4m = part("last_4m"), r.lost.start = part("start");
    r.lost.seen_free_limit = part("seen_free_limit"), r.lost.other = part("other");
    r.flown_s = number("flown_s");
    if (!(r.flown_s >= 0)) throw std::invalid_argument(where + ": 'flown_s' is not a time");
    r.has_time_lost = true;
  }
  if (r.success && !r.reached) throw std::invalid_argument(where + " succeeded without arriving (no mean speed)");
  return r;
}

// --merge: the flights of earlier runs' --json files as one cell. The files must describe the
// same course and speed (each setting the files both give must agree), and each seed is taken
// once: a long run flown in parts, side by side or over several days, is scored as one.
nlohmann::json Merge(const std::vector<std::string>& paths, std::vector<FlightResult>* results) {
  nlohmann::json out;
  std::string first;
  std::map<int, std::string> seen;  // seed -> the file it came from
  for (const std::string& path : paths) {
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(uav::ReadTextFile(path, "bench results"));
    } catch (const nlohmann::json::exception& e) {
      throw std::invalid_argument(path + " is not JSON: " + e.what());
    }
    if (!j.is_object() || !j.contains("flights") || !j["flights"].is_array() || !j.contains("speed"))
      throw std::invalid_argument(path + " is not a uav-avoid-bench --json file (no 'speed' and 'flights')");
    if (!j["speed"].is_number() || !(j["speed"].get<double>() > 0)) throw std::invalid_argument(path + ": 'speed' is not a speed");
    if (first.empty()) {
      first = path;
      out = j;
      out.erase("flights");
      out.erase("cell");
      out.erase("note");
      out["flights"] = nlohmann::json::array();
    } else {
      for (const char* key : {"density", "scene", "goal_ne_m", "altitude_m", "speed", "rig_roll_deg", "wire_rig_roll_deg"})
        if (j.contains(key) && out.contains(key) && j[key] != out[key])
          throw std::invalid_argument(path + " is another course or speed than " + first + ": '" + key + "' is " + j[key].dump() +
                                      " there, " + out[key].dump() + " here");
      for (const char* key : {"density", "scene", "goal_ne_m", "altitude_m", "rig_roll_deg", "wire_rig_roll_deg"})
        if (j.contains(key) && !out.contains(key)) out[key] = j[key];
    }
    for (std::size_t i = 0; i < j["flights"].size(); ++i) {
      const nlohmann::json& f = j["flights"][i];
      FlightResult r = FlightFromJson(f, path + ", flight " + std::to_string(i + 1));
      const auto [it, inserted] = seen.emplace(r.seed, path);
      if (!inserted) throw std::invalid_argument("seed " + std::to_string(r.seed) + " is in both " + it->second + " and " + path);
      out["flights"].push_back(f);
      results->push_back(std::move(r));
    }
  }
  std::sort(results->begin(), results->end(), [](const FlightResult& a, const FlightResult& b) { return a.seed < b.seed; });
  if (results->empty()) throw std::invalid_argument("the files given to --merge hold no flights");
  out["merged_from"] = paths;
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  CLI::App cli{"uav-avoid-bench: closed-loop obstacle avoidance over seeded obstacle fields, perception in the loop"};
  std::string density_text, scene_path, goal_text, seeds_text, json_path, picture_dir, params_path = uav::ResourcePath("vehicles/x650.params");
  double speed = 3.0, rig_roll = 0.0, wire_rig_roll = 45.0, altitude = kAltitude;
  bool quiet = false;
  std::vector<std::string> overrides;
  cli.add_option("--density", density_text, "obstacles per square metre of the generated corridor: 1/49, 1/25, 1/12 or a decimal (default 1/25)");
  cli.add_option("--scene", scene_path,
                 "fly this scene file (its objects and generators; the bench's pairs replace its cameras; the corridor's sun, "
                 "grass and clouds where it gives none) from home to --to, instead of a generated corridor");
  cli.add_option("--to", goal_text, "the goal N,E [m from home] (default 60,0: the corridor's far end; needed with --scene)");
  cli.add_option("--altitude", altitude, "the flight's altitude [m]")->check(CLI::Range(1.0, 100.0));
  cli.add_option("--speed", speed, "cruise speed [m/s] (ctl_speed_max_xy)")->check(CLI::Range(0.5, 15.0));
  cli.add_option("--seeds", seeds_text, "seed range A-B (or one seed): the scene's seed (default 1-3; with --scene, the file's own)");
  cli.add_option("--rig-roll", rig_roll, "the stereo pair rolled this much about its axis [deg] (45 ranges level wires)")
      ->check(CLI::Range(-90.0, 90.0));
  cli.add_option("--wire-rig-roll", wire_rig_roll,
                 "the second pair, for wires alone (pwl_rig 1), 10 cm above the first, rolled this much about its axis [deg]; "
                 "0: no second pair (the first has the wires)")
      ->check(CLI::Range(-90.0, 90.0));
  cli.add_option("--params", params_path, "vehicle file (avd_enable is set to 1)");
  cli.add_option("--param", overrides, "NAME=VALUE override (repeatable)");
  uav::OutputFile(cli.add_option("--json", json_path, "write the per-flight and per-cell results here"));
  cli.add_option("--picture", picture_dir, "write one picture per flight (field, true obstacles, flown track) here");
  std::string trace_dir;
  cli.add_option("--trace", trace_dir,
                 "write one CSV per flight here, every 0.1 s after the goto: the true and estimated position, speed, "
                 "true clearance and the nearest object's id, the avoidance state, speed limit, path points and reason");
  cli.add_flag("--quiet", quiet, "no progress lines");
  std::vector<std::string> merge_paths;
  cli.add_option("--merge", merge_paths,
                 "fly nothing: score the flights of these earlier --json files as one cell (the same course and speed, each seed "
                 "once), printed and, with --json, written")
      ->excludes("--density")->excludes("--scene")->excludes("--seeds")->excludes("--to")->excludes("--picture")
      ->excludes("--trace")->excludes("--speed")->excludes("--rig-roll")->excludes("--wire-rig-roll")->excludes("--param")
      ->excludes("--params")->excludes("--altitude");
  int jobs = 1, seeds_per_task = 10;
  std::string slurm_dir;
  std::vector<std::string> sbatch_options;
  bool wait = false;
  cli.add_option("--jobs", jobs, "fly this many seeds at once, each in a process of its own (a flight keeps about 1.7 cores busy)")
      ->check(CLI::Range(1, 256));
  cli.add_option("--slurm", slurm_dir,
                 "submit the seeds to Slurm (sbatch) as a job array instead of flying them here: one task per --seeds-per-task "
                 "seeds, each task's results and log in this folder (task_K.json, task_K.log)")
      ->excludes("--jobs");
  cli.add_option("--seeds-per-task", seeds_per_task, "with --slurm: seeds each task flies, one after the other (default 10)")
      ->check(CLI::Range(1, 10000));
  cli.add_option("--sbatch", sbatch_options, "with --slurm: an option for sbatch, as --sbatch=--partition=long (repeatable)");
  cli.add_flag("--wait", wait, "with --slurm: wait for the whole array and merge its results (as --merge DIR/task_*.json)");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  for (const char* option : {"--jobs", "--slurm", "--seeds-per-task", "--sbatch", "--wait"})
    if (!merge_paths.empty() && cli.count(option) > 0) {
      std::fprintf(stderr, "uav-avoid-bench: %s flies seeds; --merge flies nothing\n", option);
      return 2;
    }
  for (const char* option : {"--seeds-per-task", "--sbatch", "--wait"})
    if (slurm_dir.empty() && cli.count(option) > 0) {
      std::fprintf(stderr, "uav-avoid-bench: %s is for --slurm\n", option);
      return 2;
    }
  try {
    if (!merge_paths.empty()) {
      std::vector<FlightResult> results;
      nlohmann::json out = Merge(merge_paths, &results);
      out["cell"] = Cell(results, out["speed"].get<double>());
      if (!json_path.empty()) uav::WriteFileAtomically(json_path, out.dump(2) + "\n");
      std::printf("%s\n", out["cell"].dump(2).c_str());
      return out["cell"]["failed_seeds"].empty() ? 0 : 1;
    }
    Course course;
    course.altitude_m = altitude;
    course.rig_roll_deg = rig_roll;
    if (!scene_path.empty()) {
      if (!density_text.empty()) throw std::invalid_argument("give --density (a generated corridor) or --scene, not both");
      if (goal_text.empty()) throw std::invalid_argument("--scene needs the goal: --to N,E [m from home]");
      course.scene_path = scene_path;
      try {
        course.scene = nlohmann::json::parse(uav::ReadTextFile(scene_path, "scene"));
      } catch (const nlohmann::json::exception& e) {
        throw std::invalid_argument("scene " + scene_path + " is not JSON: " + e.what());
      }
      if (!course.scene.is_object()) throw std::invalid_argument("scene " + scene_path + " must hold a JSON object");
    } else {
      if (density_text.empty()) density_text = "1/25";
      double density = NAN;
      const auto slash = density_text.find('/');
      const auto a = uav::ParseDecimal(density_text.substr(0, slash));
      const auto b = slash == std::string::npos ? std::optional<double>(1.0) : uav::ParseDecimal(density_text.substr(slash + 1));
      if (a && b && *b != 0) density = *a / *b;
      if (!(density > 0 && density <= 0.25)) throw std::invalid_argument("--density must be in (0, 1/4] per square metre, not '" + density_text + "'");
      course.density = density;
    }
    if (!goal_text.empty()) {
      const auto ne = uav::ParseDecimalList(goal_text, 2);
      if (!ne) throw std::invalid_argument("--to must be N,E in metres from home, not '" + goal_text + "'");
      course.goal_NE = {(*ne)[0], (*ne)[1]};
      if (!(course.goal_NE.norm() >= 5.0 && course.goal_NE.norm() <= 2000.0))
        throw std::invalid_argument("--to must be 5 m to 2 km from home, not " + std::to_string(course.goal_NE.norm()) + " m");
      if (!scene_path.empty()) {
        course.lo_NE = course.goal_NE.cwiseMin(Eigen::Vector2d::Zero()) - Eigen::Vector2d::Constant(kMargin);
        course.hi_NE = course.goal_NE.cwiseMax(Eigen::Vector2d::Zero()) + Eigen::Vector2d::Constant(kMargin);
      } else if (course.goal_NE != Eigen::Vector2d(kLength, 0)) {
        throw std::invalid_argument("the generated corridor's goal is its far end (60,0): --to is for --scene");
      }
    }
    if (seeds_text.empty())
      seeds_text = course.scene_path.empty() ? "1-3" : course.scene.contains("seed") ? course.scene["seed"].dump() : "1";
    int a = -1, b = -1, used = 0;
    const int read = std::sscanf(seeds_text.c_str(), "%d%n-%d%n", &a, &used, &b, &used);
    if (read == 1) b = a;
    if (read < 1 || used != static_cast<int>(seeds_text.size()) || a < 0 || b < a || b - a > 10000)
      throw std::invalid_argument("--seeds must be A-B with 0 <= A <= B (or one seed), not '" + seeds_text + "'");
    uav::ParameterSet params = uav::ParameterSet::LoadFile(params_path, uav::VehicleParameterSchema());
    params = params.With("avd_enable", 1).With("ctl_speed_max_xy", speed);
    if (wire_rig_roll != 0.0) course.wire_rig_roll_deg = wire_rig_roll, params = params.With("pwl_rig", 1);
    for (const auto& o : overrides) params = params.WithAssignment(o);
    if (!picture_dir.empty()) std::filesystem::create_directories(picture_dir);
    if (!trace_dir.empty()) std::filesystem::create_directories(trace_dir);
    if (jobs > 1 || !slurm_dir.empty()) {
      // Every process repeats this command line but for how and where to run, its seeds and its
      // results file.
      const std::vector<std::string> repeated = uav::simflight::RepeatedArguments(
          argc, argv, {"--jobs", "--slurm", "--seeds-per-task", "--sbatch", "--seeds", "--json"}, {"--wait", "--quiet"});
      const uav::simflight::SeedRange seeds{a, b};
      std::vector<std::string> parts;
      std::string temporary;  // the local processes' results folder
      if (!slurm_dir.empty()) {
        uav::simflight::SlurmArray array;
        array.dir = std::filesystem::absolute(slurm_dir).string();
        array.seeds = seeds;
        array.seeds_per_task = seeds_per_task;
        const std::string job = uav::simflight::SubmitSlurmArray(array, uav::simflight::ThisExecutable(), repeated, sbatch_options, wait);
        std::fprintf(stderr, "uav-avoid-bench: job array %s: %d task(s) of up to %d seeds (%d-%d), results in %s/task_K.json\n",
                     job.c_str(), array.tasks(), seeds_per_task, a, b, array.dir.c_str());
        if (!wait) {
          std::printf("{\"job\": \"%s\", \"tasks\": %d, \"merge\": \"uav-avoid-bench --merge %s/task_*.json\"}\n", job.c_str(),
                      array.tasks(), array.dir.c_str());
          return 0;
        }
        const std::vector<std::string> missing = uav::simflight::MissingTasks(array);
        if (!missing.empty()) {
          std::string text;
          for (const std::string& m : missing) text += "\n  " + m;
          throw std::runtime_error(std::to_string(missing.size()) + " of " + std::to_string(array.tasks()) +
                                   " task(s) did not fly all their seeds (the others' results are in " + array.dir + "):" + text);
        }
        for (int k = 0; k < array.tasks(); ++k) parts.push_back(array.ResultFile(k));
      } else {
        char pattern[] = "/tmp/uav-avoid-bench-XXXXXX";
        if (!mkdtemp(pattern)) throw std::runtime_error("cannot make a folder for the seeds' results in /tmp");
        const std::string dir = pattern;
        int finished = 0;
        try {
          parts = uav::simflight::RunSeedsLocally(uav::simflight::ThisExecutable(), repeated, seeds, jobs, dir, 1, [&](int seed, int code) {
            ++finished;
            if (!quiet)
              std::fprintf(stderr, "seed %d: %s (%d of %d flown)\n", seed, code == 0 ? "success" : code == 1 ? "failed" : "error",
                           finished, seeds.count());
          });
        } catch (...) {
          std::filesystem::remove_all(dir);
          throw;
        }
        temporary = dir;
      }
      // One cell, as one process flying them all would have written it (the pooled planning-time
      // percentiles aside: each process keeps only its own flights' p50 and p99).
      std::vector<FlightResult> results;
      nlohmann::json out = Merge(parts, &results);
      if (!temporary.empty()) {
        out.erase("merged_from");
        std::filesystem::remove_all(temporary);
      }
      out["cell"] = Cell(results, speed);
      if (!json_path.empty()) uav::WriteFileAtomically(json_path, out.dump(2) + "\n");
      std::printf("%s\n", out["cell"].dump(2).c_str());
      return out["cell"]["failed_seeds"].empty() ? 0 : 1;
    }
    nlohmann::json out = {{"density", course.density}, {"scene", scene_path}, {"goal_ne_m", {course.goal_NE.x(), course.goal_NE.y()}},
                          {"altitude_m", course.altitude_m}, {"speed", speed}, {"rig_roll_deg", rig_roll}, {"wire_rig_roll_deg", wire_rig_roll}, {"flights", nlohmann::json::array()}};
    std::vector<FlightResult> results;
    for (int seed = a; seed <= b; ++seed) {
      FlightResult r = Fly(params, course, seed, speed, !quiet);
      if (!quiet)
        std::fprintf(stderr,
                     "seed %d: %s, clearance min %.2f p5 %.2f m, path %.1f m (shortest %s), %.1f m/s, reversals %d, stops %d, "
                     "wires passed %zu (least clearance %.2f m; least across the corridor %.2f m), replan p50 %.2f p99 %.2f ms, "
                     "navigation error moves %.2f m in 3 s (%.2f m in the map's odometry frame)\n",
                     seed, r.success ? "success" : r.why.c_str(), r.min_clearance, r.clearance_p5, r.path_m,
                     ShortestText(r.shortest_m).c_str(), r.mean_speed, r.reversals, r.stops_over_3s, r.wire_clearances.size(),
                     r.wire_clearances.empty() ? NAN : *std::min_element(r.wire_clearances.begin(), r.wire_clearances.end()),
                     LeastAcross(r),
                     Percentile(r.replan_ms, 0.5), Percentile(r.replan_ms, 0.99), r.error_drift_3s_N, r.error_drift_3s_O);
      if (!picture_dir.empty()) Picture(picture_dir + "/field_" + std::to_string(seed) + ".png", r, course);
      if (!trace_dir.empty())
        uav::WriteFileAtomically(trace_dir + "/trace_" + std::to_string(seed) + ".csv",
                                 "t_s,n_m,e_m,alt_m,est_n_m,est_e_m,est_alt_m,speed_mps,yaw_deg,pitch_deg,roll_deg,course_deg,climb_mps,clearance_m,nearest_id,perceived_range_m,"
                                 "perceived_wire_m,avoid_state,"
                                 "speed_limit_mps,path_points,reason,path_N\n" + r.trace.str());
      out["flights"].push_back({{"seed", seed}, {"success", r.success}, {"reached", r.reached}, {"why", r.why}, {"min_clearance_m", r.min_clearance},
                                {"closest_ne_m", {r.closest_N.x(), r.closest_N.y()}}, {"closest_s", r.closest_t},
                                {"clearance_p5_m", r.clearance_p5}, {"path_m", r.path_m}, {"shortest_m", r.shortest_m},
                                {"mean_speed", r.mean_speed}, {"replan_p50_ms", Percentile(r.replan_ms, 0.5)},
                                {"replan_p99_ms", Percentile(r.replan_ms, 0.99)},
                                {"replan_cpu_p50_ms", Percentile(r.replan_cpu_ms, 0.5)},
                                {"replan_cpu_p99_ms", r.replan_cpu_p99_ms}, {"reversals", r.reversals},
                                {"obstacles_passed", r.obstacles_passed}, {"stops_over_3s", r.stops_over_3s},
                                {"wire_clearances_m", r.wire_clearances}, {"wire_angles_deg", r.wire_angles_deg},
                                {"nav_error_drift_3s_N_m", r.error_drift_3s_N}, {"nav_error_drift_3s_O_m", r.error_drift_3s_O},
                                {"flown_s", r.flown_s}, {"time_lost_s", TimeLostJson(r.lost)}});
      results.push_back(std::move(r));
      // Written after every flight: a long run stopped early keeps what it flew.
      out["cell"] = Cell(results, speed);
      if (!json_path.empty()) uav::WriteFileAtomically(json_path, out.dump(2) + "\n");
    }
    const std::string text = out["cell"].dump(2);
    std::printf("%s\n", text.c_str());
    const int successes = static_cast<int>(std::count_if(results.begin(), results.end(), [](const FlightResult& r) { return r.success; }));
    return successes == static_cast<int>(results.size()) ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-avoid-bench: %s\n", e.what());
    return 2;
  }
}
