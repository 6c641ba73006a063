#pragma once
// Obstacles the vehicle's stereo pair sees (thesis 3.5), its depth from motion grid (thesis 3.4)
// and its active stereo (ch. 4). The reports themselves are kept with the vehicle's telemetry
// (VehicleTelemetry::reports); reports older than these ages are not drawn (stale obstacles must
// not look current). A sensing channel that turns unhealthy, and its recovery, go to the
// messages once each.
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
  bool stereo_unhealthy = false;
  bool depth_unhealthy = false;
  bool active_stereo_unhealthy = false;
};

class ObstacleReports {
 public:
  const ObstacleReportParams& params() const { return params_; }
  void OnObstacles(VehicleObstacles& v, const std::string& vehicle_id, const Obstacles& o, double now, MessageLog& log) const;
  void OnActiveStereo(VehicleObstacles& v, const std::string& vehicle_id, const ActiveStereoReport& r, double now,
                      MessageLog& log) const;
  void OnDepthGrid(VehicleObstacles& v, const std::string& vehicle_id, const DepthGrid& g, double now, MessageLog& log) const;

 private:
  ObstacleReportParams params_;
};

}  // namespace uav::gcs
