#pragma once
// Obstacle avoidance's plan and map (thesis 7.2) as plain data: what the vehicle's AVD thread
// publishes (avoidance_t, 2 Hz while a task travels) and the GCS draws on its map and in the
// obstacle view. Decoded once, here.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/signals.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav {

struct AvoidanceReport {
  int64_t utime = 0;                            // [us] vehicle clock of the plan
  AvoidState state = AvoidState::kClear;        // the planner's: clear, avoiding or no path
  std::string reason;                           // no path: why
  Eigen::Vector3d goal_N = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> path_N;          // from where the vehicle was, toward the goal
  double seen_free_m = 0.0;                     // along path_N: seen free with the clearance (committed)
  double planning_ms = 0.0;
  int64_t map_cells = 0;                        // nodes in the onboard map
  Eigen::Vector3d origin_N = Eigen::Vector3d::Zero();  // the vehicle when planned (cells are sent relative to it)
  double cell_m = 0.4;                          // edge of the occupied cells
  std::vector<Eigen::Vector3f> occupied_N;      // occupied cell centres around the vehicle, nearest first

  double PathLength() const;
  // The committed part of the path: from its start to seen_free_m along it.
  std::vector<Eigen::Vector3d> Committed() const;
};

// Its signals (path and committed lengths, the map's size, the planning time): group "AVOID".
template <>
struct ReportSignals<AvoidanceReport> {
  static constexpr std::string_view kGroup = "AVOID";
  static const std::vector<Signal<AvoidanceReport>>& Table();
};

}  // namespace uav
