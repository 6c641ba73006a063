#include "uav/app/mission_store.hpp"

#include "uav/waypoints/mission_file.hpp"
#include "uav/waypoints/stored_paths.hpp"

namespace uav::app {

MissionStore::MissionStore(std::string paths_dir, const GeodeticPoint& home, double max_speed_m_s)
    : paths_dir_(std::move(paths_dir)), frame_(home), max_speed_m_s_(max_speed_m_s) {}

std::optional<std::vector<waypoints::MissionStep>> MissionStore::StoredPath(int n, std::string* error) {
  try {
    return waypoints::CompileMission(waypoints::LoadStoredPath(paths_dir_, n), frame_, max_speed_m_s_);
  } catch (const std::exception& e) {
    *error = "path " + std::to_string(n) + ": " + e.what();
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
    auto steps = waypoints::CompileMission(m, frame_, max_speed_m_s_);
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

}  // namespace uav::app
