#include "uav/waypoints/mavlink_items.hpp"

#include <cmath>

namespace uav::waypoints {

const char* Name(MavMissionList list) {
  switch (list) {
    case MavMissionList::kFence: return "fence";
    case MavMissionList::kRally: return "rally";
    case MavMissionList::kMission: break;
  }
  return "mission";
}

MavMissionList ListOf(const MissionItem& it) {
  if (IsFenceItem(it.command)) return MavMissionList::kFence;
  if (IsRallyItem(it.command)) return MavMissionList::kRally;
  return MavMissionList::kMission;
}

std::vector<MissionItem> ItemsOf(const Mission& m, MavMissionList list) {
  std::vector<MissionItem> out;
  for (const MissionItem& it : m.items)
    if (ListOf(it) == list) out.push_back(it);
  return out;
}

mavlink::MissionItemInt ToItemInt(const MissionItem& it, uint16_t seq, MavMissionList list) {
  mavlink::MissionItemInt m;
  m.seq = seq;
  m.frame = static_cast<uint8_t>(it.frame);
  m.command = static_cast<uint16_t>(it.command);
  m.current = seq == 0;
  m.autocontinue = it.autocontinue;
  m.param1 = static_cast<float>(it.param[0]), m.param2 = static_cast<float>(it.param[1]);
  m.param3 = static_cast<float>(it.param[2]), m.param4 = static_cast<float>(it.param[3]);
  const bool position = it.frame != mav_frame::kMission;
  m.x = position ? static_cast<int32_t>(std::lround(it.latitude_deg * 1e7)) : static_cast<int32_t>(it.latitude_deg);
  m.y = position ? static_cast<int32_t>(std::lround(it.longitude_deg * 1e7)) : static_cast<int32_t>(it.longitude_deg);
  m.z = static_cast<float>(it.altitude_m);
  m.mission_type = static_cast<uint8_t>(list);
  return m;
}

MissionItem FromItemInt(const mavlink::MissionItemInt& m, MavMissionList list, ItemProblem* problem, std::string* why) {
  why->clear();
  *problem = ItemProblem::kNone;
  MissionItem it;
  it.command = m.command;
  // The _INT frames (5, 6) are the same frames with integer positions.
  it.frame = m.frame == 5 ? mav_frame::kGlobal : m.frame == 6 ? mav_frame::kGlobalRelativeAlt : m.frame;
  if (it.frame != mav_frame::kGlobal && it.frame != mav_frame::kMission && it.frame != mav_frame::kGlobalRelativeAlt) {
    *problem = ItemProblem::kFrame;
    *why = "frame " + std::to_string(m.frame) + " (0, 2, 3, 5 or 6 are flown)";
    return it;
  }
  if (std::string(CommandName(it.command)).empty()) {
    *problem = ItemProblem::kCommand;
    *why = "command " + std::to_string(m.command) + " is not one this vehicle flies";
    return it;
  }
  if (ListOf(it) != list) {
    *problem = ItemProblem::kList;
    *why = std::string(CommandName(it.command)) + " does not belong in a " + Name(list) + " list";
    return it;
  }
  it.param = {m.param1, m.param2, m.param3, m.param4};
  const bool position = it.frame != mav_frame::kMission;
  it.latitude_deg = position ? m.x * 1e-7 : m.x;
  it.longitude_deg = position ? m.y * 1e-7 : m.y;
  it.altitude_m = m.z;
  it.autocontinue = m.autocontinue != 0;
  return it;
}

}  // namespace uav::waypoints
