// Obstacle avoidance's parts against exact ground truth: the 3-D map (free, occupied, unknown,
// insertion at the capture pose, the memory bound, the .bt file), the distance field against
// brute force, the planner on fixed fields (a gap, a dead end, an enclosed goal, hysteresis),
// and the safety layer's braking distance and stale-data stop.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <gtest/gtest.h>

#include "uav/avoid/avoidance.hpp"
#include "uav/avoid/depth_grid_scan.hpp"
#include "uav/avoid/local_grid.hpp"
#include "uav/avoid/occupancy_map.hpp"
#include "uav/avoid/path_planner.hpp"
#include "uav/avoid/safety_layer.hpp"

namespace uav::avoid {
namespace {

// A wall of points at north = d, east in [-w, w], down in [-h, 0] seen from the origin.
RangeScan WallScan(const Eigen::Vector3d& origin, double d, double w, double h, double step = 0.1) {
  RangeScan s;
  s.origin_N = origin;
  s.max_range_m = 30;
  for (double e = -w; e <= w; e += step)
    for (double down = -h; down <= 0; down += step) s.p_N.emplace_back(float(d), float(e), float(down));
  return s;
}

TEST(OccupancyMap, RaysClearFreeSpaceMarkTheirEndsAndLeaveTheRestUnknown) {
  OccupancyMap map;
  map.InsertScan(WallScan({0, 0, -2}, 6.0, 2.0, 4.0));
  EXPECT_EQ(map.At({6.0, 0, -2}), Cell::kUnknown) << "one hit is not yet an obstacle (a stereo outlier)";
  EXPECT_EQ(map.At({3.0, 0, -2}), Cell::kFree);
  map.InsertScan(WallScan({0, 0, -2}, 6.0, 2.0, 4.0));
  EXPECT_EQ(map.At({6.0, 0, -2}), Cell::kOccupied) << "seen twice";
  EXPECT_EQ(map.At({1.0, 0.2, -2}), Cell::kFree);
  EXPECT_EQ(map.At({8.0, 0, -2}), Cell::kUnknown) << "behind the wall: never seen";
  EXPECT_EQ(map.At({-3.0, 0, -2}), Cell::kUnknown) << "behind the camera";
  EXPECT_EQ(map.At({3.0, 6.0, -2}), Cell::kUnknown) << "outside the field of view";
  EXPECT_EQ(map.At({std::nan(""), 0, 0}), Cell::kUnknown);
}

TEST(OccupancyMap, PointsBeyondTheTrustedRangeOnlyClear) {
  OccupancyMap map;
  RangeScan s = WallScan({0, 0, -2}, 12.0, 1.0, 3.0);
  s.max_range_m = 8.0;
  map.InsertScan(s);
  EXPECT_EQ(map.At({5.0, 0, -2}), Cell::kFree);
  EXPECT_EQ(map.At({12.0, 0, -2}), Cell::kUnknown) << "a point past the range gate is not an obstacle";
}

TEST(OccupancyMap, AScanLandsWhereItWasTakenWhateverTheOrderItArrivesIn) {
  // Two scans from two poses, inserted late and out of order: the same map as in order.
  const RangeScan a = WallScan({0, 0, -2}, 6.0, 1.0, 3.0), b = WallScan({3, 0, -2}, 9.0, 1.0, 3.0);
  OccupancyMap in_order, reversed;
  in_order.InsertScan(a);
  in_order.InsertScan(b);
  reversed.InsertScan(b);
  reversed.InsertScan(a);
  for (double n = -1; n < 10; n += 0.2)
    for (double e = -2; e < 2; e += 0.2) ASSERT_EQ(in_order.At({n, e, -2}), reversed.At({n, e, -2})) << n << " " << e;
}

TEST(OccupancyMap, CylindersAndWiresMarkTheCellsTheyCover) {
  OccupancyMap map;
  for (int i = 0; i < 2; ++i) {
    map.InsertCylinder({5, 1}, -6.0, 0.0, 0.15);  // a pole thinner than a cell
    map.InsertPolyline({{0, -5, -4}, {0, 5, -4}}, 0.05);
  }
  EXPECT_EQ(map.At({5, 1, -3}), Cell::kOccupied);
  EXPECT_EQ(map.At({5, 2, -3}), Cell::kUnknown);
  EXPECT_EQ(map.At({0, 0, -4}), Cell::kOccupied);
  EXPECT_EQ(map.At({0, 3.3, -4}), Cell::kOccupied);
  EXPECT_EQ(map.At({0, 0, -5}), Cell::kUnknown);
}

// The vehicle keeps its map in the odometry frame: a result and a plan cross frames whole (every
// point of the scan, its origin, the cylinders with their heights, the wires, the path, the goal).
TEST(AvoidanceFrames, AResultAndAPlanAreMovedWhole) {
  const Eigen::Vector3d d(1.5, -2.0, 0.25);
  avoid::PerceptionUpdate u;
  u.scan = avoid::RangeScan{7, {1, 2, -3}, {{4.f, 5.f, -3.f}}, 10.0};
  u.cylinders.push_back({{3, 4}, -5.0, 0.0, 0.3});
  u.wires.push_back({{{0, 0, -4}, {1, 0, -4}}, 0.2});
  const avoid::PerceptionUpdate m = avoid::Translated(u, d);
  EXPECT_TRUE(m.scan->origin_N.isApprox(Eigen::Vector3d(2.5, 0, -2.75)));
  EXPECT_TRUE(m.scan->p_N[0].isApprox(Eigen::Vector3f(5.5f, 3.f, -2.75f)));
  EXPECT_TRUE(m.cylinders[0].p_NE.isApprox(Eigen::Vector2d(4.5, 2)));
  EXPECT_DOUBLE_EQ(m.cylinders[0].top_down_m, -4.75);
  EXPECT_DOUBLE_EQ(m.cylinders[0].bottom_down_m, 0.25);
  EXPECT_DOUBLE_EQ(m.cylinders[0].radius_m, 0.3);
  EXPECT_TRUE(m.wires[0].p_N[1].isApprox(Eigen::Vector3d(2.5, -2, -3.75)));
  avoid::AvoidancePlan plan;
  plan.goal_N = {10, 0, -4};
  plan.path_N = {{0, 0, -4}, {10, 0, -4}};
  const avoid::AvoidancePlan back = avoid::Translated(avoid::Translated(plan, d), -d);
  EXPECT_TRUE(back.goal_N.isApprox(plan.goal_N));
  EXPECT_TRUE(avoid::Translated(plan, d).path_N[1].isApprox(Eigen::Vector3d(11.5, -2, -3.75)));
}

TEST(OccupancyMap, TheMemoryBoundDropsTheFarthestCellsFirst) {
  MapParams p;
  p.max_cells = 5000;
  OccupancyMap map(p);
  for (int i = 0; i < 100; ++i)
    for (int j = 0; j < 100; ++j) map.Mark({i * 0.4, j * 0.4, -2}, true);
  ASSERT_GT(map.cells(), 5000u);
  EXPECT_GT(map.EnforceBound({0, 0, -2}), 0u);
  EXPECT_LE(map.cells(), 5000u);
  EXPECT_EQ(map.At({0.4, 0.4, -2}), Cell::kOccupied) << "near the vehicle: kept";
  EXPECT_EQ(map.At({39.6, 39.6, -2}), Cell::kUnknown) << "farthest: dropped";
  EXPECT_EQ(map.EnforceBound({0, 0, -2}), 0u) << "within the bound: nothing more goes";
}

TEST(OccupancyMap, SavesAnOctoMapFileThatReadsBackAndNeverAHalfFile) {
  OccupancyMap map;
  map.InsertScan(WallScan({0, 0, -2}, 6.0, 2.0, 4.0));
  map.InsertScan(WallScan({0, 0, -2}, 6.0, 2.0, 4.0));
  const std::string dir = ::testing::TempDir() + "/avoid_map";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/map.bt";
  ASSERT_EQ(map.SaveBinary(path), "");
  const OccupancyMap back = OccupancyMap::LoadBinary(path);
  EXPECT_EQ(back.At({6.0, 0, -2}), Cell::kOccupied);
  EXPECT_EQ(back.At({3.0, 0, -2}), Cell::kFree);
  EXPECT_EQ(back.At({8.0, 0, -2}), Cell::kUnknown);
  EXPECT_NE(map.SaveBinary("/nonexistent_dir/map.bt"), "");
  EXPECT_FALSE(std::filesystem::exists("/nonexistent_dir/map.bt.part"));
  EXPECT_THROW(OccupancyMap::LoadBinary(dir + "/missing.bt"), std::runtime_error);
}

// Depth from motion's grid into the map: a trusted cell is a ray to its depth through the cell's
// centre, placed with the camera's pose; cells without enough agreeing features are left out.
TEST(DepthGridScan, ATrustedCellIsARayToItsDepthAndDoubtfulCellsAreLeftOut) {
  CameraIntrinsics k;  // 640 x 480, f 500, no distortion
  DepthGrid g;
  g.healthy = true;
  g.cols = 4, g.rows = 3;
  g.cells.resize(12);
  g.obstacle_depth_m = 10.0;
  g.cells[5] = {CellState::kObstacle, 8.0, 0.4, 12, 0.9, ""};   // row 1, col 1: trusted
  g.cells[6] = {CellState::kObstacle, 8.0, 2.0, 12, 0.2, ""};   // features disagree: left out
  g.cells[7] = {CellState::kFree, 30.0, 1.0, 2, 0.3, ""};       // too few features: left out
  // A camera 4 m up looking north (optical z along N, x along E, y down).
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  T_NC.translation() = Eigen::Vector3d(0, 0, -4);
  const RangeScan scan = DepthGridScan(g, k, T_NC);
  ASSERT_EQ(scan.p_N.size(), 1u);
  EXPECT_EQ(scan.max_range_m, 10.0);
  // Cell (1, 1): centre pixel (239.5, 239.5) is 80 px left of the principal point: 8 m * 80 / 500 west.
  EXPECT_NEAR(scan.p_N[0].x(), 8.0, 1e-4);
  EXPECT_NEAR(scan.p_N[0].y(), -8.0 * 80.0 / 500.0, 1e-4);
  EXPECT_NEAR(scan.p_N[0].z(), -4.0, 1e-4);
  g.healthy = false;
  EXPECT_TRUE(DepthGridScan(g, k, T_NC).p_N.empty());
  // Into the map: the cell at the depth occupied after two frames, the way to it free.
  OccupancyMap map;
  g.healthy = true;
  map.InsertScan(DepthGridScan(g, k, T_NC));
  map.InsertScan(DepthGridScan(g, k, T_NC));
  EXPECT_EQ(map.At(Eigen::Vector3d(8.0, -1.28, -4.0)), Cell::kOccupied);
  EXPECT_EQ(map.At(Eigen::Vector3d(4.0, -0.64, -4.0)), Cell::kFree);
}

// Dense and sparse (most rows and columns without an obstacle, which the transform skips), and
// empty (every cell "none").
TEST(LocalGrid, DistanceFieldMatchesBruteForce) {
  struct Case {
    Eigen::Vector3i size;
    int obstacles;
  };
  for (const Case& k : {Case{{23, 17, 9}, 25}, Case{{41, 30, 12}, 3}, Case{{9, 8, 7}, 0}}) {
    LocalGrid g(Eigen::Vector3d::Zero(), k.size, 0.5);
    std::mt19937 rng(3);
    std::vector<Eigen::Vector3i> occupied;
    for (int i = 0; i < k.obstacles; ++i) {
      const Eigen::Vector3i c(rng() % k.size.x(), rng() % k.size.y(), rng() % k.size.z());
      g.Set(c, Cell::kOccupied);
      occupied.push_back(c);
    }
    g.ComputeDistances();
    for (int z = 0; z < k.size.z(); ++z)
      for (int y = 0; y < k.size.y(); ++y)
        for (int x = 0; x < k.size.x(); ++x) {
          double best = LocalGrid::kFar;
          for (const auto& o : occupied) best = std::min(best, (o - Eigen::Vector3i(x, y, z)).cast<double>().norm() * 0.5);
          ASSERT_NEAR(g.Distance({x, y, z}), best, 1e-4) << x << " " << y << " " << z << " of " << k.size.transpose();
        }
  }
}

// The planner's copy of the map moves with the vehicle by reading only the slab it newly covers:
// moved any way (back, sideways, up, several slabs at once), it is the copy read whole.
TEST(LocalGrid, ARecentredCopyIsTheCopyReadAnew) {
  OccupancyMap map;
  for (int i = 0; i < 2; ++i) {
    map.InsertScan(WallScan({0, 0, -2}, 6.0, 3.0, 4.0));
    map.InsertScan(WallScan({4, 5, -3}, 12.0, 2.0, 3.0));
    map.InsertCylinder({3, -4}, -5, 0, 0.4);
  }
  const Eigen::Vector3d half(6, 6, 2);
  const LocalGrid start = LocalGrid::FromMap(map, {2, 0, -2}, half, 0.4, false);
  int occupied = 0, free = 0;
  for (const Eigen::Vector3d& to : {Eigen::Vector3d(5.3, 0, -2), Eigen::Vector3d(-1.1, 2.7, -2.5), Eigen::Vector3d(9, -4, -1.2),
                                    Eigen::Vector3d(40, 0, -2)}) {
    LocalGrid moved = start;
    moved.Recentre(map, to);
    const LocalGrid fresh = LocalGrid::FromMap(map, to, half, 0.4, false);
    ASSERT_EQ(moved.size(), fresh.size());
    ASSERT_TRUE(moved.min_N().isApprox(fresh.min_N()));
    for (int z = 0; z < fresh.size().z(); ++z)
      for (int y = 0; y < fresh.size().y(); ++y)
        for (int x = 0; x < fresh.size().x(); ++x) {
          ASSERT_EQ(moved.State({x, y, z}), fresh.State({x, y, z})) << to.transpose() << ": " << x << " " << y << " " << z;
          occupied += fresh.State({x, y, z}) == Cell::kOccupied;
          free += fresh.State({x, y, z}) == Cell::kFree;
        }
  }
  EXPECT_GT(occupied, 100) << "the cases have walls to copy";
  EXPECT_GT(free, 1000);
}

// Blind, the vehicle returns the way it flew, at the altitude it flies: the only space seen free
// is one layer of planning cells (3.6-4.0 m up) along its way, and it flies 3.9 m up, off that
// layer's centre.
TEST(AvoidancePlanner, OnTheMapAloneReturnsThroughTheOneLayerSeenFree) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  for (int n = 0; n < 110; ++n)  // north -1..21, east -2.4..2.4, down -3.9 and -3.7 (leaf centres)
    for (int e = 0; e < 24; ++e)
      for (double d : {-3.9, -3.7}) planner.map().Mark({-0.9 + 0.2 * n, -2.3 + 0.2 * e, d}, false);
  PerceptionUpdate u;
  u.utime = 1'000'000;
  planner.Add(u, {18.4, -0.7, -3.9});
  const AvoidancePlan home = planner.Plan(5'000'000, {18.4, -0.7, -3.9}, {0, 0, -3.9}, {0, 0, -3.9}, /*map_only=*/true);
  ASSERT_NE(home.state, AvoidState::kNoPath) << home.reason;
  EXPECT_NEAR(home.seen_free_m, Length(home.path_N), 0.5);
}

// The way the vehicle has flown is free space in the planning grid: its body was there (the
// return on the map alone flies it back).
TEST(OccupancyMap, TheWayTheBodyFlewIsFreeInThePlanningGrid) {
  OccupancyMap map;
  for (double n = 0; n <= 20; n += 0.3) map.InsertBody({n, 0.37 * std::sin(n), -3.93}, 0.5, 0.5);
  const LocalGrid grid = LocalGrid::FromMap(map, {10, 0, -4}, {12, 4, 2}, 0.4, false);
  for (double n = 0; n <= 20; n += 0.1) {
    const Eigen::Vector3d p(n, 0.37 * std::sin(n), -3.93);
    EXPECT_EQ(grid.StateAt(p), Cell::kFree) << p.transpose();
  }
}

// An obstacle the body is touching stays in the map however long the vehicle stays beside it:
// the body's misses clear only what was unknown (a 0.15 m pole 0.4 m from the vehicle's centre,
// fifty planning cycles, stays occupied; before, the body erased it and the layer flew into it).
// The cells within one cell of the vehicle's centre are free whatever was seen there.
TEST(OccupancyMap, TheBodyClearsWhatWasUnknownButNotAnObstacleItTouches) {
  OccupancyMap map;
  map.InsertCylinder({5.4, 0}, -6.0, 0.0, 0.15);
  map.InsertCylinder({5.4, 0}, -6.0, 0.0, 0.15);
  map.Mark({5, 0, -4}, true);  // a phantom in the centre cell
  const Eigen::Vector3d p_N(5, 0, -4);
  for (int i = 0; i < 50; ++i) map.InsertBody(p_N, 0.5, 0.5);
  EXPECT_EQ(map.At({5.3, 0.1, -3.9}), Cell::kOccupied);  // a pole cell 0.33 m from the centre
  EXPECT_EQ(map.At(p_N), Cell::kFree);
  EXPECT_EQ(map.At({4.7, 0.1, -3.9}), Cell::kFree);  // unknown before, within the body
  EXPECT_EQ(map.At({5, 0.3, -4}), Cell::kFree);
  EXPECT_EQ(map.At({5, 0, -4.9}), Cell::kUnknown);  // beyond the body
}

// The body is a flat disc, not a ball: across the ground it clears its whole radius, up and down
// only its height. As a ball it cleared 0.4 m below the vehicle, which each replanning of a
// descent counted as seen free: 1/12 seed 3 came down onto a wall top no camera had seen.
TEST(OccupancyMap, TheBodyClearsAFlatDiscNotTheSpaceBelowIt) {
  OccupancyMap map;  // 0.2 m cells, centres at odd tenths
  const Eigen::Vector3d p_N(5.1, 0.1, -3.9);
  map.InsertBody(p_N, 0.5, 0.5);
  EXPECT_EQ(map.At(p_N), Cell::kFree);
  EXPECT_EQ(map.At({5.1, 0.5, -3.9}), Cell::kFree);    // 0.4 m beside
  EXPECT_EQ(map.At({5.1, 0.5, -3.7}), Cell::kFree);    // beside and 0.2 m below, within the disc
  EXPECT_EQ(map.At({5.1, 0.1, -3.7}), Cell::kFree);    // the next cell down: within one cell
  EXPECT_EQ(map.At({5.1, 0.1, -3.5}), Cell::kUnknown);  // 0.4 m below: within a ball, not the disc
  EXPECT_EQ(map.At({5.1, 0.1, -4.3}), Cell::kUnknown);  // 0.4 m above
  // Descending 1 m in 0.1 m steps clears the column it passed through and nothing below it.
  for (double d = -3.9; d <= -2.9 + 1e-9; d += 0.1) map.InsertBody({5.1, 0.1, d}, 0.5, 0.5);
  EXPECT_EQ(map.At({5.1, 0.1, -2.7}), Cell::kFree);
  EXPECT_EQ(map.At({5.1, 0.1, -2.3}), Cell::kUnknown);
}

// A window with everything observed free but the boxes given (cells whose centre is inside).
LocalGrid Field(const std::vector<std::pair<Eigen::Vector3d, Eigen::Vector3d>>& boxes) {
  LocalGrid g(Eigen::Vector3d(-2, -12, -8), Eigen::Vector3i(80, 60, 20), 0.4);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 80; ++x) {
        const Eigen::Vector3d c = g.Centre({x, y, z});
        Cell s = Cell::kFree;
        for (const auto& [lo, hi] : boxes)
          if ((c.array() >= lo.array()).all() && (c.array() <= hi.array()).all()) s = Cell::kOccupied;
        g.Set({x, y, z}, s);
      }
  g.ComputeDistances();
  return g;
}

