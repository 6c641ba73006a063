#include "uav/gcs/power_line_warnings.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace uav::gcs {

void WireWarningParams::Validate() const {
  if (!(std::isfinite(warn_distance_m) && warn_distance_m > 0 && warn_distance_m <= 500))
    throw std::invalid_argument("wire warning distance must be in (0, 500] m");
  if (!(std::isfinite(clear_margin) && clear_margin >= 1 && clear_margin <= 3))
    throw std::invalid_argument("wire warning clear margin must be in [1, 3]");
  if (!(std::isfinite(stale_after_s) && stale_after_s > 0 && stale_after_s <= 60))
    throw std::invalid_argument("wire report staleness must be in (0, 60] s");
  if (!(std::isfinite(map_period_s) && map_period_s >= 0)) throw std::invalid_argument("wire map period must be >= 0 s");
  if (map_capacity < 1) throw std::invalid_argument("wire map capacity must be at least 1");
}

void WireWarnings::OnPowerLines(VehiclePowerLines& v, const std::string& vehicle_id, const PowerLines& lines, double now,
                                MessageLog& log) const {
  const double nearest = lines.nearest_m;
  if (v.wire_map_at < 0 || now - v.wire_map_at >= params_.map_period_s) {
    bool added = false;
    for (const PowerLine& w : lines.wires)
      if (w.ranged()) v.wire_map.push_back(w.p_N), added = true;
    while (v.wire_map.size() > params_.map_capacity) v.wire_map.pop_front();
    if (added) v.wire_map_at = now;
  }
  const bool near = nearest >= 0 && nearest < params_.warn_distance_m;
  const bool clear = nearest < 0 || nearest > params_.warn_distance_m * params_.clear_margin;
  char text[128];
  if (near && !v.wire_warning) {
    v.wire_warning = true;
    std::snprintf(text, sizeof text, "power line %.1f m away (warning under %.0f m)", nearest, params_.warn_distance_m);
    log.Add(now, vehicle_id, text, Severity::kWarning);
  } else if (clear && v.wire_warning) {
    v.wire_warning = false;
    if (nearest < 0) std::snprintf(text, sizeof text, "power lines clear: none ranged");
    else std::snprintf(text, sizeof text, "power lines clear: nearest %.1f m", nearest);
    log.Add(now, vehicle_id, text, Severity::kInfo);
  }
}

void WireWarnings::Tick(VehiclePowerLines& v, const std::string& vehicle_id, double last_report_at, double now,
                        MessageLog& log) const {
  if (v.wire_warning && now - last_report_at > params_.stale_after_s) {
    v.wire_warning = false;
    log.Add(now, vehicle_id, "power-line reports stopped: wire warning no longer current", Severity::kWarning);
  }
}

}  // namespace uav::gcs
