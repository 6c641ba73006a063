#include "uav/waypoints/mission_messages.hpp"

#include <stdexcept>
#include <string>

namespace uav::waypoints {

uavmsg::mission_upload_t ToMessage(const MissionChunk& c) {
  uavmsg::mission_upload_t m{};
  m.upload_id = c.upload_id;
  m.total_items = c.total_items;
  m.first_index = c.first_index;
  m.digest = static_cast<int64_t>(c.digest);
  m.home_latitude_deg = c.home.latitude_deg;
  m.home_longitude_deg = c.home.longitude_deg;
  m.home_altitude_m = c.home.altitude_m;
  m.cruise_speed_m_s = c.cruise_speed_m_s;
  m.num_items = static_cast<int32_t>(c.items.size());
  for (const auto& it : c.items) {
    uavmsg::mission_item_t mi{};
    mi.command = it.command;
    mi.frame = static_cast<int8_t>(it.frame);
    for (int k = 0; k < 4; ++k) mi.param[k] = it.param[k];
    mi.latitude_deg = it.latitude_deg;
    mi.longitude_deg = it.longitude_deg;
    mi.altitude_m = it.altitude_m;
    mi.autocontinue = it.autocontinue;
    m.items.push_back(mi);
  }
  return m;
}

MissionChunk FromMessage(const uavmsg::mission_upload_t& m) {
  if (m.num_items < 0 || m.num_items > kItemsPerChunk)
    throw std::invalid_argument("mission_upload_t.num_items = " + std::to_string(m.num_items) +
                                " is outside [0, " + std::to_string(kItemsPerChunk) + "]");
  if (m.first_index < 0 || m.total_items < 0)
    throw std::invalid_argument("mission_upload_t: negative first_index or total_items");
  MissionChunk c;
  c.upload_id = m.upload_id;
  c.total_items = m.total_items;
  c.first_index = m.first_index;
  c.digest = static_cast<uint64_t>(m.digest);
  c.home = {m.home_latitude_deg, m.home_longitude_deg, m.home_altitude_m};
  c.cruise_speed_m_s = m.cruise_speed_m_s;
  for (const auto& mi : m.items) {
    MissionItem it;
    it.command = mi.command;
    it.frame = mi.frame;
    for (int k = 0; k < 4; ++k) it.param[k] = mi.param[k];
    it.latitude_deg = mi.latitude_deg;
    it.longitude_deg = mi.longitude_deg;
    it.altitude_m = mi.altitude_m;
    it.autocontinue = mi.autocontinue;
    c.items.push_back(it);
  }
  return c;
}

uavmsg::mission_ack_t ToMessage(const MissionUploadAck& a) {
  uavmsg::mission_ack_t m{};
  m.upload_id = a.upload_id;
  m.received_items = a.received_items;
  m.total_items = a.total_items;
  m.result = a.result == MissionUploadAck::Result::kAccepted   ? uavmsg::mission_ack_t::RESULT_ACCEPTED
             : a.result == MissionUploadAck::Result::kRejected ? uavmsg::mission_ack_t::RESULT_REJECTED
                                                               : uavmsg::mission_ack_t::RESULT_IN_PROGRESS;
  m.reason = a.reason;
  m.digest = static_cast<int64_t>(a.digest);
  return m;
}

MissionUploadAck FromMessage(const uavmsg::mission_ack_t& m) {
  MissionUploadAck a;
  a.upload_id = m.upload_id;
  a.received_items = m.received_items;
  a.total_items = m.total_items;
  a.result = m.result == uavmsg::mission_ack_t::RESULT_ACCEPTED   ? MissionUploadAck::Result::kAccepted
             : m.result == uavmsg::mission_ack_t::RESULT_REJECTED ? MissionUploadAck::Result::kRejected
                                                                  : MissionUploadAck::Result::kInProgress;
  a.reason = m.reason;
  a.digest = static_cast<uint64_t>(m.digest);
  return a;
}

}  // namespace uav::waypoints
