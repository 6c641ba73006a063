#include "uav/shared/mavlink_px4.hpp"

namespace uav::mavlink {

const std::vector<Px4Mode>& Px4Modes() {
  using namespace px4;
  // Hold is PX4's mode for standing still and for a reposition (QGroundControl's "go to
  // location"), so idle, hover and goto all report it. Mission resumes an interrupted mission
  // where it stopped, as PX4's does; from the ground it starts it.
  static const std::vector<Px4Mode> kModes = {
      {kMainAuto, kAutoLoiter, "Hold", {Task::kIdle, Task::kHover, Task::kGoto}, "hover"},
      {kMainAuto, kAutoTakeoff, "Takeoff", {Task::kTakeoff}, "takeoff 10"},
      {kMainAuto, kAutoMission, "Mission", {Task::kMission, Task::kTrack}, "mission"},
      {kMainAuto, kAutoRtl, "Return", {Task::kReturn}, "return"},
      {kMainAuto, kAutoLand, "Land", {Task::kLand}, "land"},
      {kMainAuto, kAutoFollow, "Follow Me", {Task::kFollow}, "follow"},
      {kMainPosctl, 0, "Position", {Task::kSticks}, "sticks"},
  };
  return kModes;
}

const Px4Mode& Px4ModeOf(Task task) {
  for (const Px4Mode& m : Px4Modes())
    for (Task t : m.tasks)
      if (t == task) return m;
  return Px4Modes().front();
}

const Px4Mode* FindPx4Mode(uint8_t main_mode, uint8_t sub_mode) {
  for (const Px4Mode& m : Px4Modes())
    if (m.main_mode == main_mode && (m.main_mode != px4::kMainAuto || m.sub_mode == sub_mode)) return &m;
  return nullptr;
}

}  // namespace uav::mavlink