double MinDistance(const LocalGrid& g, const std::vector<Eigen::Vector3d>& path) {
  double best = 1e9;
  for (std::size_t i = 0; i + 1 < path.size(); ++i)
    for (double t = 0; t <= 1.0; t += 0.01) best = std::min<double>(best, g.DistanceAt(path[i] + t * (path[i + 1] - path[i])));
  return best;
}

PlannerParams Planner() {
  PlannerParams p;
  p.clearance_m = 1.0;
  p.floor_down_m = -1.5;
  p.ceiling_down_m = -7.0;
  return p;
}

TEST(PathPlanner, GoesThroughTheGapInAWallWithItsClearance) {
  // A wall across the way at north 10-11 from east -12 to 12, a 4 m gap at east 4..8.
  const LocalGrid g = Field({{{10, -12, -8}, {11, 4, 0}}, {{10, 8, -8}, {11, 12, 0}}});
  const PlannedPath p = PlanPath(g, {0, 0, -4}, {20, 0, -4}, Planner());
  ASSERT_TRUE(p.found) << p.reason;
  EXPECT_TRUE(p.reaches_goal);
  EXPECT_GE(MinDistance(g, p.p_N), 1.0);
  bool through_gap = false;
  for (std::size_t i = 0; i + 1 < p.p_N.size(); ++i)
    for (double t = 0; t <= 1; t += 0.01) {
      const Eigen::Vector3d q = p.p_N[i] + t * (p.p_N[i + 1] - p.p_N[i]);
      if (q.x() > 10 && q.x() < 11 && q.y() > 4 && q.y() < 8) through_gap = true;
    }
  EXPECT_TRUE(through_gap);
  // Shortest way: up to the gap and back, about 2 * hypot(10.5, 6) = 24.2 m, not much more.
  double length = 0;
  for (std::size_t i = 0; i + 1 < p.p_N.size(); ++i) length += (p.p_N[i + 1] - p.p_N[i]).norm();
  EXPECT_LT(length, 24.2 * 1.1);
  EXPECT_LT(p.p_N.size(), 8u) << "line of sight leaves a few waypoints";
}

