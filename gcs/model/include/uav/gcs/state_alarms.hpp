#pragma once
// Alarms on a state no vehicle can really be in (QGroundControl and Mission Planner warn when the
// estimator has gone bad): a height far below home, a roll or pitch past the vehicle's limits, a
// jump of the position estimate, a ground speed far past the vehicle's. The vehicle's own crash
// detection may not see them (its estimate is what went wrong), so the operator is told. Each
// alarm is said once when it starts (an error: spoken) and once when it is over.
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "uav/shared/parameter_table.hpp"
#include "uav/shared/vehicle_enums.hpp"
#include "uav/shared/vehicle_state.hpp"

namespace uav::gcs {

struct StateLimits {
  static constexpr double kBelowHome = -3.0;  // [m] height above home below this: absurd
  double tilt_max_rad = 45.0 * M_PI / 180;    // roll or pitch beyond 1.5 x the vehicle's ctl_tilt_max
  double speed_max_m_s = 15.0;                // ground speed beyond 3 x its speed limit (or cruise)
  bool check_tilt = true;                     // a tail-sitter's attitudes span 90 degrees
  // From the vehicle's parameter table (nullptr: not received yet, generic limits).
  static StateLimits From(const ParameterTable* table, VehicleType type);
};

struct StateAlarm {
  std::string key;   // "height", "tilt", "jump", "speed"
  std::string text;  // "height -14.5 m: far below home"
};

// What is absurd about `now` (and about the step from `previous`, when given).
std::vector<StateAlarm> AbsurdState(const VehicleState* previous, const VehicleState& now, const StateLimits& limits);

class StateAlarms {
 public:
  // The sentences to log for the alarms that began (errors) or ended (info) with this state.
  std::vector<std::pair<std::string, Severity>> Update(const std::vector<StateAlarm>& alarms);

 private:
  std::map<std::string, std::string> active_;  // key -> the text it began with
};

}  // namespace uav::gcs
