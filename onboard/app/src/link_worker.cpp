#include "uav/app/link_worker.hpp"

#include <map>

#include "uav/shared/channels.hpp"
#include "uav/shared/file_transfer.hpp"
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
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"

namespace uav::app {

namespace {
FileRequest FileRequestFromMessage(const uavmsg::file_request_t& m) {
  FileRequest r;
  r.transfer_id = m.transfer_id;
  r.complete = m.complete;
  for (int i = 0; i < m.n_ranges && i < static_cast<int>(m.first.size()) && i < static_cast<int>(m.count.size()); ++i)
    r.ranges.push_back({m.first[i], m.count[i]});
  return r;
}
}  // namespace

struct LinkWorker::Impl {
  Impl(const std::string& id, const std::string& url, Blackboard& b, MissionStore& m)
      : vehicle_id(id), bus(url), board(b), missions(m), intake(id) {}

  uavmsg::header_t NextHeader(Topic t) { return {vehicle_id, ++seq[t]}; }
  void SendReport(int64_t utime, const control::TaskReport& r) {
    intake.Remember(r);
    uavmsg::command_ack_t ack;
    ack.utime = utime;
    ack.header = NextHeader(Topic::kCommandAck);
    ack.source = r.source;
    ack.command_seq = r.seq;
    ack.command = r.command;
    ack.result = static_cast<int8_t>(r.result);
    ack.progress_percent = static_cast<int8_t>(r.percent);
    ack.reason = r.reason;
    bus.Publish(Channel(vehicle_id, Topic::kCommandAck), ack);
  }

