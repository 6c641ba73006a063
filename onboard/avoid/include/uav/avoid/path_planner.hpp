#pragma once
// The global layer of thesis 7.2's planning: the shortest path on the local window that keeps
// the clearance, by A* over the 26-connected cells, then shortened by line of sight. Occupied
// cells and cells nearer an occupied one than the clearance are closed; unknown cells are open
// at a cost (the map fills in as the vehicle gets there, and the safety layer never lets it fly
// faster than it can stop in the space it has seen). A goal outside the window is reached
// through the window's border: the rest of the way is counted as a straight line, as the
// heuristic does, which is the optimistic completion D* Lite and its peers use for unknown
// space. A goal above or below the window, but within it across the ground, is reached through
// its place at the window's nearest height.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/avoid/local_grid.hpp"

namespace uav::avoid {

struct PlannerParams {
  double clearance_m = 1.0;       // body radius + obs_margin: no path nearer an occupied cell
  double soft_clearance_m = 2.5;  // between the clearance and this, a cost that pushes paths out
  double proximity_cost = 2.0;    // extra cost per metre at the clearance, falling to 0 at the soft one
  double unknown_cost = 0.5;      // extra cost per metre through unknown cells
  double vertical_cost = 2.0;     // factor on vertical movement (keep the planned altitude)
  double shortcut_margin_m = 0.3; // a line-of-sight shortcut keeps this beyond the clearance
  int max_expansions = 200000;    // bounds the time on a window full of dead ends
  // Weighted A* (Pohl 1970): f = g + w h, a path that costs at most w times the cheapest. Most
  // of a window is unknown (1 + unknown_cost per metre) and the way out of it is costed so too,
  // so with w = 1 the search expanded 75,000-82,000 of a 128,000-cell window (25-30 ms) before
  // it left it; w = 1 + unknown_cost matches the heuristic to what the unseen way costs.
  double heuristic_weight = 1.5;
  // Altitude band of the path [m, down positive]: cells below floor_down_m (the lowest altitude
  // allowed) or above ceiling_down_m (the geofence) are closed; the start is always open.
  double floor_down_m = 1e9, ceiling_down_m = -1e9;
  bool unknown_closed = false;    // only cells seen free are open (perception lost: the map alone)
  void Validate() const;          // throws std::invalid_argument naming the bad field
};

struct PlannedPath {
  bool found = false;
  std::string reason;                // why not, when not found; why it stops short, when found
  std::vector<Eigen::Vector3d> p_N;  // waypoints, the start first
  bool reaches_goal = false;         // ends at the goal (false: at the window's border toward it)
  bool stops_short = false;          // the goal is nearer an obstacle than the clearance: ends at
                                     // the nearest point to it that keeps the clearance
  double cost = 0.0;                 // of the cells' path, with the penalties
  int expansions = 0;
};

// The search's per-cell arrays, kept by a caller that plans again and again: allocated anew
// at each plan, their pages were faulted in anew each time (more than the search itself).
struct PlannerScratch {
  // What the search keeps of a cell, together: a step reads all of it at once (one cache line,
  // where four arrays cost four misses on a window of 128,000 cells).
  struct Node {
    float g;           // cost so far
    float factor;      // cost factor of entering it
    float weighted_h;  // weighted heuristic
    int parent;
  };
  std::vector<uint8_t> state;
  std::vector<Node> nodes;
  std::vector<uint64_t> open;  // the open list's heap: f's bits above the cell's
};

// `start_N` and `goal_N` in N; the grid's distances must be computed. `scratch`: arrays to
// reuse (none: the search's own).
PlannedPath PlanPath(const LocalGrid& grid, const Eigen::Vector3d& start_N, const Eigen::Vector3d& goal_N,
                     const PlannerParams& params, PlannerScratch* scratch = nullptr);

// Whether the straight segment keeps `clearance_m` from every occupied cell of the grid (unknown
// cells allowed), sampled at a third of a cell.
bool SegmentClear(const LocalGrid& grid, const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N, double clearance_m);

// Arc length along the polyline from its start to the first sample (a third of a cell apart)
// that is not observed free or nearer an occupied cell than clearance_m: how far the vehicle
// may count on. The polyline's length when all of it is. A sample within body_half_height_m of
// a cell's top or bottom face counts as observed free if the cell across that face is: the
// body spans both, and which of the two holds its centre must not decide the speed.
double SeenFreeLength(const LocalGrid& grid, const std::vector<Eigen::Vector3d>& p_N, double clearance_m,
                      double body_half_height_m);

}  // namespace uav::avoid