TEST(PathPlanner, LeavesAUShapedDeadEndTheWayItCame) {
  // A U open toward the start: the straight way runs into its bottom.
  const LocalGrid g = Field({{{8, -4, -8}, {9, 4, 0}}, {{2, -4, -8}, {9, -3, 0}}, {{2, 3, -8}, {9, 4, 0}}});
  const PlannedPath p = PlanPath(g, {4, 0, -4}, {20, 0, -4}, Planner());
  ASSERT_TRUE(p.found) << p.reason;
  EXPECT_GE(MinDistance(g, p.p_N), 1.0);
  EXPECT_TRUE(p.reaches_goal);
  bool left_the_u = false;
  for (const auto& q : p.p_N) left_the_u |= q.x() < 2.0 || std::abs(q.y()) > 4.0;
  EXPECT_TRUE(left_the_u);
}

TEST(PathPlanner, SaysWhyWhenThereIsNoWayOrTheGoalIsInAnObstacle) {
  // A closed box around the goal.
  const LocalGrid boxed = Field({{{14, -5, -8}, {15, 5, 0}}, {{25, -5, -8}, {26, 5, 0}},
                                 {{14, -5, -8}, {26, -4, 0}}, {{14, 4, -8}, {26, 5, 0}}, {{14, -5, -8}, {26, 5, -7}}});
  PlannerParams params = Planner();
  const PlannedPath none = PlanPath(boxed, {0, 0, -4}, {20, 0, -4}, params);
  EXPECT_FALSE(none.found);
  EXPECT_NE(none.reason.find("no path"), std::string::npos) << none.reason;
  const LocalGrid wall = Field({{{10, -12, -8}, {11, 12, 0}}});
  const PlannedPath inside = PlanPath(wall, {0, 0, -4}, {10.5, 0, -4}, params);
  EXPECT_FALSE(inside.found);
  EXPECT_NE(inside.reason.find("inside an obstacle"), std::string::npos) << inside.reason;
  EXPECT_FALSE(PlanPath(wall, {0, 0, -4}, {std::nan(""), 0, -4}, params).found);
}

// A goal nearer an obstacle than the clearance, but not in one (0.5 m in front of a wall, the
// clearance 1 m): the path goes as near it as the clearance lets it and says so; the vehicle
// does not hold short of it, as it did with the goal refused (7 m short, 1/25 field, seed 1).
TEST(PathPlanner, GoesAsNearAGoalBesideAnObstacleAsItsClearanceLets) {
  const LocalGrid wall = Field({{{10, -12, -8}, {11, 12, 0}}});
  const Eigen::Vector3d goal(9.4, 0, -4);
  const PlannedPath p = PlanPath(wall, {0, 0, -4}, goal, Planner());
  ASSERT_TRUE(p.found) << p.reason;
  EXPECT_FALSE(p.reaches_goal);
  EXPECT_TRUE(p.stops_short);
  EXPECT_NE(p.reason.find("from an obstacle"), std::string::npos) << p.reason;
  EXPECT_NE(p.reason.find("short of it"), std::string::npos) << p.reason;
  const Eigen::Vector3d end = p.p_N.back();
  // Kept the clearance (the wall's face is at north 10, its cells' centres from 10.2) ...
  EXPECT_GE(wall.DistanceAt(end), 1.0);
  EXPECT_LT(end.x(), 9.2);
  // ... and within it of the goal.
  EXPECT_LE((end - goal).norm(), 1.0 + 1e-9);
  for (std::size_t i = 0; i + 1 < p.p_N.size(); ++i) EXPECT_TRUE(SegmentClear(wall, p.p_N[i], p.p_N[i + 1], 1.0));
}