  std::string vehicle_id;
  Bus bus;
  Blackboard& board;
  MissionStore& missions;
  std::map<std::string, waypoints::MissionAssembler> uploads;  // per GCS
  CommandIntake intake;
  std::map<Topic, int64_t> seq;
  std::map<std::string, int64_t> gcs_last_seen;  // GCS name -> vehicle utime of last heartbeat
  int64_t start_utime = -1;
  int64_t now = 0;
  int64_t last_heartbeat = -1;
  int64_t last_gcs_wall_us = -1;  // monotonic wall clock of the last GCS heartbeat
  std::unique_ptr<EventLog> events;
  FileSender files;  // finished maps, offered until a GCS has them
  int64_t last_tile_utime = -1000000;
};

LinkWorker::LinkWorker(const std::string& vehicle_id, const std::string& lcm_url, Blackboard& board,
                       MissionStore& missions, std::unique_ptr<EventLog> events)
    : impl_(std::make_unique<Impl>(vehicle_id, lcm_url, board, missions)) {
  Impl* im = impl_.get();
  im->events = std::move(events);
  if (im->events) {
    im->bus.SubscribeRaw(".*", [im](const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
      im->events->Write(channel, rbuf.data, static_cast<int>(rbuf.data_size), rbuf.recv_utime);
    });
  }
  im->bus.Subscribe<uavmsg::mission_upload_t>(
      Channel(vehicle_id, Topic::kMissionUpload),
      [im](const std::string&, const uavmsg::mission_upload_t& m) {
        if (m.header.vehicle_id != im->vehicle_id || m.source.empty() || m.source.size() > 64) return;
        waypoints::MissionUploadAck ack;
        try {
          const waypoints::MissionChunk chunk = waypoints::FromMessage(m);
          ack = im->uploads[m.source].Receive(chunk, [im](const waypoints::Mission& mission) {
            return im->missions.AcceptUpload(mission);
          });
        } catch (const std::invalid_argument& e) {
          ack.upload_id = m.upload_id;
          ack.result = waypoints::MissionUploadAck::Result::kRejected;
          ack.reason = e.what();
        }
        if (ack.result != waypoints::MissionUploadAck::Result::kInProgress && ack.received_items == ack.total_items)
          im->board.PushStatus(ack.result == waypoints::MissionUploadAck::Result::kAccepted ? 6 : 4,
                               ack.result == waypoints::MissionUploadAck::Result::kAccepted
                                   ? "mission of " + std::to_string(ack.total_items) + " items accepted from " + m.source
                                   : "mission upload rejected: " + ack.reason);
        else if (ack.result == waypoints::MissionUploadAck::Result::kRejected)
          im->board.PushStatus(4, "mission upload rejected: " + ack.reason);
        uavmsg::mission_ack_t out = waypoints::ToMessage(ack);
        out.utime = im->now;
        out.header = im->NextHeader(Topic::kMissionAck);
        out.source = m.source;
        im->bus.Publish(Channel(im->vehicle_id, Topic::kMissionAck), out);
      });
  im->bus.Subscribe<uavmsg::command_t>(
      Channel(vehicle_id, Topic::kCommand), [im](const std::string&, const uavmsg::command_t& m) {
        auto r = im->intake.Receive(m.header.vehicle_id, m.source, m.command_seq, m.text);
        for (const auto& rep : r.replies) im->SendReport(im->now, rep);
        if (r.request) im->board.PushCommand(*r.request);
      });
  im->bus.Subscribe<uavmsg::heartbeat_t>(
      Channel(vehicle_id, Topic::kGcsHeartbeat),
      [im](const std::string&, const uavmsg::heartbeat_t& m) {
        if (m.source_kind != uavmsg::heartbeat_t::SOURCE_GCS) return;
        if (!im->gcs_last_seen.count(m.source_name))
          im->board.PushStatus(6, "GCS link up: " + m.source_name);
        im->gcs_last_seen[m.source_name] = im->now;
        im->last_gcs_wall_us = MonotonicMicros();
      });
  im->bus.Subscribe<uavmsg::file_request_t>(
      Channel(vehicle_id, Topic::kFileRequest), [im](const std::string&, const uavmsg::file_request_t& m) {
        if (m.header.vehicle_id != im->vehicle_id) return;
        im->files.OnRequest(FileRequestFromMessage(m));
      });
}

LinkWorker::~LinkWorker() = default;


void LinkWorker::Tick(int64_t utime) {
  Impl& im = *impl_;
  im.now = utime;
  if (im.start_utime < 0) im.start_utime = utime;
  im.bus.Handle(0);  // commands and GCS heartbeats received since the last tick
  const double link_age = im.last_gcs_wall_us < 0 ? -1.0 : (MonotonicMicros() - im.last_gcs_wall_us) * 1e-6;
  im.board.Update([&](BlackboardData& b) { b.gcs_link_age_s = link_age; });

  for (const auto& r : im.board.TakeReports()) im.SendReport(utime, r);
  for (const auto& s : im.board.TakeStatus()) {
    uavmsg::status_text_t st;
    st.utime = utime;
    st.header = im.NextHeader(Topic::kStatusText);
    st.severity = static_cast<int8_t>(s.severity);
    st.text = s.text;
    im.bus.Publish(Channel(im.vehicle_id, Topic::kStatusText), st);
  }

  const BlackboardData d = im.board.Snapshot();
  const auto& e = d.estimate;
  uavmsg::vehicle_state_t m;
  m.utime = e.utime ? e.utime : utime;
  m.header = im.NextHeader(Topic::kState);
  m.x = e.p_N.x(); m.y = e.p_N.y(); m.z = e.p_N.z();
  const Eigen::Vector3d v_B = e.q_NB.conjugate() * e.v_N;
  m.u = v_B.x(); m.v = v_B.y(); m.w = v_B.z();
  m.phi = e.euler.phi; m.theta = e.euler.theta; m.psi = e.euler.psi;
  m.p = e.w_B.x(); m.q = e.w_B.y(); m.r = e.w_B.z();
  m.acx = e.f_B.x(); m.acy = e.f_B.y(); m.acz = e.f_B.z();
  m.gps_latitude_deg = d.sample.gps.latitude_deg;
  m.gps_longitude_deg = d.sample.gps.longitude_deg;
  m.gps_altitude_m = d.sample.gps.altitude_m;
  m.gps_fix = static_cast<int8_t>(d.sample.gps_fix);
  m.gps_satellites = static_cast<int8_t>(d.sample.gps_satellites);
  for (int i = 0; i < 4; ++i) m.rotor_input[i] = static_cast<float>(d.rotor_inputs[i]);
  m.servo_input[0] = static_cast<float>(d.servo.aileron);
  m.servo_input[1] = static_cast<float>(d.servo.elevator);
  m.servo_input[2] = static_cast<float>(d.servo.throttle);
  m.servo_input[3] = static_cast<float>(d.servo.rudder);
  m.flight_mode = d.sample.rc_manual ? uavmsg::vehicle_state_t::MODE_MANUAL
                                     : uavmsg::vehicle_state_t::MODE_AUTO;
  m.task = static_cast<int8_t>(d.task);
  m.failsafe = static_cast<int8_t>(d.failsafe);
  m.mission_item = d.mission_item;
  m.home_latitude_deg = im.missions.home().latitude_deg;
  m.home_longitude_deg = im.missions.home().longitude_deg;
  m.home_altitude_m = im.missions.home().altitude_m;
  m.capturing = d.capture_interval_s.has_value() || d.capture_distance_m.has_value();
  m.armed = d.armed;
  m.landed = !d.airborne;
  m.battery_voltage_v = static_cast<float>(d.sample.battery_voltage_v);
  m.battery_remaining = static_cast<float>(d.sample.battery_remaining);
  m.obstacle_range_m = static_cast<float>(d.obstacle_range_m);
  m.fence_radius_m = static_cast<float>(d.fence_radius_m);
  m.fence_alt_m = static_cast<float>(d.fence_alt_m);
  im.bus.Publish(Channel(im.vehicle_id, Topic::kState), m);

  if (im.last_heartbeat < 0 || utime - im.last_heartbeat >= 1000000) {
    im.last_heartbeat = utime;
    uavmsg::heartbeat_t hb;
    hb.utime = utime;
    hb.header = im.NextHeader(Topic::kHeartbeat);
    hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
    hb.source_name = im.vehicle_id;
    hb.uptime_us = utime - im.start_utime;
    hb.armed = d.armed;
    hb.flight_mode = m.flight_mode;
    hb.task = m.task;
    im.bus.Publish(Channel(im.vehicle_id, Topic::kHeartbeat), hb);
  }
  if (auto preview = im.board.TakePreview()) {
    if (preview->jpeg.size() <= static_cast<size_t>(uavmsg::video_frame_t::MAX_JPEG_BYTES)) {
      uavmsg::video_frame_t v;
      v.utime = preview->utime;
      v.header = im.NextHeader(Topic::kVideo);
      v.camera = preview->camera;
      v.width = static_cast<int16_t>(preview->width);
      v.height = static_cast<int16_t>(preview->height);
      v.source_width = static_cast<int16_t>(preview->source_width);
      v.source_height = static_cast<int16_t>(preview->source_height);
      v.size = static_cast<int32_t>(preview->jpeg.size());
      v.jpeg = std::move(preview->jpeg);
      im.bus.Publish(Channel(im.vehicle_id, Topic::kVideo), v);
    }
  }
  // Live map: one tile per 200 ms at most (~100 kB/s), the longest-waiting first.
  if (utime - im.last_tile_utime >= 200000) {
    if (auto tile = im.board.TakeTile()) {
      im.last_tile_utime = utime;
      uavmsg::map_tile_t m;
      m.utime = utime;
      m.header = im.NextHeader(Topic::kMapTile);
      m.map_id = tile->map_id;
      m.tile_x = tile->tx;
      m.tile_y = tile->ty;
      m.tile_px = static_cast<int16_t>(tile->tile_px);
      m.gsd_m = tile->gsd_m;
      m.origin_north_m = tile->origin_north_m;
      m.origin_east_m = tile->origin_east_m;
      m.georeferenced = tile->georeferenced;
      m.size = static_cast<int32_t>(tile->jpeg.size());
      m.jpeg = std::move(tile->jpeg);
      im.bus.Publish(Channel(im.vehicle_id, Topic::kMapTile), m);
    }
  }
  for (auto& [name, contents] : im.board.TakeDownloads()) im.files.Offer(name, contents);
  const FileSender::Output files = im.files.Poll(utime * 1e-6);
  for (const FileOffer& o : files.offers) {
    uavmsg::file_offer_t m;
    m.utime = utime;
    m.header = im.NextHeader(Topic::kFileOffer);
    m.transfer_id = o.transfer_id;
    m.name = o.name;
    m.size = o.size;
    m.chunk_bytes = o.chunk_bytes;
    m.chunks = o.chunks;
    m.sha256 = o.sha256;
    im.bus.Publish(Channel(im.vehicle_id, Topic::kFileOffer), m);
  }
  for (const FileChunk& c : files.chunks) {
    uavmsg::file_chunk_t m;
    m.utime = utime;
    m.header = im.NextHeader(Topic::kFileChunk);
    m.transfer_id = c.transfer_id;
    m.index = c.index;
    m.crc32 = static_cast<int32_t>(c.crc32);
    m.size = static_cast<int32_t>(c.data.size());
    m.data = c.data;
    im.bus.Publish(Channel(im.vehicle_id, Topic::kFileChunk), m);
  }
  if (im.events) im.events->Flush();
}

}  // namespace uav::app
