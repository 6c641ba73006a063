// Obstacle avoidance's planning cycle, part by part, on a map as the vehicle builds it in a pole
// field: 30 forward stereo scans' worth of rays (6000 each, to 15 m) and 40 cylinders. The
// whole cycle (window, distance field, plan, checks) must fit the 10 Hz replanning rate with
// room: the target is a p99 under 10 ms.
#include <random>

#include <benchmark/benchmark.h>

#include "uav/avoid/avoidance.hpp"
#include "uav/avoid/local_grid.hpp"
#include "uav/avoid/path_planner.hpp"

namespace {

using namespace uav::avoid;

struct Field {
  AvoidanceParams params;
  std::unique_ptr<AvoidancePlanner> planner;
  Field() {
    params.enabled = true;
    planner = std::make_unique<AvoidancePlanner>(params);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(0, 1);
    std::vector<MapCylinder> poles;
    for (int i = 0; i < 40; ++i) poles.push_back({{4 + 40 * U(rng), -10 + 20 * U(rng)}, -8, 0, 0.2 + 0.4 * U(rng)});
    for (int k = 0; k < 30; ++k) {
      // A scan from (k * 0.3, 0, -4) looking north, 60 x 45 degrees: rays end on the nearest pole
      // or at 20 m (beyond the trusted 15 m: they clear only).
      PerceptionUpdate u;
      u.utime = k;
      RangeScan s;
      s.origin_N = {k * 0.3, 0, -4};
      s.max_range_m = 15;
      for (int i = 0; i < 6000; ++i) {
        const double az = (U(rng) - 0.5) * 1.05, el = (U(rng) - 0.5) * 0.78;
        const Eigen::Vector3d dir(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), -std::sin(el));
        double t_hit = 20.0;
        for (const auto& p : poles) {
          const Eigen::Vector2d o = s.origin_N.head<2>() - p.p_NE;
          const Eigen::Vector2d d = dir.head<2>();
          const double a = d.squaredNorm(), b = 2 * o.dot(d), c = o.squaredNorm() - p.radius_m * p.radius_m;
          const double disc = b * b - 4 * a * c;
          if (disc > 0) {
            const double t = (-b - std::sqrt(disc)) / (2 * a);
            if (t > 0 && t < t_hit) t_hit = t;
          }
        }
        s.p_N.push_back((s.origin_N + t_hit * dir).cast<float>());
      }
      u.scan = s;
      planner->Add(u, s.origin_N);
    }
    PerceptionUpdate u;
    u.utime = 30;
    u.cylinders = poles;
    planner->Add(u, {9, 0, -4});
  }
};

Field& TheField() {
  static Field f;
  return f;
}

void BM_Scan(benchmark::State& state) {
  Field f;  // its own: the scans it adds would change the field the other benchmarks plan on
  PerceptionUpdate u;
  RangeScan s;
  s.origin_N = {9, 0, -4};
  s.max_range_m = 15;
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(0, 1);
  for (int i = 0; i < 6000; ++i) s.p_N.emplace_back(9 + 15 * U(rng), -8 + 16 * U(rng), -1 - 6 * U(rng));
  u.scan = s;
  for (auto _ : state) f.planner->Add(u, s.origin_N);
}
BENCHMARK(BM_Scan)->Unit(benchmark::kMillisecond);

void BM_Window(benchmark::State& state) {
  Field& f = TheField();
  for (auto _ : state) {
    LocalGrid g = LocalGrid::FromMap(f.planner->map(), {17, 0, -4}, {16, 16, 4}, 0.4);
    benchmark::DoNotOptimize(g);
  }
}
BENCHMARK(BM_Window)->Unit(benchmark::kMillisecond);

void BM_DistanceField(benchmark::State& state) {
  Field& f = TheField();
  LocalGrid g = LocalGrid::FromMap(f.planner->map(), {17, 0, -4}, {16, 16, 4}, 0.4);
  for (auto _ : state) g.ComputeDistances();
}
BENCHMARK(BM_DistanceField)->Unit(benchmark::kMillisecond);

// The planner's copy of the map (as the planner sizes it for 16 m windows) moved along with the
// vehicle by 2 m, as the planner moves it: the slab it newly covers (in the field, from x = 29 m
// on) is read from the tree.
void BM_Recentre(benchmark::State& state) {
  Field& f = TheField();
  LocalGrid copy = LocalGrid::FromMap(f.planner->map(), {3, 0, -4}, {26.4, 26.4, 6.4}, 0.4, /*distances=*/false);
  bool there = false;
  for (auto _ : state) {
    there = !there;
    copy.Recentre(f.planner->map(), {there ? 5.0 : 3.0, 0, -4});
  }
}
BENCHMARK(BM_Recentre)->Unit(benchmark::kMillisecond);

void BM_PlanPath(benchmark::State& state) {
  Field& f = TheField();
  const LocalGrid g = LocalGrid::FromMap(f.planner->map(), {17, 0, -4}, {16, 16, 4}, 0.4);
  PlannerParams p;
  p.floor_down_m = -1.5;
  PlannerScratch scratch;  // kept between plans, as the planner keeps it
  for (auto _ : state) benchmark::DoNotOptimize(PlanPath(g, {9, 0, -4}, {60, 0, -4}, p, &scratch));
}
BENCHMARK(BM_PlanPath)->Unit(benchmark::kMillisecond);

// The replanning's worst cycles in the dense fields: the way ahead blocked across most of the
// window, so the search spreads through the (mostly unknown) window before it finds the way
// round. A wall of known cells across x = 20 m, from y = -13 to 13 m and 2 to 6 m up, on the field.
void BM_PlanPathAroundAWall(benchmark::State& state) {
  Field& f = TheField();
  LocalGrid g = LocalGrid::FromMap(f.planner->map(), {17, 0, -4}, {16, 16, 4}, 0.4, /*distances=*/false);
  for (double y = -13; y <= 13; y += 0.2)
    for (double z = -6; z <= -2; z += 0.2) g.SetAt({20, y, z}, Cell::kOccupied);
  g.ComputeDistances();
  PlannerParams p;
  p.floor_down_m = -1.5;
  PlannerScratch scratch;
  int expansions = 0;
  for (auto _ : state) {
    const PlannedPath path = PlanPath(g, {9, 0, -4}, {60, 0, -4}, p, &scratch);
    expansions = path.expansions;
    benchmark::DoNotOptimize(path);
  }
  state.counters["expansions"] = expansions;
}
BENCHMARK(BM_PlanPathAroundAWall)->Unit(benchmark::kMillisecond);

void BM_ReplanCycle(benchmark::State& state) {
  Field& f = TheField();
  int64_t t = 0;
  for (auto _ : state) benchmark::DoNotOptimize(f.planner->Plan(++t, {9, 0, -4}, {60, 0, -4}, {60, 0, -4}));
}
BENCHMARK(BM_ReplanCycle)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
