#include "uav/wire/messages.hpp"

#include <stdexcept>

namespace uav {

namespace {
void RequireJpeg(int32_t size, const std::vector<uint8_t>& jpeg, int max_bytes, const char* type) {
  if (size < 0 || size > max_bytes || static_cast<std::size_t>(size) != jpeg.size())
    throw std::invalid_argument(std::string(type) + ": size " + std::to_string(size) + " does not match its " +
                                std::to_string(jpeg.size()) + " JPEG bytes (at most " + std::to_string(max_bytes) + ")");
}
}  // namespace

VideoFrame FromMessage(const uavmsg::video_frame_t& m) {
  RequireJpeg(m.size, m.jpeg, uavmsg::video_frame_t::MAX_JPEG_BYTES, "video_frame_t");
  return {m.utime, m.camera, m.width, m.height, m.source_width, m.source_height, m.jpeg};
}

uavmsg::video_frame_t ToMessage(const VideoFrame& f) {
  uavmsg::video_frame_t m;
  m.utime = f.utime;
  m.camera = f.camera;
  m.width = static_cast<int16_t>(f.width);
  m.height = static_cast<int16_t>(f.height);
  m.source_width = static_cast<int16_t>(f.source_width);
  m.source_height = static_cast<int16_t>(f.source_height);
  m.size = static_cast<int32_t>(f.jpeg.size());
  m.jpeg = f.jpeg;
  return m;
}

MapTile FromMessage(const uavmsg::map_tile_t& m) {
  RequireJpeg(m.size, m.jpeg, uavmsg::map_tile_t::MAX_JPEG_BYTES, "map_tile_t");
  return {m.map_id, m.tile_x, m.tile_y, m.tile_px, m.gsd_m, m.origin_north_m, m.origin_east_m, m.georeferenced != 0, m.jpeg};
}

uavmsg::map_tile_t ToMessage(const MapTile& t) {
  uavmsg::map_tile_t m;
  m.map_id = t.map_id;
  m.tile_x = t.tile_x;
  m.tile_y = t.tile_y;
  m.tile_px = static_cast<int16_t>(t.tile_px);
  m.gsd_m = t.gsd_m;
  m.origin_north_m = t.origin_north_m;
  m.origin_east_m = t.origin_east_m;
  m.georeferenced = t.georeferenced;
  m.size = static_cast<int32_t>(t.jpeg.size());
  m.jpeg = t.jpeg;
  return m;
}

CommandAck FromMessage(const uavmsg::command_ack_t& m) {
  const auto result = CommandResultFromWire(m.result);
  if (!result) throw std::invalid_argument("command_ack_t: unknown command result " + std::to_string(m.result));
  return {m.source, m.command_seq, m.command, *result, m.progress_percent, m.reason};
}

uavmsg::command_ack_t ToMessage(const CommandAck& a) {
  uavmsg::command_ack_t m;
  m.source = a.source;
  m.command_seq = a.command_seq;
  m.command = a.command;
  m.result = static_cast<int8_t>(a.result);
  m.progress_percent = static_cast<int8_t>(a.percent);
  m.reason = a.reason;
  return m;
}

}  // namespace uav
