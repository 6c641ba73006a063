#pragma once
// Where the task manager gets "track N" and "mission" from: stored path files, and the last
// mission the GCS uploaded (checked and compiled when it arrives, so "mission" never finds a
// mission it cannot fly). Thread-safe: CMM stores uploads, CTL reads them.
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "uav/control/task_manager.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::runtime {

class MissionStore : public control::MissionSource {
 public:
  // Missions are compiled in the NED frame at `home` and checked against the vehicle's limits
  // (its speed, ceiling, range): `limits` until SetLimitsSource gives the live ones.
  MissionStore(std::string paths_dir, const GeodeticPoint& home, const waypoints::VehicleLimits& limits);
  void SetLimitsSource(std::function<waypoints::VehicleLimits()> source);

  std::optional<std::vector<waypoints::MissionStep>> StoredPath(int n, std::string* error) override;
  std::optional<std::vector<waypoints::MissionStep>> UploadedMission(std::string* error) override;
  int64_t upload_count() override;
  waypoints::Geofence UploadedGeofence() override;

  // Checks and compiles an uploaded mission; on success it replaces the stored one and ""
  // is returned, else the reason naming the item (and the stored mission is unchanged).
  std::string AcceptUpload(const waypoints::Mission& m);

  const GeodeticPoint& home() const { return frame_.home(); }

 private:
  std::string paths_dir_;
  LocalNedFrame frame_;
  waypoints::VehicleLimits Limits();
  std::mutex mutex_;
  waypoints::VehicleLimits limits_;
  std::function<waypoints::VehicleLimits()> limits_source_;
  std::optional<std::vector<waypoints::MissionStep>> uploaded_;
  int64_t upload_count_ = 0;
  waypoints::Geofence geofence_;
};

}  // namespace uav::runtime
