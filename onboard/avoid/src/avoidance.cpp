#include "uav/avoid/avoidance.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <time.h>

namespace uav::avoid {

namespace {
// CPU time this thread has used [ms].
double ThreadCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return t.tv_sec * 1e3 + t.tv_nsec * 1e-6;
}
}  // namespace

AvoidanceParams AvoidanceParams::FromParameters(const ParameterSet& p) {
  AvoidanceParams a;
  a.enabled = p.Get("avd_enable") != 0.0;
  a.body_radius_m = p.Get("avd_body_radius");
  a.body_height_m = p.Get("avd_body_height");
  a.margin_m = p.Get("obs_margin");
  a.brake_accel = p.Get("avd_brake_accel");
  a.reaction_s = p.Get("avd_reaction");
  a.stale_s = p.Get("avd_stale");
  a.blind_return_s = p.Get("avd_blind_return");
  a.rate_hz = p.Get("avd_rate");
  a.window_m = p.Get("avd_window");
  a.window_up_m = p.Get("avd_window_up");
  a.grid_m = p.Get("avd_grid");
  a.min_alt_m = p.Get("avd_min_alt");
  a.lookahead_m = p.Get("avd_lookahead");
  a.hysteresis = p.Get("avd_hysteresis");
  a.yaw_rate = p.Get("avd_yaw_rate") * M_PI / 180.0;
  a.cruise_speed = p.Get("ctl_speed_max_xy");
  a.climb_speed = p.Get("ctl_speed_max_up");
  a.sink_speed = p.Get("ctl_speed_max_down");
  a.map.resolution_m = p.Get("avd_map_res");
  a.map.max_cells = static_cast<std::size_t>(p.Get("avd_map_cells"));
  a.map.Validate();
  if (a.GridLevels() < 0) throw std::invalid_argument("avd_grid must be avd_map_res times 1, 2, 4, 8 or 16");
  return a;
}

PerceptionUpdate Translated(PerceptionUpdate u, const Eigen::Vector3d& d_N) {
  if (u.scan) {
    u.scan->origin_N += d_N;
    const Eigen::Vector3f d = d_N.cast<float>();
    for (Eigen::Vector3f& p : u.scan->p_N) p += d;
  }
  for (MapCylinder& c : u.cylinders) {
    c.p_NE += d_N.head<2>();
    c.top_down_m += d_N.z(), c.bottom_down_m += d_N.z();
  }
  for (MapWire& w : u.wires)
    for (Eigen::Vector3d& p : w.p_N) p += d_N;
  return u;
}

AvoidancePlan Translated(AvoidancePlan plan, const Eigen::Vector3d& d_N) {
  plan.goal_N += d_N;
  for (Eigen::Vector3d& p : plan.path_N) p += d_N;
  return plan;
}

double Length(const std::vector<Eigen::Vector3d>& path) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) s += (path[i + 1] - path[i]).norm();
  return s;
}

double ArcLengthOf(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& p) {
  double best_d = 1e18, best_s = 0.0, s = 0.0;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const Eigen::Vector3d ab = path[i + 1] - path[i];
    const double len = ab.norm();
    const double t = len > 1e-9 ? std::clamp((p - path[i]).dot(ab) / (len * len), 0.0, 1.0) : 0.0;
    const double d = (path[i] + t * ab - p).squaredNorm();
    if (d < best_d) best_d = d, best_s = s + t * len;
    s += len;
  }
  return best_s;
}

Eigen::Vector3d PointAt(const std::vector<Eigen::Vector3d>& path, double s) {
  if (path.empty()) return Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    const double len = (path[i + 1] - path[i]).norm();
    if (s <= len) return path[i] + (path[i + 1] - path[i]) * (len > 1e-9 ? std::max(0.0, s) / len : 0.0);
    s -= len;
  }
  return path.back();
}

AvoidancePlanner::AvoidancePlanner(const AvoidanceParams& params) : p_(params), map_(params.map) { SetParams(params); }