TEST(PathPlanner, FromInsideTheClearanceGoesStraightOutBeforeGoingOn) {
  // A long wall along the way (east 1.2..1.6) and the vehicle 0.6 m from it, inside the 1 m
  // clearance. The way out leads away from the wall, each step farther from it: never along it
  // at the distance it started from (each replan would start a little nearer and ratchet in).
  const LocalGrid g = Field({{{-2, 1.2, -8}, {30, 1.6, 0}}});
  const Eigen::Vector3d start(2, 0.6, -4);
  const PlannedPath p = PlanPath(g, start, {20, -1.5, -4}, Planner());
  ASSERT_TRUE(p.found) << p.reason;
  ASSERT_GE(p.p_N.size(), 2u);
  double before = g.DistanceAt(start);
  bool out = false;
  for (std::size_t i = 0; i + 1 < p.p_N.size() && !out; ++i)
    for (double t = 0.05; t <= 1.0 && !out; t += 0.05) {
      const Eigen::Vector3d q = p.p_N[i] + t * (p.p_N[i + 1] - p.p_N[i]);
      const double d = g.DistanceAt(q);
      EXPECT_GE(d, before - 1e-3) << "nearer the wall at " << q.transpose();
      before = std::max(before, d);
      out = d >= 1.0;
      // Out first, then on: it has gone less than a metre toward the goal when it is out.
      if (out) {
        EXPECT_LT(q.x() - start.x(), 1.0);
      }
    }
  EXPECT_TRUE(out);
  EXPECT_GE(MinDistance(g, {p.p_N.begin() + 1, p.p_N.end()}), 1.0);
}

TEST(PathPlanner, AWayBlockedAheadIsPassedRoundNotLeftThroughTheBackOfTheWindow) {
  // As flown in a field: a pocket seen free around the vehicle, a wide clump of obstacles 6 m
  // ahead (east -5..6), everything else unknown, the goal 60 m on beyond the window. Leaving
  // through the back border is 8 m away; round the clump costs more inside the window, but the
  // rest of the way from the back is 66 m, not 36 m.
  LocalGrid g(Eigen::Vector3d(-6.4, -16.4, -8.4), Eigen::Vector3i(80, 80, 20), 0.4);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 80; ++y)
      for (int x = 0; x < 80; ++x) {
        const Eigen::Vector3d c = g.Centre({x, y, z});
        if (c.x() > -1 && c.x() < 5 && std::abs(c.y()) < 4) g.Set({x, y, z}, Cell::kFree);
        if (c.x() > 6 && c.x() < 9 && c.y() > -5 && c.y() < 6) g.Set({x, y, z}, Cell::kOccupied);
      }
  g.ComputeDistances();
  const PlannedPath p = PlanPath(g, {1.6, -0.4, -4}, {60, 0, -4}, Planner());
  ASSERT_TRUE(p.found) << p.reason;
  EXPECT_FALSE(p.reaches_goal);
  EXPECT_GT(p.p_N.back().x(), 9.0) << "left the window at " << p.p_N.back().transpose();
  EXPECT_GE(MinDistance(g, p.p_N), 1.0);
}

TEST(PathPlanner, UnknownSpaceIsOpenAndSeenFreeLengthStopsAtIt) {
  LocalGrid g(Eigen::Vector3d(-2, -12, -8), Eigen::Vector3i(80, 60, 20), 0.4);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 60; ++y)
      for (int x = 0; x < 80; ++x)
        if (g.Centre({x, y, z}).x() < 8.0) g.Set({x, y, z}, Cell::kFree);
  g.ComputeDistances();
  const PlannedPath p = PlanPath(g, {0, 0, -4}, {20, 0, -4}, Planner());
  ASSERT_TRUE(p.found);
  const double seen = SeenFreeLength(g, p.p_N, 1.0, 0.25);
  EXPECT_NEAR(seen, 8.0, 0.5);
}

// A vehicle cruising on the face between two layers of cells, 4.0 m up on 0.4 m cells, in an
// open field: rays from its camera down to the ground have crossed the layer below (3.6-4.0 m)
// for metres ahead, the layer above hardly at all. Its body (0.5 m high) is in both, so the
// seen-free length must not swing with which of the two its centre is in (2 cm higher or lower);
// with neither layer seen it is nothing, and the layer below alone is not enough for a body that
// does not reach into it.
TEST(PathPlanner, SeenFreeLengthDoesNotTurnOnWhichCellTheBodysCentreIsIn) {
  LocalGrid g(Eigen::Vector3d(-2, -6, -8), Eigen::Vector3i(60, 30, 20), 0.4);
  for (int z = 0; z < 20; ++z)
    for (int y = 0; y < 30; ++y)
      for (int x = 0; x < 60; ++x) {
        const Eigen::Vector3d c = g.Centre({x, y, z});
        if (c.z() > -4.0 && c.z() < -3.6 && c.x() < 12.0) g.Set({x, y, z}, Cell::kFree);  // 3.6-4.0 m up
      }
  g.ComputeDistances();
  for (const double up : {3.98, 4.02}) {
    const double seen = SeenFreeLength(g, {{0, 0, -up}, {20, 0, -up}}, 1.0, 0.25);
    EXPECT_NEAR(seen, 12.0, 0.2) << up << " m up";
  }
  // 4.1 m up, a body 0.5 m high reaches into the layer seen; one 0.1 m high does not.
  EXPECT_NEAR(SeenFreeLength(g, {{0, 0, -4.1}, {20, 0, -4.1}}, 1.0, 0.25), 12.0, 0.2);
  EXPECT_LT(SeenFreeLength(g, {{0, 0, -4.1}, {20, 0, -4.1}}, 1.0, 0.05), 0.2);
  // Nothing seen at 5 m up.
  EXPECT_LT(SeenFreeLength(g, {{0, 0, -5.0}, {20, 0, -5.0}}, 1.0, 0.25), 0.2);
}

// The box [lo, hi) seen free (one leaf every `step` m), then a pole seen twice (certain).
void SeenFreeWithAPole(AvoidancePlanner& planner, const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, double step,
                       const MapCylinder& pole) {
  for (double n = lo.x(); n < hi.x(); n += step)
    for (double e = lo.y(); e < hi.y(); e += step)
      for (double d = lo.z(); d < hi.z(); d += step) planner.map().Mark({n, e, d}, false);
  PerceptionUpdate u;
  u.utime = 1;
  u.cylinders.push_back(pole);
  planner.Add(u, Eigen::Vector3d::Zero());
  planner.Add(u, Eigen::Vector3d::Zero());
}

// The vehicle has climbed to 10 m over something and the goal, 12 m ahead, is 4 m up: below the
// planning window (4 m either side of the vehicle's height), with a tall pole between. The path
// goes round the pole toward the goal and down to it; searched toward the window's side faces,
// the back face was the cheaper way out and the vehicle flew away from the goal (a 1/12 field,
// seed 3, never reached its goal).
TEST(AvoidancePlanner, AGoalBelowTheWindowIsFlownTowardNotAwayFrom) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  SeenFreeWithAPole(planner, {-4, -10, -15}, {24, 10, -0.5}, 0.4, {{5.0, 0.0}, -16.0, 0.0, 1.5});
  const Eigen::Vector3d goal(12, 0, -4);
  const AvoidancePlan plan = planner.Plan(2, {0, 0, -10}, goal, goal);
  ASSERT_EQ(plan.state, AvoidState::kAvoiding) << plan.reason;
  EXPECT_TRUE(plan.path_N.back().isApprox(goal)) << plan.path_N.back().transpose();
  for (const Eigen::Vector3d& q : plan.path_N) EXPECT_GT(q.x(), -0.5) << "heads away from the goal: " << q.transpose();
}

// A pole 2 m beside the straight way to the goal, and the vehicle, just off a detour, flying at
// 2.8 m/s 45 degrees across that way toward the pole: the straight way is clear, the turn onto
// it from where the momentum carries the vehicle is not. Still, the planner said "clear" and the
// vehicle swung into a pole (1/49 field, seed 8).
TEST(AvoidancePlanner, TheStraightWayIsClearOnlyIfTheTurnOntoItIs) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  SeenFreeWithAPole(planner, {-2, -10, -8}, {30, 10, -0.5}, 0.2, {{8.5, 2.3}, -9.0, 0.0, 0.3});
  const Eigen::Vector3d p(7, 0.3, -4), goal(22, 0.3, -4), across(2, 2, 0);
  EXPECT_EQ(planner.Plan(1, p, goal, goal, false, Eigen::Vector3d(2.8, 0, 0)).state, AvoidState::kClear)
      << "flying along the way";
  const AvoidancePlan plan = planner.Plan(2, p, goal, goal, false, across);
  ASSERT_EQ(plan.state, AvoidState::kAvoiding) << plan.reason;
  for (double s = 0; s < Length(plan.path_N); s += 0.1) {
    const Eigen::Vector3d q = PointAt(plan.path_N, s);
    EXPECT_GT((q.head<2>() - Eigen::Vector2d(8.5, 2.3)).norm() - 0.3, params.clearance() - 0.25) << q.transpose();
  }
}

