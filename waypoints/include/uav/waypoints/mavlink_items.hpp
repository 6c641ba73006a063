#pragma once
// Mission items as MAVLink's mission protocol carries them (MISSION_ITEM_INT), both ways, and
// which of MAVLink's three lists (mission, fence, rally: MISSION_COUNT.mission_type) an item
// belongs to. Our missions hold all three in one list, the fence and rally items after the
// mission's; the vehicle's endpoint and the GCS's MAVLink link split and join them here.
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/mavlink_messages.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {

// MAV_MISSION_TYPE.
enum class MavMissionList : uint8_t { kMission = 0, kFence = 1, kRally = 2 };
const char* Name(MavMissionList list);  // "mission", "fence", "rally"
MavMissionList ListOf(const MissionItem& it);
// The items of `m` that travel in `list`, in order.
std::vector<MissionItem> ItemsOf(const Mission& m, MavMissionList list);

// `it` as item `seq` of `list` (positions in 1e-7 degrees; the integer frames 5 and 6 are not
// used: the message's _INT type already says so).
mavlink::MissionItemInt ToItemInt(const MissionItem& it, uint16_t seq, MavMissionList list);
// Back. What can be wrong with it: a frame we do not fly, a command we do not know, an item that
// does not belong in `list` (MISSION_ACK answers UNSUPPORTED_FRAME for the first, UNSUPPORTED
// for the others); `why` says which.
enum class ItemProblem { kNone, kFrame, kCommand, kList };
MissionItem FromItemInt(const mavlink::MissionItemInt& m, MavMissionList list, ItemProblem* problem, std::string* why);

}  // namespace uav::waypoints