void AvoidancePlanner::SetParams(const AvoidanceParams& params) {
  if (params.GridLevels() < 0) throw std::invalid_argument("the planning cell must be the map's cell times 1, 2, 4, 8 or 16");
  if (params.map.resolution_m != p_.map.resolution_m || params.grid_m != p_.grid_m)
    throw std::invalid_argument("the map's and the planning cell's sizes are set at start");
  PlannerParams planner;
  planner.clearance_m = params.clearance();
  planner.soft_clearance_m = params.clearance() + 1.5;
  planner.floor_down_m = -params.min_alt_m;
  planner.Validate();
  p_ = params;
  planner_ = planner;
}

std::string AvoidancePlanner::Add(const PerceptionUpdate& u, const Eigen::Vector3d& p_N) {
  if (u.scan) map_.InsertScan(*u.scan);
  for (const MapCylinder& c : u.cylinders) map_.InsertCylinder(c.p_NE, c.top_down_m, c.bottom_down_m, c.radius_m);
  for (const MapWire& w : u.wires) map_.InsertPolyline(w.p_N, w.radius_m);
  if (u.watches_ahead) {
    perception_utime_ = std::max(perception_utime_, u.utime);
    if (u.view_half_rad > 0) view_azimuth_B_ = u.view_azimuth_B, view_half_rad_ = u.view_half_rad;
  }
  const std::size_t dropped = map_.EnforceBound(p_N);
  if (dropped > 0 && !bound_announced_) {
    bound_announced_ = true;
    char buf[160];
    std::snprintf(buf, sizeof buf, "obstacle map full (%zu cells): the cells farthest from the vehicle are dropped",
                  p_.map.max_cells);
    return buf;
  }
  return "";
}

int AvoidanceParams::GridLevels() const {
  for (int k = 0; k <= 4; ++k)
    if (std::abs(grid_m - map.resolution_m * (1 << k)) < 1e-9) return k;
  return -1;
}

void AvoidancePlanner::RefreshKnown(const Eigen::Vector3d& p_N) {
  const int coarser = p_.GridLevels();
  bool complete = true;
  const std::vector<OccupancyMap::Change> changes = map_.TakeChanges(coarser, &complete);
  // The copy covers every window the vehicle may plan in from where it is (a window reaches
  // 1.5 windows from it across the ground, one window up and down) plus 2 m, and follows the
  // vehicle once it is 2 m from the copy's centre: only the 2 m slab newly covered is read from
  // the tree. Reading the whole copy anew took 54-75 ms; a copy three windows wide moved every
  // half window still took up to 9 ms, the replanning's p99.
  constexpr double kLag = 2.0;
  const Eigen::Vector3d reach(1.5 * p_.window_m, 1.5 * p_.window_m, p_.window_up_m);
  const Eigen::Vector3d half = reach + Eigen::Vector3d::Constant(kLag + p_.grid_m);
  const Eigen::Vector3d margin = half - Eigen::Vector3d::Constant(kLag);
  const Eigen::Vector3d lo = known_.min_N(), hi = lo + known_.size().cast<double>() * known_.resolution();
  const bool inside = known_.size().prod() > 0 && ((p_N - margin).array() >= lo.array()).all() &&
                      ((p_N + margin).array() <= hi.array()).all();
  // A new window size (a parameter changed) needs a copy of the new size.
  const bool resized = (2.0 * half / p_.grid_m).array().ceil().cast<int>().max(1).matrix() != known_.size();
  if (!complete || resized) {
    known_ = LocalGrid::FromMap(map_, p_N, half, p_.grid_m, /*distances=*/false);
    return;
  }
  for (const OccupancyMap::Change& c : changes) known_.SetAt(c.centre_N, c.state);
  if (!inside) known_.Recentre(map_, p_N);
}

std::vector<Eigen::Vector3f> AvoidancePlanner::OccupiedAround(const Eigen::Vector3d& p_N, const Eigen::Vector3d& half_m) const {
  std::vector<std::pair<float, Eigen::Vector3f>> found;
  if (known_.size().prod() == 0) return {};
  const Eigen::Vector3i lo = known_.CellOf(p_N - half_m).cwiseMax(Eigen::Vector3i::Zero());
  const Eigen::Vector3i hi = known_.CellOf(p_N + half_m).cwiseMin(known_.size() - Eigen::Vector3i::Ones());
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x)
        if (known_.State({x, y, z}) == Cell::kOccupied) {
          const Eigen::Vector3d c = known_.Centre({x, y, z});
          found.emplace_back(static_cast<float>((c - p_N).squaredNorm()), c.cast<float>());
        }
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Eigen::Vector3f> out;
  out.reserve(found.size());
  for (const auto& f : found) out.push_back(f.second);
  return out;
}

