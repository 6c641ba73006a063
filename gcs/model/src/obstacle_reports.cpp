#include "uav/gcs/obstacle_reports.hpp"

namespace uav::gcs {
namespace {

// Logs a sensing channel turning unavailable, and its recovery, once each.
void LogAvailability(bool healthy, bool* was_unhealthy, const std::string& what, const std::string& reason,
                     const std::string& vehicle_id, double now, MessageLog& log) {
  if (!healthy && !*was_unhealthy) log.Add(now, vehicle_id, what + " unavailable: " + reason, Severity::kWarning);
  if (healthy && *was_unhealthy) log.Add(now, vehicle_id, what + " available again", Severity::kInfo);
  *was_unhealthy = !healthy;
}

}  // namespace

void ObstacleReports::OnObstacles(VehicleObstacles& v, const std::string& vehicle_id, const Obstacles& o, double now,
                                  MessageLog& log) const {
  LogAvailability(o.healthy, &v.stereo_unhealthy, "stereo obstacles", o.reason, vehicle_id, now, log);
}

void ObstacleReports::OnDepthGrid(VehicleObstacles& v, const std::string& vehicle_id, const DepthGrid& g, double now,
                                  MessageLog& log) const {
  LogAvailability(g.healthy, &v.depth_unhealthy, "depth from motion", g.reason, vehicle_id, now, log);
}

void ObstacleReports::OnActiveStereo(VehicleObstacles& v, const std::string& vehicle_id, const ActiveStereoReport& r,
                                     double now, MessageLog& log) const {
  LogAvailability(r.healthy, &v.active_stereo_unhealthy, "active stereo height", r.reason, vehicle_id, now, log);
}

}  // namespace uav::gcs
