#pragma once
// Obstacle avoidance (thesis 7.2: path planning with a global and a local layer, and a reactive
// one). Three plain classes, fed plain data:
// - AvoidancePlanner (the AVD thread, 10 Hz): fuses what the vehicle senses into the 3-D map at
//   each result's capture pose, and plans from the vehicle to the task's goal on it.
// - SafetyLayer (the CTL thread, 50 Hz, in safety_layer.hpp): between every task and the
//   position controller; flies the plan and never faster than the vehicle can stop within the
//   space it has seen.
// - AvoidanceParams: the vehicle file's avd_* settings.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "uav/avoid/local_grid.hpp"
#include "uav/avoid/occupancy_map.hpp"
#include "uav/avoid/path_planner.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::avoid {

using uav::AvoidState;  // declared with the other vehicle enums (vehicle_state_t.AVOID_*)

struct AvoidanceParams {
  bool enabled = false;
  double body_radius_m = 0.5;   // the airframe's, props included
  double body_height_m = 0.5;   // the airframe's, landing gear and props included
  double margin_m = 0.5;        // obs_margin: kept beyond the body radius
  double brake_accel = 2.5;     // [m/s^2] the deceleration the speed limit counts on
  double reaction_s = 0.4;      // [s] control and attitude lag before the braking bites
  double stale_s = 0.5;         // perception older than this: brake and hold (PX4 CP's 0.5 s)
  double blind_return_s = 3.0;  // no perception this long in flight: return on the map alone
  double rate_hz = 10.0;        // replanning rate
  double window_m = 16.0;       // half width of the planning window
  double window_up_m = 4.0;     // half height of the planning window
  double grid_m = 0.4;          // planning cell
  double min_alt_m = 1.5;       // lowest altitude a detour may take
  double lookahead_m = 2.0;     // the carrot's lead along the path
  double hysteresis = 0.15;     // keep the current detour unless a new one is this much shorter
  double yaw_rate = 1.0;        // [rad/s] turning to face the way it flies (the cameras look ahead)
  double cruise_speed = 3.0;    // [m/s] ctl_speed_max_xy
  double climb_speed = 2.0;     // [m/s] ctl_speed_max_up
  double sink_speed = 1.0;      // [m/s] ctl_speed_max_down
  MapParams map;
  double clearance() const { return body_radius_m + margin_m; }
  // k where grid_m = map.resolution_m * 2^k (the octree level the planning cells are read at);
  // -1 when it is not such a multiple.
  int GridLevels() const;
  static AvoidanceParams FromParameters(const ParameterSet& p);
};

// A detected obstacle cylinder for the map.
struct MapCylinder {
  Eigen::Vector2d p_NE = Eigen::Vector2d::Zero();
  double top_down_m = 0.0, bottom_down_m = 0.0, radius_m = 0.0;
};

// A ranged wire for the map: its polyline in N, and the radius it is drawn with (the cable's
// own plus its ranging uncertainty, so the planner's clearance holds from the true cable).
struct MapWire {
  std::vector<Eigen::Vector3d> p_N;
  double radius_m = 0.1;
};

// One perception result for the map, at its capture time (the STEREO thread's per pair).
struct PerceptionUpdate {
  int64_t utime = 0;
  std::optional<RangeScan> scan;
  std::vector<MapCylinder> cylinders;
  std::vector<MapWire> wires;
  // From the stereo pair that watches the way ahead: its results keep the perception fresh (the
  // safety layer's avd_stale and the failsafe's avd_blind_return); others (depth from motion)
  // only add to the map.
  bool watches_ahead = true;
  // The watching pair's view across the ground, in the body frame: the azimuth of its optical
  // axis and half its horizontal field of view [rad] (0: not given).
  double view_azimuth_B = 0.0;
  double view_half_rad = 0.0;
};