AvoidancePlan AvoidancePlanner::Plan(int64_t utime, const Eigen::Vector3d& p_N, const Eigen::Vector3d& via_N,
                                     const Eigen::Vector3d& goal_N, bool map_only, const Eigen::Vector3d& v_N) {
  const auto t0 = std::chrono::steady_clock::now();
  const double cpu0_ms = ThreadCpuMs();
  AvoidancePlan plan;
  plan.utime = utime;
  plan.perception_utime = perception_utime_;
  plan.view_azimuth_B = view_azimuth_B_;
  plan.view_half_rad = view_half_rad_;
  plan.goal_N = goal_N;
  plan.map_cells = map_.cells();
  plan.map_only = map_only;
  // On the map alone nothing new will be seen: the detour is planned anew each time (the map
  // no longer changes, so neither does the plan), and only through space seen free.
  if (map_only) previous_.clear();
  if ((goal_N - previous_goal_N_).norm() > 0.5) previous_.clear();
  map_.InsertBody(p_N, p_.body_radius_m, p_.body_height_m);
  previous_goal_N_ = goal_N;
  // The window reaches ahead toward the goal: the vehicle sits a quarter of it from the back.
  const Eigen::Vector3d to_goal = goal_N - p_N;
  Eigen::Vector3d ahead = to_goal;
  ahead.z() = 0;
  if (ahead.norm() > 1e-6) ahead *= std::min(ahead.norm(), 0.5 * p_.window_m) / ahead.norm();
  RefreshKnown(p_N);
  window_.Extract(known_, p_N + ahead, Eigen::Vector3d(p_.window_m, p_.window_m, p_.window_up_m));
  const LocalGrid& grid = window_;
  PlannerParams planner = planner_;
  // Climbing or descending to the goal's altitude is the task's: the band opens to include it.
  planner.floor_down_m = std::max(planner.floor_down_m, std::max(p_N.z(), goal_N.z()));
  planner.unknown_closed = map_only;
  // The straight way, clipped to the window: clear means the task flies as it planned.
  // The task's straight way (to its own setpoint, then on to the goal), clipped to the window.
  const Eigen::Vector3d lo = grid.min_N(), hi = lo + grid.size().cast<double>() * grid.resolution();
  auto clipped = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    double t_exit = 1.0;
    for (int i = 0; i < 3; ++i)
      if (std::abs(b[i] - a[i]) > 1e-9) t_exit = std::min(t_exit, ((b[i] > a[i] ? hi[i] : lo[i]) - a[i]) / (b[i] - a[i]));
    return Eigen::Vector3d(a + (b - a) * std::max(0.0, 0.999 * t_exit));
  };
  auto way_clear = [&](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return map_only ? SeenFreeLength(grid, {a, b}, p_.clearance(), 0.5 * p_.body_height_m) >= (b - a).norm() - 1e-6 : SegmentClear(grid, a, b, p_.clearance());
  };
  // A vehicle flying across the straight way does not turn onto it where it is: its momentum
  // carries it on toward where it would stop braking at brake_accel, v|v| / 2a (no farther than
  // the setpoint). The way is clear only if that stretch and the way on from its end are: else a
  // vehicle coming off a detour at 2 m/s, 40 degrees across the line to its goal, swung 0.5 m
  // past the line into a pole the line itself passed with 1.15 m (1/49 field, seed 8).
  const double coast_m = std::min(v_N.squaredNorm() / (2.0 * p_.brake_accel), (via_N - p_N).norm());
  const Eigen::Vector3d p_coast_N = v_N.norm() > 1e-6 ? Eigen::Vector3d(p_N + v_N.normalized() * coast_m) : p_N;
  const bool coast_clear = (p_coast_N - p_N).norm() < p_.grid_m ||
                           (way_clear(p_N, clipped(p_N, p_coast_N)) && way_clear(p_coast_N, clipped(p_coast_N, via_N)));
  const bool direct = coast_clear && way_clear(p_N, clipped(p_N, via_N)) &&
                      ((via_N - goal_N).norm() < 1e-6 || way_clear(via_N, clipped(via_N, goal_N)));
  auto finish = [&](AvoidancePlan& out) -> AvoidancePlan {
    out.seen_free_m = out.path_N.size() >= 2 ? SeenFreeLength(grid, out.path_N, p_.clearance(), 0.5 * p_.body_height_m) : 0.0;
    out.planning_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    out.planning_cpu_ms = ThreadCpuMs() - cpu0_ms;
    return out;
  };
  if (direct) {
    previous_.clear();
    plan.state = AvoidState::kClear;
    plan.path_N = {p_N, via_N};
    if ((via_N - goal_N).norm() > 1e-6) plan.path_N.push_back(goal_N);
    return finish(plan);
  }
  PlannedPath fresh = PlanPath(grid, p_N, goal_N, planner, &scratch_);
  // Hysteresis: the detour being flown is kept while it stays clear and no new one is clearly
  // shorter, so the vehicle does not swap sides of an obstacle from one plan to the next.
  // A kept detour that ended on the border of an earlier window now ends inside this one: it
  // leads nowhere any more (flown to its end, the vehicle would stop there).
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(grid.resolution());
  const bool ends_inside = previous_.size() >= 2 && (previous_.back() - goal_N).norm() > 0.5 &&
                           ((previous_.back() - margin).head<2>().array() > lo.head<2>().array()).all() &&
                           ((previous_.back() + margin).head<2>().array() < hi.head<2>().array()).all();
  if (ends_inside) previous_.clear();
  if (previous_.size() >= 2) {
    std::vector<Eigen::Vector3d> rest{p_N};
    const double s = ArcLengthOf(previous_, p_N);
    double along = 0.0;
    for (std::size_t i = 0; i + 1 < previous_.size(); ++i) {
      along += (previous_[i + 1] - previous_[i]).norm();
      if (along > s + 1e-6) rest.push_back(previous_[i + 1]);
    }
    // A corner within a planning cell of the vehicle is reached (nothing finer is known of where
    // it should be): the rest leads on from the one after it. Kept while the vehicle was beside
    // it, never on it, a corner drew the vehicle back to itself at every plan: 1/12 seed 16
    // circled 0.2-0.45 m round a corner at the top of a dive for 65 s, the loop's lag carrying
    // it past the corner each time it came back.
    while (rest.size() > 2 && (rest[1] - p_N).norm() < p_.grid_m) rest.erase(rest.begin() + 1);
    bool clear = rest.size() >= 2;
    for (std::size_t i = 0; clear && i + 1 < rest.size(); ++i) clear = SegmentClear(grid, rest[i], rest[i + 1], p_.clearance());
    const double kept = Length(rest) + (rest.back() - goal_N).norm();
    const double best = fresh.found ? Length(fresh.p_N) + (fresh.p_N.back() - goal_N).norm() : 1e18;
    if (clear && kept <= (1.0 + p_.hysteresis) * best) {
      plan.state = AvoidState::kAvoiding;
      plan.reason = previous_reason_;
      plan.stops_short = previous_stops_short_;
      plan.path_N = rest;
      previous_ = rest;
      return finish(plan);
    }
  }
  if (!fresh.found) {
    previous_.clear();
    plan.state = AvoidState::kNoPath;
    plan.reason = map_only ? "perception lost and " + fresh.reason + " through space seen free" : fresh.reason;
    plan.path_N = {p_N};
    return finish(plan);
  }
  plan.state = AvoidState::kAvoiding;
  plan.reason = fresh.reason;
  plan.path_N = fresh.p_N;
  previous_ = fresh.p_N;
  previous_reason_ = fresh.reason;
  plan.stops_short = previous_stops_short_ = fresh.stops_short;
  return finish(plan);
}

}  // namespace uav::avoid
