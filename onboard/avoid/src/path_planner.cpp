#include "uav/avoid/path_planner.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>
#include <stdexcept>

namespace uav::avoid {

void PlannerParams::Validate() const {
  if (!(clearance_m > 0 && clearance_m < 10)) throw std::invalid_argument("planner clearance must be in (0, 10) m");
  if (!(soft_clearance_m >= clearance_m)) throw std::invalid_argument("planner soft clearance must be at least the clearance");
  if (!(proximity_cost >= 0) || !(unknown_cost >= 0) || !(vertical_cost >= 1))
    throw std::invalid_argument("planner costs must be non-negative (vertical factor at least 1)");
  if (max_expansions < 1) throw std::invalid_argument("planner max_expansions must be positive");
  if (!(heuristic_weight >= 1 && heuristic_weight <= 5)) throw std::invalid_argument("planner heuristic_weight must be in [1, 5]");
}

namespace {

// The grid's distance is between cell centres; the vehicle may be anywhere in its cell and the
// obstacle anywhere in its own, so a cell counts as clear only with half a cell to spare.
double Inflated(const LocalGrid& g, double clearance_m) { return clearance_m + 0.5 * g.resolution(); }

// The open list: a 4-ary min-heap of (f, cell) on the scratch's memory. Half as deep as a binary
// heap, a node's four children are in one or two cache lines, and an entry is one 64-bit key
// compared without branches: f's bits above the cell's (f >= 0, whose IEEE bits order as the
// numbers do). Entries are ordered by f, then by cell, as std::priority_queue orders the pairs,
// so the search pops them in the same order.
class OpenList {
 public:
  explicit OpenList(std::vector<uint64_t>& heap) : v_(heap) { v_.clear(); }
  static uint64_t Key(float f, int cell) {
    uint32_t bits;
    std::memcpy(&bits, &f, sizeof bits);
    return (uint64_t{bits} << 32) | static_cast<uint32_t>(cell);
  }
  bool Empty() const { return v_.empty(); }
  void Push(float f, int cell) {
    const uint64_t e = Key(f, cell);
    std::size_t i = v_.size();
    v_.push_back(e);
    while (i > 0) {
      const std::size_t up = (i - 1) / 4;
      if (e >= v_[up]) break;
      v_[i] = v_[up];
      i = up;
    }
    v_[i] = e;
  }
  // The cell of the least entry, removed.
  int Pop() {
    const uint64_t top = v_.front();
    const uint64_t last = v_.back();
    v_.pop_back();
    const std::size_t n = v_.size();
    std::size_t i = 0;
    for (;;) {
      const std::size_t first = 4 * i + 1;
      if (first >= n) break;
      std::size_t best = first;
      const std::size_t end = std::min(first + 4, n);
      for (std::size_t k = first + 1; k < end; ++k) best = v_[k] < v_[best] ? k : best;
      if (v_[best] >= last) break;
      v_[i] = v_[best];
      i = best;
    }
    if (n > 0) v_[i] = last;
    return static_cast<int>(static_cast<uint32_t>(top));
  }

 private:
  std::vector<uint64_t>& v_;
};

}  // namespace

bool SegmentClear(const LocalGrid& grid, const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N, double clearance_m) {
  const double need = Inflated(grid, clearance_m);
  const double length = (b_N - a_N).norm();
  const int n = std::max(1, static_cast<int>(std::ceil(length / (grid.resolution() / 3.0))));
  for (int i = 0; i <= n; ++i)
    if (grid.DistanceAt(a_N + (b_N - a_N) * (double(i) / n)) < need) return false;
  return true;
}

double SeenFreeLength(const LocalGrid& grid, const std::vector<Eigen::Vector3d>& p_N, double clearance_m,
                      double body_half_height_m) {
  if (p_N.empty()) return 0.0;
  // Observed free: the body's centre's cell, or the cell above or below when the body reaches
  // into it. A vehicle cruising on a cell's face (4.0 m up on 0.4 m cells) otherwise had its
  // seen-free length swing between 0.3 and 5.6 m as its height wandered by 2 cm: rays from a
  // camera at the bottom of the upper cell, down to the ground, hardly cross that cell, and
  // cross the one below it for metres. In an open field it surged to 3 m/s and braked to
  // 0.6 m/s every 2-3 s, 0.69 x cruise on average; 20 cm higher or lower, 0.86-0.89 x.
  const double half = std::min(body_half_height_m, 0.5 * grid.resolution());
  auto observed_free = [&](const Eigen::Vector3d& p) {
    if (grid.StateAt(p) == Cell::kFree) return true;
    const Eigen::Vector3i c = grid.CellOf(p);
    const double into = p.z() - grid.Centre(c).z();  // [m] from the cell's middle, down positive
    const Eigen::Vector3i across = c + Eigen::Vector3i(0, 0, into > 0 ? 1 : -1);
    return 0.5 * grid.resolution() - std::abs(into) < half && grid.Contains(across) && grid.State(across) == Cell::kFree;
  };
  // A vehicle already nearer an obstacle than the clearance may move as long as it gets no nearer
  // (the planner's way out).
  const double need = std::min(Inflated(grid, clearance_m), static_cast<double>(grid.DistanceAt(p_N.front())));
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < p_N.size(); ++i) {
    const double length = (p_N[i + 1] - p_N[i]).norm();
    const int n = std::max(1, static_cast<int>(std::ceil(length / (grid.resolution() / 3.0))));
    for (int k = i == 0 ? 0 : 1; k <= n; ++k) {
      const Eigen::Vector3d p = p_N[i] + (p_N[i + 1] - p_N[i]) * (double(k) / n);
      if (!observed_free(p) || grid.DistanceAt(p) < need) return s + length * std::max(0, k - 1) / n;
    }
    s += length;
  }
  return s;
}

