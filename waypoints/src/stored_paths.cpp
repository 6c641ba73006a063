#include "uav/waypoints/stored_paths.hpp"

#include "uav/waypoints/mission_file.hpp"

namespace uav::waypoints {

std::string StoredPathFile(const std::string& dir, int n) {
  return dir + "/track_" + std::to_string(n) + ".waypoints";
}

Mission LoadStoredPath(const std::string& dir, int n) { return ReadMissionFile(StoredPathFile(dir, n)); }

}  // namespace uav::waypoints