// What the planner hands the safety layer.
struct AvoidancePlan {
  int64_t utime = 0;             // when planned
  int64_t perception_utime = 0;  // capture time of the newest result in the map (0: none yet)
  Eigen::Vector3d goal_N = Eigen::Vector3d::Zero();
  AvoidState state = AvoidState::kOff;  // kClear, kAvoiding or kNoPath
  std::string reason;                   // kNoPath: why; kAvoiding: why it stops short, if it does
  bool stops_short = false;             // the goal is nearer an obstacle than the clearance: path_N
                                        // ends at the nearest point to it that keeps the clearance
  bool map_only = false;                // planned through space seen free only (perception lost)
  std::vector<Eigen::Vector3d> path_N;  // from where the vehicle was, toward the goal
  double seen_free_m = 0.0;             // along path_N: observed free with the clearance
  double view_azimuth_B = 0.0;          // the watching pair's view, as in PerceptionUpdate
  double view_half_rad = 0.0;
  double planning_ms = 0.0;             // wall time of the window, the plan and the checks
  // The planning thread's CPU time for the same: the work itself, without the time other
  // threads (in simulation the renderer and the matchers) held the cores meanwhile.
  double planning_cpu_ms = 0.0;
  std::size_t map_cells = 0;
};

class AvoidancePlanner {
 public:
  explicit AvoidancePlanner(const AvoidanceParams& params);

  // Fuses one result (in capture order). Returns "" or a message for the operator (the map
  // reached its memory bound: far cells dropped, said once).
  std::string Add(const PerceptionUpdate& update, const Eigen::Vector3d& p_N);
  // Plans from p_N (the vehicle at utime) to goal_N. `via_N` is the task's own setpoint (a
  // mission's reference on its leg; the goal itself for goto): the task flies as it planned
  // while the straight way through it to the goal is clear. `v_N` is the vehicle's velocity:
  // the straight way is clear only if the turn onto it from where the momentum carries the
  // vehicle is clear too.
  // `map_only`: the perception is lost; only cells seen free are open, unknown ones closed.
  AvoidancePlan Plan(int64_t utime, const Eigen::Vector3d& p_N, const Eigen::Vector3d& via_N, const Eigen::Vector3d& goal_N,
                     bool map_only = false, const Eigen::Vector3d& v_N = Eigen::Vector3d::Zero());
  // New settings (a parameter changed over the link). The map is kept: its resolution and bound
  // are set at start only (std::invalid_argument when they differ or the cell does not fit).
  void SetParams(const AvoidanceParams& params);
  // Forgets the current detour (a new goal).
  void Reset() { previous_.clear(); }

  // The occupied planning cells within half_m of p_N (as of the last Plan), nearest first.
  std::vector<Eigen::Vector3f> OccupiedAround(const Eigen::Vector3d& p_N, const Eigen::Vector3d& half_m) const;
  double grid_m() const { return p_.grid_m; }
  const AvoidanceParams& params() const { return p_; }

  const OccupancyMap& map() const { return map_; }
  OccupancyMap& map() { return map_; }
  int64_t perception_utime() const { return perception_utime_; }

 private:
  // The map at the planning resolution around the vehicle, kept current from the octree's
  // changes, so that a planning window is a copy, not a walk of the tree.
  void RefreshKnown(const Eigen::Vector3d& p_N);

  AvoidanceParams p_;
  PlannerParams planner_;
  OccupancyMap map_;
  LocalGrid known_;
  LocalGrid window_;        // this replan's window (its memory kept from one to the next)
  PlannerScratch scratch_;  // the search's, likewise
  int64_t perception_utime_ = 0;
  double view_azimuth_B_ = 0.0, view_half_rad_ = 0.0;  // the watching pair's, from its results
  bool bound_announced_ = false;
  std::vector<Eigen::Vector3d> previous_;  // the detour being flown
  std::string previous_reason_;            // why it stops short of the goal, when it does
  bool previous_stops_short_ = false;
  Eigen::Vector3d previous_goal_N_ = Eigen::Vector3d::Constant(1e9);
};

// The same result or plan with every position moved by d_N (between frames of the same axes: the
// vehicle keeps its map in the odometry frame, hal::VehicleEstimate::p_O).
PerceptionUpdate Translated(PerceptionUpdate update, const Eigen::Vector3d& d_N);
AvoidancePlan Translated(AvoidancePlan plan, const Eigen::Vector3d& d_N);

// Arc length of p on the polyline (its nearest point), and the point at arc length s.
double ArcLengthOf(const std::vector<Eigen::Vector3d>& path, const Eigen::Vector3d& p);
Eigen::Vector3d PointAt(const std::vector<Eigen::Vector3d>& path, double s);
double Length(const std::vector<Eigen::Vector3d>& path);

}  // namespace uav::avoid
