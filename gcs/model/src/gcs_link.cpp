#include "uav/gcs/gcs_link.hpp"

#include <map>

#include "uav/shared/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/time.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/video_frame_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"

namespace uav::gcs {
namespace {

std::string VehicleOf(const std::string& channel) { return channel.substr(0, channel.find('/')); }

const char* ResultName(int8_t r) {
  switch (r) {
    case uavmsg::command_ack_t::RESULT_ACCEPTED: return "accepted";
    case uavmsg::command_ack_t::RESULT_REJECTED: return "rejected";
    case uavmsg::command_ack_t::RESULT_IN_PROGRESS: return "in_progress";
    case uavmsg::command_ack_t::RESULT_COMPLETED: return "completed";
    case uavmsg::command_ack_t::RESULT_FAILED: return "failed";
  }
  return "unknown";
}

TelemetrySample Flatten(const uavmsg::vehicle_state_t& m) {
  TelemetrySample s{m.header.vehicle_id, "STATE", m.header.seq, m.utime * 1e-6, {}};
  s.values = {{"x", m.x}, {"y", m.y}, {"z", m.z}, {"alt", -m.z},
              {"u", m.u}, {"v", m.v}, {"w", m.w},
              {"phi", m.phi}, {"theta", m.theta}, {"psi", m.psi},
              {"p", m.p}, {"q", m.q}, {"r", m.r},
              {"acx", m.acx}, {"acy", m.acy}, {"acz", m.acz},
              {"gps_lat", m.gps_latitude_deg}, {"gps_lon", m.gps_longitude_deg},
              {"gps_alt", m.gps_altitude_m}, {"gps_fix", m.gps_fix}, {"gps_sats", m.gps_satellites},
              {"M1", m.rotor_input[0]}, {"M2", m.rotor_input[1]},
              {"M3", m.rotor_input[2]}, {"M4", m.rotor_input[3]},
              {"Ua", m.servo_input[0]}, {"Ue", m.servo_input[1]},
              {"Uth", m.servo_input[2]}, {"Ur", m.servo_input[3]},
              {"mode", m.flight_mode}, {"task", m.task}, {"failsafe", m.failsafe}, {"armed", m.armed ? 1.0 : 0.0},
              {"landed", m.landed ? 1.0 : 0.0},
              {"battery_v", m.battery_voltage_v}, {"battery_remaining", m.battery_remaining},
              {"mission_item", m.mission_item}, {"capturing", m.capturing ? 1.0 : 0.0},
              {"obstacle_range", m.obstacle_range_m},
              {"fence_radius", m.fence_radius_m}, {"fence_alt", m.fence_alt_m},
              {"home_lat", m.home_latitude_deg}, {"home_lon", m.home_longitude_deg},
              {"home_alt", m.home_altitude_m}};
  return s;
}

}  // namespace

struct GcsLink::Impl {
  Impl(const std::string& url, GcsModel& m) : bus(url), model(m) {}
  bool Accept(const std::string& channel, const std::string& header_vehicle) {
    if (VehicleOf(channel) == header_vehicle && IsValidVehicleId(header_vehicle)) return true;
    ++dropped;
    return false;
  }
  Bus bus;
  GcsModel& model;
  double now = 0.0;
  double last_heartbeat = -1e9;
  int64_t heartbeat_seq = 0;
  int64_t command_msg_seq = 0;
  int64_t upload_msg_seq = 0;
  int64_t file_request_seq = 0;
  int64_t track_target_seq = 0;
  int64_t dropped = 0;
};

GcsLink::GcsLink(const std::string& lcm_url, GcsModel& model)
    : impl_(std::make_unique<Impl>(lcm_url, model)) {
  Impl* im = impl_.get();
  im->bus.Subscribe<uavmsg::heartbeat_t>(
      "[^/]+/HEARTBEAT", [im](const std::string& ch, const uavmsg::heartbeat_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id) ||
            m.source_kind != uavmsg::heartbeat_t::SOURCE_VEHICLE)
          return;
        im->model.OnHeartbeat(m.header.vehicle_id, m.header.seq, m.task, m.armed, im->now);
      });
  im->bus.Subscribe<uavmsg::vehicle_state_t>(
      "[^/]+/STATE", [im](const std::string& ch, const uavmsg::vehicle_state_t& m) {
        if (im->Accept(ch, m.header.vehicle_id)) im->model.OnTelemetry(Flatten(m), im->now);
      });
  im->bus.Subscribe<uavmsg::command_ack_t>(
      "[^/]+/COMMAND_ACK", [im](const std::string& ch, const uavmsg::command_ack_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        im->model.OnAck(m.header.vehicle_id, m.source,
                        {m.command_seq, m.command, ResultName(m.result), m.progress_percent, m.reason},
                        im->now);
      });
  im->bus.Subscribe<uavmsg::mission_ack_t>(
      "[^/]+/MISSION_ACK", [im](const std::string& ch, const uavmsg::mission_ack_t& m) {
        if (im->Accept(ch, m.header.vehicle_id))
          im->model.OnMissionAck(m.header.vehicle_id, m.source, waypoints::FromMessage(m), im->now);
      });
  im->bus.Subscribe<uavmsg::video_frame_t>(
      "[^/]+/VIDEO", [im](const std::string& ch, const uavmsg::video_frame_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        VideoFrameIn f;
        f.utime = m.utime;
        f.camera = m.camera;
        f.width = m.width;
        f.height = m.height;
        f.source_width = m.source_width;
        f.source_height = m.source_height;
        f.jpeg = m.jpeg;
        im->model.OnVideoFrame(m.header.vehicle_id, f, im->now);
      });
  im->bus.Subscribe<uavmsg::file_offer_t>(
      "[^/]+/FILE_OFFER", [im](const std::string& ch, const uavmsg::file_offer_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        FileOffer o;
        o.transfer_id = m.transfer_id;
        o.name = m.name;
        o.size = m.size;
        o.chunk_bytes = m.chunk_bytes;
        o.chunks = m.chunks;
        o.sha256 = m.sha256;
        im->model.OnFileOffer(m.header.vehicle_id, o, im->now);
      });
  im->bus.Subscribe<uavmsg::file_chunk_t>(
      "[^/]+/FILE_CHUNK", [im](const std::string& ch, const uavmsg::file_chunk_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        FileChunk c;
        c.transfer_id = m.transfer_id;
        c.index = m.index;
        c.crc32 = static_cast<uint32_t>(m.crc32);
        c.data = m.data;
        im->model.OnFileChunk(m.header.vehicle_id, c, im->now);
      });
  im->bus.Subscribe<uavmsg::map_tile_t>(
      "[^/]+/MAP_TILE", [im](const std::string& ch, const uavmsg::map_tile_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        MapTileIn t;
        t.map_id = m.map_id;
        t.tile_x = m.tile_x;
        t.tile_y = m.tile_y;
        t.tile_px = m.tile_px;
        t.gsd_m = m.gsd_m;
        t.origin_north_m = m.origin_north_m;
        t.origin_east_m = m.origin_east_m;
        t.georeferenced = m.georeferenced;
        t.jpeg = m.jpeg;
        im->model.OnMapTile(m.header.vehicle_id, t, im->now);
      });
  im->bus.Subscribe<uavmsg::track_status_t>(
      "[^/]+/TRACK_STATUS", [im](const std::string& ch, const uavmsg::track_status_t& m) {
        if (!im->Accept(ch, m.header.vehicle_id)) return;
        TrackStatus st;
        st.utime = m.utime;
        st.seq = m.header.seq;
        st.target_seq = m.target_seq;
        st.state = static_cast<TrackStatus::State>(m.state);
        st.center_x = m.center_x;
        st.center_y = m.center_y;
        st.width = m.width;
        st.height = m.height;
        st.angle_rad = m.angle_rad;
        im->model.OnTrackStatus(m.header.vehicle_id, st, im->now);
      });
  im->bus.Subscribe<uavmsg::status_text_t>(
      "[^/]+/STATUS_TEXT", [im](const std::string& ch, const uavmsg::status_text_t& m) {
        if (im->Accept(ch, m.header.vehicle_id))
          im->model.OnStatusText(m.header.vehicle_id, m.severity, m.text, im->now);
      });
}