// A wire across the way, slanting across the planning cells and off their centres, drawn as the
// stereo worker draws a well-ranged one (the cable's 0.1 m): what is planned passes it with the
// whole clearance from the true cable, not only from the cells the grid rounded it into (the
// soft clearance keeps the detour off the rounding; the straight way's check adds half a cell).
TEST(AvoidancePlanner, PassesAWireWithTheWholeClearanceFromTheCable) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  SeenFreeWithAPole(planner, {-2, -10, -9}, {30, 10, -0.5}, 0.2, {{8.0, -9.0}, -9.0, 0.0, 0.2});
  const Eigen::Vector3d a(11.07, -10.0, -4.13), b(12.93, 10.0, -3.71);
  PerceptionUpdate u;
  u.utime = 2;
  u.wires.push_back({{a, b}, 0.1});
  planner.Add(u, Eigen::Vector3d::Zero());
  // Flown level at every height from 2.5 m below the cable to 2.5 m above it: whether the
  // straight way is taken or a detour planned, what is flown keeps the clearance.
  for (double dz = -2.5; dz <= 2.5; dz += 0.05) {
    const Eigen::Vector3d p(0, 0.1, -3.92 + dz), goal(22, 0.1, -3.92 + dz);
    const AvoidancePlan plan = planner.Plan(3, p, goal, goal);
    ASSERT_NE(plan.state, AvoidState::kNoPath) << dz << ": " << plan.reason;
    std::vector<Eigen::Vector3d> flown = plan.path_N;
    if (plan.state == AvoidState::kClear) flown = {p, goal};
    double least = 1e9;
    for (double s = 0; s < Length(flown); s += 0.05) {
      const Eigen::Vector3d q = PointAt(flown, s);
      const double t = std::clamp((q - a).dot(b - a) / (b - a).squaredNorm(), 0.0, 1.0);
      least = std::min(least, (a + t * (b - a) - q).norm());
    }
    EXPECT_GE(least, params.clearance()) << "flown " << dz << " m from the cable's height, " << (plan.state == AvoidState::kClear ? "straight" : "round");
  }
}

// The planner's copy of the map is sized to its windows: a window widened in flight (a
// parameter changed) sees a wall 30 m ahead that the narrow one's copy did not hold.
TEST(AvoidancePlanner, AWiderWindowSeesWhatTheNarrowOnesCopyDidNotHold) {
  AvoidanceParams params;
  params.enabled = true;
  params.window_m = 8;
  AvoidancePlanner planner(params);
  for (double e = -4; e <= 4; e += 0.2)
    for (double d = -7; d <= -1; d += 0.2) planner.map().Mark({30.1, e, d}, true);
  const Eigen::Vector3d goal(60, 0, -4);
  EXPECT_EQ(planner.Plan(1, {0, 0, -4}, goal, goal).state, AvoidState::kClear) << "the wall is beyond the narrow window";
  params.window_m = 24;
  planner.SetParams(params);
  const AvoidancePlan plan = planner.Plan(2, {0, 0, -4}, goal, goal);
  EXPECT_EQ(plan.state, AvoidState::kAvoiding) << plan.reason;
}

TEST(AvoidancePlanner, KeepsItsSideOfAnObstacleAsItFliesPast) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  // Everything seen free, then a pole right on the line to the goal.
  SeenFreeWithAPole(planner, {-2, -10, -8}, {30, 10, -0.5}, 0.2, {{10.0, 0.0}, -9.0, 0.0, 0.5});
  Eigen::Vector3d p(0, 0, -4);
  int side = 0;
  for (int step = 0; step < 40; ++step) {
    const AvoidancePlan plan = planner.Plan(step, p, {22, 0, -4}, {22, 0, -4});
    ASSERT_NE(plan.state, AvoidState::kNoPath) << step << ": " << plan.reason;
    // Clear once the straight way to the goal passes the pole with the clearance.
    if (plan.state == AvoidState::kClear) {
      EXPECT_GT(std::abs(p.y()), 0.5) << step;
    }
    const Eigen::Vector3d next = PointAt(plan.path_N, 0.5);
    // Which side the path passes the pole on.
    double e_at_pole = 0;
    for (double s = 0; s < Length(plan.path_N); s += 0.1)
      if (std::abs(PointAt(plan.path_N, s).x() - 10.0) < 0.1) e_at_pole = PointAt(plan.path_N, s).y();
    if (p.x() < 9.0) {
      const int now = e_at_pole > 0 ? 1 : -1;
      if (side == 0) side = now;
      EXPECT_EQ(now, side) << "flipped sides at step " << step;
    }
    p = next;
    // A little noise in the estimate, as in flight.
    p.y() += (step % 2 ? 0.05 : -0.05);
    if (p.x() > 12.0) break;
  }
  EXPECT_GT(p.x(), 12.0) << "got past the pole";
}

// A vehicle that comes within a planning cell of its detour's next corner, but not onto it (its
// loop lags, the navigation is noisy), has reached it: the next plan leads on from the corner,
// not back to it. Drawn back to a corner 0.2-0.45 m away at every plan, the vehicle circled it
// for 65 s (1/12 field, seed 16).
TEST(AvoidancePlanner, ACornerPassedWithinAPlanningCellIsNotFlownBackTo) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  // A wide trunk with the goal just behind it: the detour wraps round it in several corners.
  SeenFreeWithAPole(planner, {-2, -10, -8}, {30, 10, -0.5}, 0.2, {{10.0, 0.0}, -9.0, 0.0, 3.0});
  const Eigen::Vector3d goal(15.6, 0, -4);
  const AvoidancePlan first = planner.Plan(1, {0, 0, -4}, goal, goal);
  ASSERT_EQ(first.state, AvoidState::kAvoiding) << first.reason;
  ASSERT_GE(first.path_N.size(), 3u);
  const Eigen::Vector3d corner = first.path_N[1];
  // On the way to it, 0.3 m short and 0.1 m to the side.
  const Eigen::Vector3d in = (corner - first.path_N[0]).normalized();
  const Eigen::Vector3d side = Eigen::Vector3d::UnitZ().cross(in).normalized();
  const Eigen::Vector3d p = corner - 0.3 * in + 0.1 * side;
  const AvoidancePlan next = planner.Plan(2, p, goal, goal);
  ASSERT_EQ(next.state, AvoidState::kAvoiding) << next.reason;
  ASSERT_GE(next.path_N.size(), 2u);
  EXPECT_GE((next.path_N[1] - p).norm(), params.grid_m - 1e-9)
      << "leads back to a point " << (next.path_N[1] - p).norm() << " m away: " << next.path_N[1].transpose()
      << " (the corner " << corner.transpose() << ")";
  // And it still goes round the pole with its clearance.
  for (double s = 0; s < Length(next.path_N); s += 0.05)
    EXPECT_GT((PointAt(next.path_N, s).head<2>() - Eigen::Vector2d(10.0, 0.0)).norm(), 3.0 + params.body_radius_m);
}

