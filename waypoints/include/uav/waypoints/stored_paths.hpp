#pragma once
// Stored paths for "track <N>" (thesis 2.3.2): QGC WPL 110 files named track_<N>.waypoints in a
// directory (waypoints/paths in the source tree), the same format the survey planner exports.
#include <string>

#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {

constexpr const char* kStoredPathsDir = UAV_STORED_PATHS_DIR;

std::string StoredPathFile(const std::string& dir, int n);
// Throws MissionFileError naming the file when it is missing or invalid.
Mission LoadStoredPath(const std::string& dir, int n);

}  // namespace uav::waypoints