GcsLink::~GcsLink() = default;

int64_t GcsLink::dropped_messages() const { return impl_->dropped + impl_->bus.DecodeErrors(); }

void GcsLink::Poll(int timeout_ms, double now) {
  Impl& im = *impl_;
  im.now = now;
  im.bus.Handle(timeout_ms);
  for (const auto& c : im.model.TakeOutgoing()) {
    uavmsg::command_t m;
    m.utime = WallTimeMicros();
    m.header = {c.vehicle_id, ++im.command_msg_seq};
    m.source = im.model.gcs_name();
    m.command_seq = c.command_seq;
    m.text = c.text;
    im.bus.Publish(Channel(c.vehicle_id, Topic::kCommand), m);
  }
  for (const auto& c : im.model.TakeOutgoingChunks()) {
    uavmsg::mission_upload_t m = waypoints::ToMessage(c.chunk);
    m.utime = WallTimeMicros();
    m.header = {c.vehicle_id, ++im.upload_msg_seq};
    m.source = im.model.gcs_name();
    im.bus.Publish(Channel(c.vehicle_id, Topic::kMissionUpload), m);
  }
  for (const auto& r : im.model.TakeOutgoingFileRequests()) {
    uavmsg::file_request_t m;
    m.utime = WallTimeMicros();
    m.header = {r.vehicle_id, ++im.file_request_seq};
    m.source = im.model.gcs_name();
    m.transfer_id = r.request.transfer_id;
    m.complete = r.request.complete;
    for (const FileRange& range : r.request.ranges) {
      if (m.first.size() >= 1000) break;  // the rest next time
      m.first.push_back(range.first);
      m.count.push_back(range.count);
    }
    m.n_ranges = static_cast<int16_t>(m.first.size());
    im.bus.Publish(Channel(r.vehicle_id, Topic::kFileRequest), m);
  }
  for (const auto& t : im.model.TakeOutgoingTrackTargets()) {
    uavmsg::track_target_t m{};
    m.utime = WallTimeMicros();
    m.header = {t.vehicle_id, ++im.track_target_seq};
    m.source = im.model.gcs_name();
    m.target_seq = t.target_seq;
    m.frame_utime = t.target.frame_utime;
    m.camera = t.target.camera;
    m.method = static_cast<int8_t>(t.target.method);
    m.x = t.target.x;
    m.y = t.target.y;
    m.width = t.target.width;
    m.height = t.target.height;
    for (int i = 0; i < 4; ++i) {
      m.corner_x[i] = t.target.corners[i][0];
      m.corner_y[i] = t.target.corners[i][1];
    }
    im.bus.Publish(Channel(t.vehicle_id, Topic::kTrackTarget), m);
  }
  if (now - im.last_heartbeat >= 1.0) {
    im.last_heartbeat = now;
    ++im.heartbeat_seq;
    for (const auto& [id, v] : im.model.vehicles()) {
      uavmsg::heartbeat_t hb{};
      hb.utime = WallTimeMicros();
      hb.header = {id, im.heartbeat_seq};
      hb.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
      hb.source_name = im.model.gcs_name();
      im.bus.Publish(Channel(id, Topic::kGcsHeartbeat), hb);
    }
  }
}

}  // namespace uav::gcs
