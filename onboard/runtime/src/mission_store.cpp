#include "uav/runtime/mission_store.hpp"

#include "uav/waypoints/mission_file.hpp"
#include "uav/waypoints/stored_paths.hpp"

namespace uav::runtime {

MissionStore::MissionStore(std::string paths_dir, const GeodeticPoint& home, const waypoints::VehicleLimits& limits)
    : paths_dir_(std::move(paths_dir)), frame_(home), limits_(limits) {}

void MissionStore::SetLimitsSource(std::function<waypoints::VehicleLimits()> source) {
  std::lock_guard<std::mutex> lock(mutex_);
  limits_source_ = std::move(source);
}

waypoints::VehicleLimits MissionStore::Limits() {
  std::function<waypoints::VehicleLimits()> source;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!limits_source_) return limits_;
    source = limits_source_;
  }
  return source();
}

std::optional<std::vector<waypoints::MissionStep>> MissionStore::StoredPath(int n, std::string* error) {
  try {
    return waypoints::CompileMission(waypoints::LoadStoredPath(paths_dir_, n), frame_, Limits());
  } catch (const std::exception& e) {
    // The refusal goes to the GCS: the file by its name, not where it lies on the vehicle.
    std::string why = e.what();
    for (std::size_t at; !paths_dir_.empty() && (at = why.find(paths_dir_ + "/")) != std::string::npos;)
      why.erase(at, paths_dir_.size() + 1);
    *error = "path " + std::to_string(n) + ": " + why;
    return std::nullopt;
  }
}

std::optional<std::vector<waypoints::MissionStep>> MissionStore::UploadedMission(std::string* error) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!uploaded_) *error = "no mission uploaded";
  return uploaded_;
}

int64_t MissionStore::upload_count() {
  std::lock_guard<std::mutex> lock(mutex_);
  return upload_count_;
}

waypoints::Geofence MissionStore::UploadedGeofence() {
  std::lock_guard<std::mutex> lock(mutex_);
  return geofence_;
}

std::string MissionStore::AcceptUpload(const waypoints::Mission& m) {
  try {
    auto steps = waypoints::CompileMission(m, frame_, Limits());
    auto fence = waypoints::CompileGeofence(m, frame_);
    std::lock_guard<std::mutex> lock(mutex_);
    uploaded_ = std::move(steps);
    geofence_ = std::move(fence);
    ++upload_count_;
    return "";
  } catch (const std::exception& e) {
    return e.what();
  }
}

}  // namespace uav::runtime
