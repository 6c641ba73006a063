#include "uav/gcs/obstacle_reports.hpp"

namespace uav::gcs {

void ObstacleReports::OnObstacles(VehicleObstacles& v, const std::string& vehicle_id, Obstacles o, double now,
                                  MessageLog& log) const {
  if (!o.healthy && !v.stereo_unhealthy) log.Add(now, vehicle_id, "stereo obstacles unavailable: " + o.reason, Severity::kWarning);
  if (o.healthy && v.stereo_unhealthy) log.Add(now, vehicle_id, "stereo obstacles available again", Severity::kInfo);
  v.stereo_unhealthy = !o.healthy;
  v.obstacles = std::move(o);
  v.obstacles_at = now;
}

void ObstacleReports::OnDepthGrid(VehicleObstacles& v, const std::string& vehicle_id, DepthGrid g, double now,
                                  MessageLog& log) const {
  if (!g.healthy && !v.depth_unhealthy) log.Add(now, vehicle_id, "depth from motion unavailable: " + g.reason, Severity::kWarning);
  if (g.healthy && v.depth_unhealthy) log.Add(now, vehicle_id, "depth from motion available again", Severity::kInfo);
  v.depth_unhealthy = !g.healthy;
  v.depth_grid = std::move(g);
  v.depth_grid_at = now;
}

void ObstacleReports::OnPointCloud(VehicleObstacles& v, PointCloud c, double now) const {
  v.cloud = std::move(c);
  v.cloud_at = now;
}

}  // namespace uav::gcs