// Perception lost (a failed camera): the planner goes only through space seen free, and the
// safety layer flies such plans however old the perception, and no other.
TEST(AvoidancePlanner, OnTheMapAloneGoesOnlyThroughSpaceSeenFree) {
  AvoidanceParams params;
  params.enabled = true;
  AvoidancePlanner planner(params);
  // The way the vehicle came (north 0..20, a corridor 4 m wide) seen free; the rest unknown.
  for (int n = 0; n < 105; ++n)  // every leaf's centre (0.2 m leaves)
    for (int e = 0; e < 20; ++e)
      for (int d = 0; d < 20; ++d) planner.map().Mark({-1.1 + 0.2 * n, -1.9 + 0.2 * e, -5.9 + 0.2 * d}, false);
  PerceptionUpdate u;
  u.utime = 1'000'000;
  planner.Add(u, {18, 0, -4});
  // Home through the corridor: found, and flown on the map alone.
  AvoidancePlan home = planner.Plan(5'000'000, {18, 0, -4}, {0, 0, -4}, {0, 0, -4}, /*map_only=*/true);
  EXPECT_TRUE(home.map_only);
  ASSERT_NE(home.state, AvoidState::kNoPath) << home.reason;
  EXPECT_NEAR(home.seen_free_m, Length(home.path_N), 0.5);
  // Off to the side, into space never seen: no path, and why.
  const AvoidancePlan aside = planner.Plan(5'100'000, {18, 0, -4}, {18, 12, -4}, {18, 12, -4}, /*map_only=*/true);
  EXPECT_EQ(aside.state, AvoidState::kNoPath);
  EXPECT_NE(aside.reason.find("seen free"), std::string::npos) << aside.reason;
  // With the perception, the same goal is planned through the unknown (the cameras will see it).
  EXPECT_NE(planner.Plan(5'200'000, {18, 0, -4}, {18, 12, -4}, {18, 12, -4}).state, AvoidState::kNoPath);

  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {18, 0, -4};
  control::Setpoint task;
  task.p_N = {0, 0, -4};
  // The perception is 4 s old: with it, a hold; on the map alone, the map's plan is flown.
  home.utime = 5'000'000;
  EXPECT_EQ(layer.Apply(task, task.p_N, est, &home, 5'010'000, 0.02).state, AvoidState::kNoData);
  const SafetyLayer::Output flown = layer.Apply(task, task.p_N, est, &home, 5'010'000, 0.02, /*map_only=*/true);
  EXPECT_NE(flown.state, AvoidState::kNoData) << flown.reason;
  EXPECT_GT(flown.speed_limit, 1.0);
  // A plan made with the perception is not flown on the map alone.
  AvoidancePlan old = home;
  old.map_only = false;
  const SafetyLayer::Output refused = layer.Apply(task, task.p_N, est, &old, 5'010'000, 0.02, /*map_only=*/true);
  EXPECT_EQ(refused.state, AvoidState::kNoData);
  EXPECT_NE(refused.reason.find("map alone"), std::string::npos) << refused.reason;
}

AvoidancePlan StraightPlan(double seen_free_m, int64_t utime, int64_t perception_utime) {
  AvoidancePlan plan;
  plan.utime = utime;
  plan.perception_utime = perception_utime;
  plan.goal_N = {50, 0, -4};
  plan.state = AvoidState::kClear;
  plan.path_N = {{0, 0, -4}, {50, 0, -4}};
  plan.seen_free_m = seen_free_m;
  return plan;
}

// One control step of a point mass under the layer's setpoint: the position loop (gain 1/s, the
// feed-forward, the horizontal, climb and sink, and 3-D speed limits, as the position controller
// has them), then the velocity reached at no more than the layer's deceleration.
void FlyPointMass(const control::Setpoint& sp, const AvoidanceParams& params, double dt, hal::VehicleEstimate& est) {
  Eigen::Vector3d want = sp.v_ff_N + (sp.p_N - est.p_N);
  const double limit_xy = sp.speed_max_xy.value_or(params.cruise_speed);
  if (want.head<2>().norm() > limit_xy) want.head<2>() *= limit_xy / want.head<2>().norm();
  want.z() = std::clamp(want.z(), -params.climb_speed, params.sink_speed);
  if (sp.speed_max && want.norm() > *sp.speed_max) want *= *sp.speed_max / want.norm();
  Eigen::Vector3d dv = want - est.v_N;
  if (dv.norm() > params.brake_accel * dt) dv *= params.brake_accel * dt / dv.norm();
  est.v_N += dv;
  est.p_N += est.v_N * dt;
}

// The layer as these tests fly it: on, cruising at 3 m/s.
AvoidanceParams EnabledAtThreeMetresPerSecond() {
  AvoidanceParams params;
  params.enabled = true;
  params.cruise_speed = 3.0;
  return params;
}

// A detour turning a right angle round the corner of what it avoids (north, then east: the
// obstacle lies inside the turn). The planner's shortcuts put their corners at the clearance
// from it. A point mass flies it from 3 m/s: it slows for the corner (to 1.1 m/s) and cuts it
// by 0.16 m, where the carrot 2 m ahead chased at cruise speed cut it by 0.31 m (at 2.6 m/s).
TEST(SafetyLayer, SlowsForACornerAndDoesNotCutIt) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  est.v_N = {3, 0, 0};
  control::Setpoint task;
  task.p_N = {10, 10, -4};
  const Eigen::Vector2d corner(10, 0);
  const double dt = 0.02;
  double cut = 0, slowest_near_corner = 1e9;
  for (int i = 0; i < 600; ++i) {
    const int64_t utime = int64_t(i) * 20000 + 1'000'000;
    AvoidancePlan plan;
    plan.utime = utime, plan.perception_utime = utime - 50'000;
    plan.goal_N = {10, 10, -4};
    plan.state = AvoidState::kAvoiding;
    plan.path_N = {{0, 0, -4}, {10, 0, -4}, {10, 10, -4}};
    plan.seen_free_m = 100;
    const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, utime, dt);
    FlyPointMass(out.setpoint, params, dt, est);
    // Inside the turn (short of the first leg's end, east of its line): off the path toward what
    // the corner goes round.
    if (est.p_N.x() < corner.x() && est.p_N.y() > corner.y()) cut = std::max(cut, std::min(corner.x() - est.p_N.x(), est.p_N.y()));
    if ((est.p_N.head<2>() - corner).norm() < 1.0) slowest_near_corner = std::min(slowest_near_corner, est.v_N.head<2>().norm());
  }
  EXPECT_LT(cut, 0.2) << "cut the corner toward what it goes round";
  std::printf("cut %.2f m, slowest near the corner %.2f m/s\n", cut, slowest_near_corner);
  EXPECT_LT(slowest_near_corner, 2.0) << "did not slow for the corner";
  EXPECT_GT(est.p_N.y(), 9.0) << "did not go on round it";
}

// A replanned path may leave across the way the vehicle flies, or turn back in a few short
// corners that are one hairpin together. The turn is counted from the vehicle's velocity to each
// leg ahead: at once for the leg it is on, after its reaction time for the legs ahead.
TEST(SafetyLayer, SlowsForATurnFromTheWayItFliesNotCornerByCorner) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  control::Setpoint task;
  task.p_N = {0, 20, -4};
  auto limit_for = [&](const std::vector<Eigen::Vector3d>& path) {
    SafetyLayer layer(params);
    hal::VehicleEstimate est;
    est.p_N = {0, 0, -4};
    est.v_N = {2.5, 0, 0};  // north
    AvoidancePlan plan;
    plan.utime = 1'000'000, plan.perception_utime = 950'000;
    plan.goal_N = path.back();
    plan.state = AvoidState::kAvoiding;
    plan.path_N = path;
    plan.seen_free_m = 100;
    return layer.Apply(task, plan.goal_N, est, &plan, 1'010'000, 0.02).speed_limit;
  };
  // East at a right angle: the arc within 0.2 m of the turn at 2.5 m/s^2 sideways,
  // sqrt(2.5 * 0.2 / (1 / cos 45deg - 1)) = 1.10 m/s.
  EXPECT_NEAR(limit_for({{0, 0, -4}, {0, 20, -4}}), 1.10, 0.01);
  // Straight on: cruise.
  EXPECT_NEAR(limit_for({{0, 0, -4}, {20, 0, -4}}), 3.0, 1e-9);
  // North 1 m, then three corners of 50 degrees 0.4 m apart (back south-west). Corner by corner
  // each allows 2.2 m/s and the vehicle could arrive at cruise; from the way it flies, the
  // 100-degree turn 1.4 m ahead allows -a t + sqrt((a t)^2 + v^2 + 2 a d) = 1.98 m/s
  // (v = 0.95 m/s, a = 2.5 m/s^2, t = 0.4 s).
  std::vector<Eigen::Vector3d> hairpin{{0, 0, -4}, {1, 0, -4}};
  for (double heading_deg : {50.0, 100.0, 150.0}) {
    const double h = heading_deg * M_PI / 180.0;
    hairpin.push_back(hairpin.back() + 0.4 * Eigen::Vector3d(std::cos(h), std::sin(h), 0));
  }
  hairpin.push_back(hairpin.back() + Eigen::Vector3d(-10, 0, 0));
  EXPECT_NEAR(limit_for(hairpin), 1.98, 0.01);
}

