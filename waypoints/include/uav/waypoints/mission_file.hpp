#pragma once
// Mission files: QGroundControl .plan (JSON) and QGC WPL 110 (tab-separated text).
// Reading is all or nothing: a mission comes back complete and valid, or MissionFileError names
// the file, the field or line, and what was wrong.
#include <stdexcept>
#include <string>

#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {

class MissionFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// `origin` names the text in messages (a file name).
Mission ParsePlan(const std::string& text, const std::string& origin);
std::string FormatPlan(const Mission& m);

// Item 0 of a WPL file is home (QGroundControl's convention); the survey definition is not part
// of the format and is not kept.
Mission ParseWpl(const std::string& text, const std::string& origin);
std::string FormatWpl(const Mission& m);

// By extension: ".plan" or ".waypoints"/".txt" (WPL). Writing goes to a temporary name in the
// same directory and is renamed over the target, so a crash never leaves half a file.
Mission ReadMissionFile(const std::string& path);
void WriteMissionFile(const std::string& path, const Mission& m);

}  // namespace uav::waypoints
