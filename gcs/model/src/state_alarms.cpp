#include "uav/gcs/state_alarms.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace uav::gcs {

StateLimits StateLimits::From(const ParameterTable* table, VehicleType type) {
  StateLimits l;
  l.check_tilt = type != VehicleType::kTailSitter;
  if (!table) return l;
  if (const ParameterEntry* tilt = table->Find("ctl_tilt_max")) l.tilt_max_rad = 1.5 * tilt->value;
  // The fastest it flies: its speed limit, or a tail-sitter's cruise on the wing.
  double speed = 0.0;
  if (const ParameterEntry* e = table->Find("ctl_speed_max_xy")) speed = e->value;
  if (const ParameterEntry* e = table->Find("ts_cruise_speed"); e && type == VehicleType::kTailSitter)
    speed = std::max(speed, e->value);
  if (speed > 0.0) l.speed_max_m_s = 3.0 * speed;
  return l;
}

std::vector<StateAlarm> AbsurdState(const VehicleState* previous, const VehicleState& now, const StateLimits& limits) {
  std::vector<StateAlarm> out;
  char buf[160];
  if (now.altitude() < StateLimits::kBelowHome) {
    std::snprintf(buf, sizeof buf, "height %.1f m: far below home (the estimate has gone wrong, or a crash)", now.altitude());
    out.push_back({"height", buf});
  }
  if (limits.check_tilt) {
    const double roll = std::abs(now.euler.phi), pitch = std::abs(now.euler.theta);
    if (std::max(roll, pitch) > limits.tilt_max_rad) {
      std::snprintf(buf, sizeof buf, "%s %.0f deg: past the vehicle's limits (%.0f deg)", roll >= pitch ? "roll" : "pitch",
                    std::max(roll, pitch) * 180 / M_PI, limits.tilt_max_rad * 180 / M_PI);
      out.push_back({"tilt", buf});
    }
  }
  if (previous && now.utime > previous->utime) {
    const double dt = (now.utime - previous->utime) * 1e-6;
    const double d = (now.p_N - previous->p_N).norm();
    if (dt <= 1.0 && d > 5.0 && d / dt > 50.0) {
      std::snprintf(buf, sizeof buf, "the position estimate jumped %.0f m in %.2f s", d, dt);
      out.push_back({"jump", buf});
    }
  }
  if (now.ground_speed() > limits.speed_max_m_s) {
    std::snprintf(buf, sizeof buf, "ground speed %.1f m/s: over three times what the vehicle flies", now.ground_speed());
    out.push_back({"speed", buf});
  }
  return out;
}

std::vector<std::pair<std::string, Severity>> StateAlarms::Update(const std::vector<StateAlarm>& alarms) {
  std::vector<std::pair<std::string, Severity>> said;
  std::set<std::string> now;
  for (const StateAlarm& a : alarms) {
    now.insert(a.key);
    if (active_.emplace(a.key, a.text).second) said.push_back({"ALARM: " + a.text, Severity::kError});
  }
  for (auto it = active_.begin(); it != active_.end();) {
    if (now.count(it->first)) {
      ++it;
      continue;
    }
    said.push_back({"alarm over: " + it->second, Severity::kInfo});
    it = active_.erase(it);
  }
  return said;
}

}  // namespace uav::gcs