// A detour that dives under a cable: level, then down from 6 to 3 m over 3.5 m across the
// ground. The vehicle sinks at most at ctl_speed_max_down (1 m/s) whatever its speed across the
// ground, so along the dive it may fly 1 m/s x 4.61 m / 3 m = 1.54 m/s, and it slows for it
// before it gets there. At cruise along the dive it stays up to 1.8 m above it, toward the cable
// the dive passes under (1/12 field, seed 82: 0.75 m from a cable).
TEST(SafetyLayer, SlowsForALegSteeperThanItCanClimbOrSink) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  const std::vector<Eigen::Vector3d> path{{0, 0, -6}, {4, 0, -6}, {7.5, 0, -3}, {30, 0, -3}};
  control::Setpoint task;
  task.p_N = path.back();
  auto plan_at = [&](int64_t utime) {
    AvoidancePlan plan;
    plan.utime = utime, plan.perception_utime = utime - 50'000;
    plan.goal_N = path.back();
    plan.state = AvoidState::kAvoiding;
    plan.path_N = path;
    plan.seen_free_m = 100;
    return plan;
  };
  {  // On the dive itself, already travelling along it: the slope's speed.
    SafetyLayer layer(params);
    hal::VehicleEstimate est;
    est.p_N = {5, 0, -6 + 3.0 / 3.5};
    est.v_N = (path[2] - path[1]).normalized() * 1.5;
    const AvoidancePlan plan = plan_at(1'000'000);
    EXPECT_NEAR(layer.Apply(task, plan.goal_N, est, &plan, 1'010'000, 0.02).speed_limit, std::hypot(3.5, 3.0) / 3.0, 1e-6);
  }
  {  // A near-vertical drop (3 m over 0.5 m: 0.17 m/s across the ground) brings the ground speed
     // down to the arrival speed, 0.5 m/s, but never above what the task itself asks (0.3 m/s).
    const std::vector<Eigen::Vector3d> drop{{0, 0, -6}, {0.5, 0, -3}, {10, 0, -3}};
    AvoidancePlan plan = plan_at(1'000'000);
    plan.path_N = drop;
    hal::VehicleEstimate est;
    est.p_N = drop.front();
    for (double task_limit : {3.0, 0.3}) {
      control::Setpoint slow = task;
      slow.speed_max_xy = task_limit;
      SafetyLayer slow_layer(params);
      const auto out = slow_layer.Apply(slow, plan.goal_N, est, &plan, 1'010'000, 0.02);
      ASSERT_TRUE(out.setpoint.speed_max_xy.has_value());
      EXPECT_NEAR(*out.setpoint.speed_max_xy, std::min(task_limit, 0.5), 1e-9);
    }
  }
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = path.front();
  est.v_N = {3, 0, 0};
  const double dt = 0.02;
  double above = 0;
  for (int i = 0; i < 800; ++i) {
    const int64_t utime = int64_t(i) * 20000 + 1'000'000;
    const AvoidancePlan plan = plan_at(utime);
    FlyPointMass(layer.Apply(task, task.p_N, est, &plan, utime, dt).setpoint, params, dt, est);
    const double x = est.p_N.x();
    const double path_height = x < 4 ? 6.0 : x < 7.5 ? 6.0 - 3.0 * (x - 4) / 3.5 : 3.0;
    above = std::max(above, -est.p_N.z() - path_height);
  }
  std::printf("at most %.2f m above the dive\n", above);
  EXPECT_LT(above, 0.4) << "fell behind the dive";
  EXPECT_GT(est.p_N.x(), 28.0) << "did not go on";
}

// A plan that stops short of a goal too near an obstacle gives the task its stand-in (where the
// goto completes), but only for the goal it was planned for.
TEST(SafetyLayer, PassesOnWhereThePlanStopsShortOfItsGoal) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  AvoidancePlan plan;
  plan.utime = 1'000'000, plan.perception_utime = 950'000;
  plan.goal_N = {20, 0, -4};
  plan.state = AvoidState::kAvoiding;
  plan.path_N = {{0, 0, -4}, {10, 3, -4}, {19.2, 0, -4}};
  plan.seen_free_m = 100;
  plan.stops_short = true;
  plan.reason = "the goal is 0.5 m from an obstacle";
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  control::Setpoint task;
  task.p_N = plan.goal_N;
  SafetyLayer layer(params);
  const SafetyLayer::Output out = layer.Apply(task, plan.goal_N, est, &plan, 1'010'000, 0.02);
  ASSERT_TRUE(out.stand_in_N.has_value());
  EXPECT_EQ(*out.stand_in_N, plan.path_N.back());
  EXPECT_EQ(out.reason, plan.reason);
  SafetyLayer other(params);
  EXPECT_FALSE(other.Apply(task, Eigen::Vector3d(21, 0, -4), est, &plan, 1'010'000, 0.02).stand_in_N.has_value());
  plan.stops_short = false;
  SafetyLayer reaching(params);
  EXPECT_FALSE(reaching.Apply(task, plan.goal_N, est, &plan, 1'010'000, 0.02).stand_in_N.has_value());
}

TEST(SafetyLayer, StopsWithinTheSpaceItHasSeen) {
  // A point mass that accelerates and brakes at the layer's deceleration toward unseen space
  // 15 m ahead, from 4 m/s (PX4 Collision Prevention's validated speed).
  AvoidanceParams params;
  params.enabled = true;
  params.cruise_speed = 5.0;
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  est.v_N = {4, 0, 0};
  control::Setpoint task;
  task.p_N = {50, 0, -4};
  const double dt = 0.02;
  double max_x = 0;
  for (int i = 0; i < 1000; ++i) {
    const int64_t utime = int64_t(i) * 20000 + 1'000'000;
    // The map saw 15 m ahead of the start; nothing new is seen (a textureless wall).
    AvoidancePlan plan = StraightPlan(15.0, utime, utime - 100'000);
    const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, utime, dt);
    FlyPointMass(out.setpoint, params, dt, est);
    max_x = std::max(max_x, est.p_N.x());
  }
  EXPECT_LT(max_x, 15.0 - params.clearance() * 0) << "went into unseen space";
  EXPECT_GT(max_x, 12.0) << "stopped needlessly early";
  EXPECT_NEAR(est.v_N.x(), 0.0, 0.25);
}

// A detour that climbs steeply (over a wall) into space seen free for 3 m only: the speed the
// seen space allows holds for the speed in 3-D, climbing included, not for the speed across the
// ground alone (which a steep climb hardly has).
TEST(SafetyLayer, TheSeenSpaceLimitsTheClimbAsMuchAsTheLevelSpeed) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  control::Setpoint task;
  task.p_N = {20, 0, -4};
  const double dt = 0.02;
  const std::vector<Eigen::Vector3d> over_the_wall{{0, 0, -4}, {1, 0, -4}, {2, 0, -10}, {20, 0, -10}, {20, 0, -4}};
  double fastest = 0, allowed_then = 0, highest = 0;
  for (int i = 0; i < 300; ++i) {
    const int64_t utime = int64_t(i) * 20000 + 1'000'000;
    AvoidancePlan plan;
    plan.utime = utime, plan.perception_utime = utime - 50'000;
    plan.goal_N = task.p_N;
    plan.state = AvoidState::kAvoiding;
    plan.path_N = over_the_wall;
    plan.seen_free_m = 3.0;  // nothing more is seen (the cameras look ahead, not up)
    const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, utime, dt);
    if (out.state == AvoidState::kAvoiding) {  // (else stopped short, holding)
      ASSERT_TRUE(out.setpoint.speed_max.has_value());
      EXPECT_NEAR(*out.setpoint.speed_max, std::max(0.05, out.speed_limit), 1e-9);
      EXPECT_LE(out.setpoint.v_ff_N.norm(), *out.setpoint.speed_max + 1e-9);
    }
    FlyPointMass(out.setpoint, params, dt, est);
    if (est.v_N.norm() > fastest) fastest = est.v_N.norm(), allowed_then = out.speed_limit;
    highest = std::max(highest, -est.p_N.z());
  }
  std::printf("fastest %.2f m/s where %.2f m/s was allowed; climbed to %.2f m\n", fastest, allowed_then, highest);
  // Stopping within the 3 m seen from 0.45 s of perception age and reaction at 2.5 m/s^2
  // allows 2.9 m/s at the start; the vehicle stops short of the end of what it has seen.
  EXPECT_LT(fastest, 2.0) << "climbed faster than the seen space allows";
  EXPECT_GT(highest, 4.5) << "did not climb";
  EXPECT_LT(ArcLengthOf(over_the_wall, est.p_N), 3.0) << "flew beyond the space seen free";
}

