#pragma once
// Conversions between the mission transfer structs and their LCM messages. Included only by the
// link code on each side (messages stay at the edges).
#include "uav/waypoints/mission_transfer.hpp"
#include "uavmsg/mission_ack_t.hpp"
#include "uavmsg/mission_upload_t.hpp"

namespace uav::waypoints {

uavmsg::mission_upload_t ToMessage(const MissionChunk& c);
// Throws std::invalid_argument naming the field when the message is inconsistent (num_items
// over kItemsPerChunk, negative indices).
MissionChunk FromMessage(const uavmsg::mission_upload_t& m);

uavmsg::mission_ack_t ToMessage(const MissionUploadAck& a);
MissionUploadAck FromMessage(const uavmsg::mission_ack_t& m);

}  // namespace uav::waypoints
