#pragma once
// Power lines the vehicle sees (thesis 3.6; the newest power_lines_t is kept with the vehicle's
// telemetry, VehicleTelemetry::reports): the operator's warning when a ranged wire comes closer than a
// set distance (status bar and messages). The warning clears with a margin, so a wire hovering
// at the threshold does not flood the messages, and when the reports stop (stale data must not
// look like clear air, nor keep a warning up forever). Ranged wires are also kept, sampled once a
// second, for the map.
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/gcs/message_log.hpp"
#include "uav/shared/power_lines.hpp"

namespace uav::gcs {

struct WireWarningParams {
  double warn_distance_m = 15.0;  // [m] a ranged wire nearer than this raises the warning
  double clear_margin = 1.2;      // ... which clears beyond warn_distance_m * clear_margin
  double stale_after_s = 2.0;     // [s] reports older than this no longer count
  double map_period_s = 1.0;      // [s] ranged wires are kept for the map once per period ...
  std::size_t map_capacity = 400;  // ... up to this many polylines (the oldest go first)
  // Throws std::invalid_argument naming the bad field.
  void Validate() const;
};

// Per vehicle.
struct VehiclePowerLines {
  bool wire_warning = false;
  // Ranged wires seen during the flight (NED polylines), for the map: what is out of view now
  // is still there.
  std::deque<std::vector<Eigen::Vector3d>> wire_map;
  double wire_map_at = -1.0;  // [s] GCS clock of the last addition
};

class WireWarnings {
 public:
  WireWarningParams& params() { return params_; }
  const WireWarningParams& params() const { return params_; }
  void OnPowerLines(VehiclePowerLines& v, const std::string& vehicle_id, const PowerLines& lines, double now,
                    MessageLog& log) const;
  // Clears the warning of a vehicle whose reports went stale.
  // `last_report_at`: when the newest power_lines_t came (GCS clock).
  void Tick(VehiclePowerLines& v, const std::string& vehicle_id, double last_report_at, double now, MessageLog& log) const;

 private:
  WireWarningParams params_;
};

}  // namespace uav::gcs