// Moving where the watching pair does not look: the way north is seen free for 40 m, but the
// nose points 90 degrees off it (the pair sees 33 degrees either side). The speed is what stops
// the vehicle within its clearance (1 m, perception 0.1 s old, 0.4 s reaction, 2.5 m/s^2:
// 1.31 m/s); at the edge of the view it is the seen space's; 5 degrees past it, half way. The
// heading's reference turns toward the way at avd_yaw_rate, and that rate is fed forward.
TEST(SafetyLayer, MovesWhereThePairDoesNotLookOnlyAsFastAsItStopsWithinItsClearance) {
  AvoidanceParams params;
  params.enabled = true;
  params.cruise_speed = 5.0;
  const double half_view = 33.0 * M_PI / 180.0;
  auto limit_at = [&](double heading_deg) {
    SafetyLayer layer(params);
    hal::VehicleEstimate est;
    est.p_N = {0, 0, -4};
    est.v_N = {2, 0, 0};
    est.euler.psi = heading_deg * M_PI / 180.0;
    control::Setpoint task;
    task.p_N = {50, 0, -4};
    AvoidancePlan plan = StraightPlan(40.0, 1'000'000, 900'000);
    plan.view_half_rad = half_view;
    const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, 1'000'000, 0.02);
    EXPECT_EQ(out.state, AvoidState::kClear);
    EXPECT_NEAR(out.setpoint.yaw_rate_ff, heading_deg > 0 ? -params.yaw_rate : heading_deg < 0 ? params.yaw_rate : 0.0, 1e-9);
    return out.speed_limit;
  };
  const double a = params.brake_accel, t = 0.1 + params.reaction_s;
  const double blind = -a * t + std::sqrt(a * a * t * t + 2 * a * params.clearance());
  const double seen = -a * t + std::sqrt(a * a * t * t + 2 * a * 40.0);
  EXPECT_NEAR(limit_at(90), blind, 1e-9);
  EXPECT_NEAR(limit_at(-90), blind, 1e-9);
  EXPECT_NEAR(limit_at(0), seen, 1e-9);
  EXPECT_NEAR(limit_at(33), seen, 1e-6);
  EXPECT_NEAR(limit_at(38), 0.5 * (seen + blind), 1e-6);
  EXPECT_NEAR(blind, 1.31, 0.01);
}

TEST(SafetyLayer, BrakesAndHoldsOnStalePerceptionAndSaysWhy) {
  AvoidanceParams params;
  params.enabled = true;
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  est.v_N = {3, 0, 0};
  control::Setpoint task;
  task.p_N = {50, 0, -4};
  AvoidancePlan plan = StraightPlan(40.0, 1'000'000, 400'000);  // perception 0.6 s old
  SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, 1'000'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kNoData);
  EXPECT_NE(out.reason.find("0.6 s old"), std::string::npos) << out.reason;
  // It holds where a 2.5 m/s^2 stop from 3 m/s ends: 1.8 m on.
  EXPECT_NEAR(out.setpoint.p_N.x(), 1.8, 1e-6);
  EXPECT_TRUE(out.setpoint.v_ff_N.isZero());
  // Fresh again: flies on toward the goal.
  plan = StraightPlan(40.0, 1'100'000, 1'050'000);
  out = layer.Apply(task, task.p_N, est, &plan, 1'100'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kClear);
  EXPECT_EQ(out.setpoint.p_N.x(), 50.0);
  // No plan at all: holds too.
  out = layer.Apply(task, task.p_N, est, nullptr, 1'200'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kNoData);
}

// A stereo pair at 1.25 Hz (a loaded computer): between its frames the vehicle is not held for
// "no data" (the operator heard that every 0.3 s and the goto timed out at 8 m of 50); it flies
// on a speed that counts the wait for the next frame, steady between frames, lower than with a
// 10 Hz pair over the same seen space, and stops within what it has seen. A frame missing for
// more than twice the period is late: it holds.
TEST(SafetyLayer, ASlowPerceptionSlowsTheVehicleAndIsNotTakenForLost) {
  const AvoidanceParams params = EnabledAtThreeMetresPerSecond();
  auto fly = [&](int64_t frame_period_us, double* lowest_limit, double* highest_limit) {
    SafetyLayer layer(params);
    hal::VehicleEstimate est;
    est.p_N = {0, 0, -4};
    control::Setpoint task;
    task.p_N = {50, 0, -4};
    *lowest_limit = 1e9, *highest_limit = 0;
    int held = 0;
    const double dt = 0.02;
    int64_t last_frame = -1;
    double seen_end = 0;  // [m] along the path: what the newest frame saw free
    for (int i = 0; i < 1500; ++i) {  // 30 s
      const int64_t utime = int64_t(i) * 20000 + 1'000'000;
      const int64_t frame = utime - (utime - 1'000'000) % frame_period_us;  // the newest frame
      // Each frame sees 8 m ahead of where the vehicle was; the plan is made at 10 Hz from it.
      if (frame != last_frame) last_frame = frame, seen_end = std::min(50.0, est.p_N.x() + 8.0);
      AvoidancePlan plan = StraightPlan(seen_end, std::max(frame, utime - utime % 100'000), frame);
      const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, utime, dt);
      if (i > 50) held += out.state == AvoidState::kNoData;  // once two frames have told the rate
      EXPECT_LE(est.p_N.x(), seen_end + 1e-9) << "beyond what was seen free at " << utime;
      if (i > 100 && est.p_N.x() < 40.0) {  // cruising: not the start, nor the slowing for the goal
        *lowest_limit = std::min(*lowest_limit, out.speed_limit);
        *highest_limit = std::max(*highest_limit, out.speed_limit);
      }
      FlyPointMass(out.setpoint, params, dt, est);
    }
    EXPECT_EQ(held, 0) << "held for no data between the frames of a " << frame_period_us / 1000 << " ms pair";
    return est.p_N.x();
  };
  double slow_lo, slow_hi, fast_lo, fast_hi;
  const double slow_x = fly(800'000, &slow_lo, &slow_hi);
  const double fast_x = fly(100'000, &fast_lo, &fast_hi);
  EXPECT_GT(slow_x, 45.0) << "the slow pair's vehicle did not get there";
  EXPECT_GT(fast_x, 45.0);
  // t = 0.4 s reaction + 0.8 s period over 8 m: v = -a t + sqrt((a t)^2 + 2 a d) = 4.0 m/s at
  // most, 3.1 m/s when 2.4 m of it are flown; at 10 Hz (t = 0.5 s) 5.2 m/s. With the age alone
  // the slow pair's limit swung from 5.4 m/s (t = 0.4 s) to 3.1 m/s within each frame.
  EXPECT_NEAR(slow_hi, 4.0, 0.05);
  EXPECT_GT(slow_lo, 2.9);
  EXPECT_NEAR(fast_hi, 5.2, 0.1);
  // A frame late by more than twice the period: held, and why.
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  control::Setpoint task;
  task.p_N = {50, 0, -4};
  for (int64_t frame = 1'000'000; frame <= 4'200'000; frame += 800'000) {
    AvoidancePlan plan = StraightPlan(20.0, frame + 50'000, frame);
    EXPECT_EQ(layer.Apply(task, task.p_N, est, &plan, frame + 50'000, 0.02).state, AvoidState::kClear);
  }
  AvoidancePlan late = StraightPlan(20.0, 5'900'000, 4'200'000);  // 1.7 s old: more than 2 x 0.8 s
  const SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &late, 5'900'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kNoData);
  EXPECT_NE(out.reason.find("1.7 s old (limit 1.6 s)"), std::string::npos) << out.reason;
}

TEST(SafetyLayer, HoldsWhenThePlannerFindsNoPathAndIsOffWithoutAGoal) {
  AvoidanceParams params;
  params.enabled = true;
  SafetyLayer layer(params);
  hal::VehicleEstimate est;
  est.p_N = {0, 0, -4};
  control::Setpoint task;
  task.p_N = {50, 0, -4};
  AvoidancePlan plan = StraightPlan(0.0, 1'000'000, 1'000'000);
  plan.state = AvoidState::kNoPath;
  plan.reason = "no path: every way within the window is blocked";
  SafetyLayer::Output out = layer.Apply(task, task.p_N, est, &plan, 1'000'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kNoPath);
  EXPECT_NE(out.reason.find("holding"), std::string::npos);
  EXPECT_EQ(out.setpoint.p_N, est.p_N);
  out = layer.Apply(task, std::nullopt, est, &plan, 1'000'000, 0.02);
  EXPECT_EQ(out.state, AvoidState::kOff);
  EXPECT_EQ(out.setpoint.p_N, task.p_N);
}

}  // namespace
}  // namespace uav::avoid