PlannedPath PlanPath(const LocalGrid& grid, const Eigen::Vector3d& start_N, const Eigen::Vector3d& goal_N,
                     const PlannerParams& params, PlannerScratch* scratch) {
  params.Validate();
  PlannedPath out;
  if (!start_N.allFinite() || !goal_N.allFinite()) {
    out.reason = "start or goal is not finite";
    return out;
  }
  const Eigen::Vector3i size = grid.size();
  const Eigen::Vector3i vehicle = grid.CellOf(start_N);
  if (!grid.Contains(vehicle)) {
    out.reason = "the vehicle is outside the planning window";
    return out;
  }
  const Eigen::Vector3i goal = grid.CellOf(goal_N);
  const bool goal_inside = grid.Contains(goal);
  // A goal within the window across the ground but above or below it (the vehicle climbed over
  // something; the goal is on the ground's side of it): the search goes to the goal's place at
  // the window's nearest height, and the path on down (or up) to the goal. Reached through the
  // side faces instead, the back face can be the cheaper way out (nearer, as the goal is near),
  // and the vehicle flew away from a goal 10 m ahead.
  if (!goal_inside && goal.x() >= 0 && goal.y() >= 0 && goal.x() < size.x() && goal.y() < size.y()) {
    const double lo_z = grid.min_N().z(), hi_z = lo_z + size.z() * grid.resolution();
    Eigen::Vector3d at_height = goal_N;
    at_height.z() = std::clamp(goal_N.z(), lo_z + 0.5 * grid.resolution(), hi_z - 0.5 * grid.resolution());
    PlannedPath to_height = PlanPath(grid, start_N, at_height, params, scratch);
    if (to_height.found) {
      to_height.p_N.push_back(goal_N);
      return to_height;
    }
  }
  const double need = Inflated(grid, params.clearance_m);
  if (goal_inside && grid.State(goal) == Cell::kOccupied) {
    out.reason = "the goal is inside an obstacle";
    return out;
  }
  if (goal_inside && grid.Distance(goal) < params.clearance_m) {
    // A goal nearer an obstacle than the clearance, but not in one: the vehicle goes as near it
    // as the clearance lets it, to the nearest cell within the clearance of the goal that keeps
    // it, and says so (PX4 Collision Prevention likewise stops at the obstacle, short of a
    // setpoint beyond it). Refused outright, a goal 2 m from a pole, read nearer by the pole's
    // measured width and the planning cells, held the vehicle 7 m short (1/25 field, seed 1).
    const int reach = static_cast<int>(std::ceil(params.clearance_m / grid.resolution()));
    double nearest = std::numeric_limits<double>::infinity();
    Eigen::Vector3d stand_in_N = goal_N;
    for (int dz = -reach; dz <= reach; ++dz)
      for (int dy = -reach; dy <= reach; ++dy)
        for (int dx = -reach; dx <= reach; ++dx) {
          const Eigen::Vector3i c = goal + Eigen::Vector3i(dx, dy, dz);
          if (!grid.Contains(c) || grid.Distance(c) < need || grid.State(c) == Cell::kOccupied) continue;
          const double down = grid.Centre(c).z();
          if (down > params.floor_down_m || down < params.ceiling_down_m) continue;
          const double off = (grid.Centre(c) - goal_N).norm();
          if (off <= params.clearance_m && off < nearest) nearest = off, stand_in_N = grid.Centre(c);
        }
    char buf[160];
    if (!std::isfinite(nearest)) {
      std::snprintf(buf, sizeof buf, "the goal is too close to an obstacle (%.1f m, clearance %.1f m)", grid.Distance(goal),
                    params.clearance_m);
      out.reason = buf;
      return out;
    }
    PlannedPath near = PlanPath(grid, start_N, stand_in_N, params, scratch);
    if (!near.found) return near;
    near.reaches_goal = false;
    near.stops_short = true;
    std::snprintf(buf, sizeof buf, "the goal is %.1f m from an obstacle (clearance %.1f m): going to %.1f m short of it",
                  grid.Distance(goal), params.clearance_m, nearest);
    near.reason = buf;
    return near;
  }
  // Already nearer an obstacle than the clearance (one appeared close, or the vehicle was pushed
  // in): first straight out, up the distance field's steepest ascent until the clearance is
  // kept. A search that only forbade getting nearer would let the path slide along the
  // obstacle at the distance it started from, and each replan, started a little nearer,
  // ratchets the vehicle in.
  auto in_band = [&](const Eigen::Vector3i& c) {
    const double down = grid.Centre(c).z();
    return down <= params.floor_down_m && down >= params.ceiling_down_m;
  };
  std::vector<Eigen::Vector3i> climb{vehicle};
  while (grid.Distance(climb.back()) < need && climb.size() < 64) {
    Eigen::Vector3i best = climb.back();
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const Eigen::Vector3i c = climb.back() + Eigen::Vector3i(dx, dy, dz);
          if (grid.Contains(c) && in_band(c) && grid.Distance(c) > grid.Distance(best)) best = c;
        }
    if (best == climb.back()) break;  // a ridge of the field (a narrow gap): searched from here
    climb.push_back(best);
  }
  const Eigen::Vector3i start = climb.back();
  // Where the climb stopped short of the clearance, cells at least as far as its end are open.
  const double open_from = std::min(need, static_cast<double>(grid.Distance(start)));
  const double res = grid.resolution();
  const double soft = std::max(params.soft_clearance_m, need + 1e-6);
  auto h = [&](const Eigen::Vector3i& c) { return (grid.Centre(c) - goal_N).norm(); };
  const float w = static_cast<float>(params.heuristic_weight);
  auto on_border = [&](const Eigen::Vector3i& c) {
    // The side faces only: a goal beyond the window is reached across the ground, not over the top.
    return c.x() == 0 || c.y() == 0 || c.x() == size.x() - 1 || c.y() == size.y() - 1;
  };
  const int n = size.prod();
  // Per cell, worked out when the search first reaches it (it reaches a small part of the
  // window): closed (the altitude band, or nearer an obstacle than allowed) or not, the cost
  // factor of entering it, its cost so far, its parent and its weighted heuristic. Per
  // neighbour: the index offset and the step length. The search then only adds and compares.
  constexpr uint8_t kOpen = 0, kClosed = 1, kExpanded = 2, kNotReached = 3;
  PlannerScratch own;
  PlannerScratch& arrays = scratch ? *scratch : own;
  arrays.state.assign(n, kNotReached);
  arrays.nodes.resize(n);
  uint8_t* closed = arrays.state.data();
  PlannerScratch::Node* node = arrays.nodes.data();
  std::vector<uint8_t> band(size.z());
  for (int z = 0; z < size.z(); ++z) {
    const double down = grid.Centre({0, 0, z}).z();
    band[z] = down <= params.floor_down_m && down >= params.ceiling_down_m;
  }
  auto cell_of = [&](int i) { return Eigen::Vector3i(i % size.x(), (i / size.x()) % size.y(), i / (size.x() * size.y())); };
  // Cell i, at c, reached for the first time.
  auto reach = [&](int i, const Eigen::Vector3i& c) {
    const double d = grid.Distance(c);
    const Cell state = grid.State(c);
    closed[i] = !band[c.z()] || d < open_from || (params.unknown_closed && state != Cell::kFree) ? kClosed : kOpen;
    node[i].factor = static_cast<float>(1.0 + params.proximity_cost * std::clamp((soft - d) / (soft - need), 0.0, 1.0) +
                                        (state == Cell::kUnknown ? params.unknown_cost : 0.0));
    node[i].g = std::numeric_limits<float>::infinity();
    node[i].parent = -1;
    node[i].weighted_h = w * static_cast<float>(h(c));
  };
  const int s = grid.Index(start);
  reach(s, start);
  closed[s] = kOpen;
  const int goal_index = goal_inside ? grid.Index(goal) : -1;
  if (goal_inside) {
    reach(goal_index, goal);
    closed[goal_index] = kOpen;
  }
  struct Step {
    int dx, dy, dz, offset;
    float length;
  };
  std::vector<Step> steps;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (dx || dy || dz)
          steps.push_back({dx, dy, dz, (dz * size.y() + dy) * size.x() + dx,
                           static_cast<float>(std::hypot(res * std::hypot(dx, dy), res * std::abs(dz) * params.vertical_cost))});
  OpenList open(arrays.open);
  node[s].g = 0;
  open.Push(node[s].weighted_h, s);
  int found = -1;
  // A goal beyond the window: leaving it across a border cell completes the way with the straight
  // line to the goal, costed as unknown space (it has not been seen). Costed as free, the straight
  // line would make any border cheap against unknown cells inside, and a blocked way ahead would
  // send the vehicle out of the back of the window. The exit is an entry of its own (index n),
  // popped when no cheaper way is left.
  const float exit_factor = static_cast<float>(1.0 + params.unknown_cost);
  int exit_from = -1;
  float exit_cost = std::numeric_limits<float>::infinity();
  while (!open.Empty()) {
    const int i = open.Pop();
    if (i == n) {
      found = exit_from;
      break;
    }
    if (closed[i] == kExpanded) continue;
    closed[i] = kExpanded;
    const Eigen::Vector3i c = cell_of(i);
    if (i == goal_index) {
      found = i;
      break;
    }
    if (!goal_inside && on_border(c) && i != s) {
      const float cost = node[i].g + exit_factor * static_cast<float>(h(c));
      if (cost < exit_cost) {
        exit_cost = cost, exit_from = i;
        open.Push(cost, n);
      }
      continue;
    }
    if (++out.expansions > params.max_expansions) break;
    const bool interior = c.x() > 0 && c.y() > 0 && c.z() > 0 && c.x() < size.x() - 1 && c.y() < size.y() - 1 && c.z() < size.z() - 1;
    for (const Step& st : steps) {
      if (!interior && !grid.Contains(c + Eigen::Vector3i(st.dx, st.dy, st.dz))) continue;
      const int j = i + st.offset;
      if (closed[j] == kNotReached) reach(j, c + Eigen::Vector3i(st.dx, st.dy, st.dz));
      if (closed[j] != kOpen) continue;
      PlannerScratch::Node& next = node[j];
      const float cost = node[i].g + st.length * next.factor;
      if (cost < next.g) {
        next.g = cost;
        next.parent = i;
        open.Push(cost + next.weighted_h, j);
      }
    }
  }
  if (found < 0) {
    out.reason = out.expansions > params.max_expansions ? "no path found within the planner's budget"
                                                        : "no path: every way within the window is blocked";
    return out;
  }
  std::vector<Eigen::Vector3d> cells;
  for (int i = found; i >= 0; i = node[i].parent) cells.push_back(grid.Centre(cell_of(i)));
  std::reverse(cells.begin(), cells.end());
  if (climb.size() == 1) cells.front() = start_N;
  out.reaches_goal = goal_inside;
  if (goal_inside) cells.back() = goal_N;
  out.cost = node[found].g;
  // The climb out is flown as it is (each step farther from the obstacle than the one before).
  out.p_N.push_back(start_N);
  for (std::size_t i = 1; i + 1 < climb.size(); ++i) out.p_N.push_back(grid.Centre(climb[i]));
  // Line of sight: from each kept point, on along the cells while the straight way to them keeps
  // the clearance and a little more (shortcuts run along the obstacles the cells stayed clear
  // of, and the vehicle follows them with some error); the last such cell is the next point.
  const double keep = open_from < need ? 0.0 : params.clearance_m + params.shortcut_margin_m;
  if (climb.size() > 1) out.p_N.push_back(cells.front());
  for (std::size_t i = 0; i + 1 < cells.size();) {
    std::size_t j = i + 1;
    while (j + 1 < cells.size() && SegmentClear(grid, cells[i], cells[j + 1], keep)) ++j;
    out.p_N.push_back(cells[j]);
    i = j;
  }
  out.found = true;
  return out;
}

}  // namespace uav::avoid
