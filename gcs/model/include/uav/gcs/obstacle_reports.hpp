#pragma once
// Obstacles the vehicle's stereo pair sees (thesis 3.5) and its depth from motion grid (thesis
// 3.4): each vehicle's newest obstacles_t, point_cloud_t and mono_depth_t, decoded, for the map, video and obstacle-view panels. Reports older than a set
// age are not drawn (stale obstacles must not look current). A stereo channel that turns
// unhealthy, and its recovery, go to the messages once each.
#include <optional>
#include <string>

#include "uav/gcs/message_log.hpp"
#include "uav/shared/active_stereo.hpp"
#include "uav/shared/mono_depth.hpp"
#include "uav/shared/obstacles.hpp"

namespace uav::gcs {

struct ObstacleReportParams {
  double stale_after_s = 2.0;        // [s] obstacle reports older than this are not drawn
  double cloud_stale_after_s = 5.0;  // [s] the point cloud comes at about 1 Hz
};

// Per vehicle.
struct VehicleObstacles {
  std::optional<Obstacles> obstacles;  // newest report
  double obstacles_at = -1.0;          // [s] GCS clock it arrived
  std::optional<PointCloud> cloud;
  double cloud_at = -1.0;
  bool stereo_unhealthy = false;
  std::optional<DepthGrid> depth_grid;  // depth from motion (thesis 3.4): newest grid
  double depth_grid_at = -1.0;
  bool depth_unhealthy = false;
  std::optional<ActiveStereoReport> active_stereo;  // laser dots and height (thesis ch. 4): newest
  double active_stereo_at = -1.0;
  bool active_stereo_unhealthy = false;
  const Obstacles* FreshObstacles(double now, const ObstacleReportParams& p) const {
    return obstacles && now - obstacles_at <= p.stale_after_s ? &*obstacles : nullptr;
  }
  const DepthGrid* FreshDepthGrid(double now, const ObstacleReportParams& p) const {
    return depth_grid && now - depth_grid_at <= p.stale_after_s ? &*depth_grid : nullptr;
  }
  const ActiveStereoReport* FreshActiveStereo(double now, const ObstacleReportParams& p) const {
    return active_stereo && now - active_stereo_at <= p.stale_after_s ? &*active_stereo : nullptr;
  }
  const PointCloud* FreshCloud(double now, const ObstacleReportParams& p) const {
    return cloud && now - cloud_at <= p.cloud_stale_after_s ? &*cloud : nullptr;
  }
};

class ObstacleReports {
 public:
  const ObstacleReportParams& params() const { return params_; }
  void OnObstacles(VehicleObstacles& v, const std::string& vehicle_id, Obstacles o, double now, MessageLog& log) const;
  void OnPointCloud(VehicleObstacles& v, PointCloud c, double now) const;
  void OnActiveStereo(VehicleObstacles& v, const std::string& vehicle_id, ActiveStereoReport r, double now, MessageLog& log) const;
  void OnDepthGrid(VehicleObstacles& v, const std::string& vehicle_id, DepthGrid g, double now, MessageLog& log) const;

 private:
  ObstacleReportParams params_;
};

}  // namespace uav::gcs
