// make_fuzz_seeds OUT_DIR: the binary seed corpora, encoded by the project's own code so they
// stay valid as the message types change: OUT_DIR/vehicle_messages (GCS -> vehicle, signed with
// the harness's key), OUT_DIR/gcs_messages (vehicle -> GCS, one per topic) and
// OUT_DIR/event_log (a short onboard event log). Text seeds are files of the project
// (tests/fuzz/CMakeLists.txt lists them).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "uav/wire/messages.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "uav/wire/reports.hpp"
#include "uav/wire/signed_message.hpp"
#include "uavmsg/active_stereo_t.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/mission_ack_t.hpp"
#include "uavmsg/mission_upload_t.hpp"
#include "uavmsg/mono_depth_t.hpp"
#include "uavmsg/obstacles_t.hpp"
#include "uavmsg/point_cloud_t.hpp"
#include "uavmsg/power_lines_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"
#include "uavmsg/visual_odometry_t.hpp"
#include "uavmsg/sensing_t.hpp"

namespace {

namespace fs = std::filesystem;
constexpr int64_t kUtime = 1'795'000'000'000'000;

template <class Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> b(m.getEncodedSize());
  m.encode(b.data(), 0, static_cast<int>(b.size()));
  return b;
}

void WriteBytes(const fs::path& path, const std::vector<uint8_t>& bytes) {
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

void Write(const fs::path& path, uint8_t selector, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.put(static_cast<char>(selector));
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

template <class Msg>
Msg ForVehicle() {
  Msg m{};
  m.utime = kUtime;
  m.header.vehicle_id = "UAV1";
  m.header.seq = 1;
  return m;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: make_fuzz_seeds OUT_DIR\n");
    return 2;
  }
  const fs::path out = argv[1];
  for (const char* d : {"vehicle_messages", "gcs_messages", "event_log", "mavlink", "gcs_mavlink"}) fs::create_directories(out / d);

  // GCS -> vehicle, selector = the harness's case; signed with its key (0x42 x 32).
  uav::SigningKey key;
  key.bytes.fill(0x42);
  uav::MessageSigner signer(key, 0);
  {
    auto m = ForVehicle<uavmsg::command_t>();
    m.source = "gcs";
    m.command_seq = 7;
    for (const char* text : {"arm", "goto 10 20 15", "takeoff 10"}) {
      m.text = text;
      uav::SignMessage(signer, kUtime, m);
      Write(out / "vehicle_messages" / (std::string("command_") + text[0]), 0, Encode(m));
    }
  }
  {
    auto m = ForVehicle<uavmsg::mission_upload_t>();
    m.source = "gcs";
    m.upload_id = 3;
    m.total_items = 2;
    m.home_latitude_deg = 1.2966;
    m.home_longitude_deg = 103.7764;
    m.home_altitude_m = 15;
    m.cruise_speed_m_s = 5;
    for (int i = 0; i < 2; ++i) {
      uavmsg::mission_item_t it{};
      it.command = i == 0 ? 22 : 16;
      it.frame = 3;
      it.latitude_deg = 1.2966 + 1e-4 * i;
      it.longitude_deg = 103.7764;
      it.altitude_m = 20;
      it.autocontinue = 1;
      m.items.push_back(it);
    }
    m.num_items = 2;
    uav::SignMessage(signer, kUtime, m);
    Write(out / "vehicle_messages" / "mission_upload", 1, Encode(m));
  }
  {
    auto m = ForVehicle<uavmsg::file_request_t>();
    m.source = "gcs";
    m.first = {0, 5};
    m.count = {3, 1};
    m.n_ranges = 2;
    uav::SignMessage(signer, kUtime, m);
    Write(out / "vehicle_messages" / "file_request", 2, Encode(m));
  }
  {
    auto m = ForVehicle<uavmsg::track_target_t>();
    m.source = "gcs";
    m.target_seq = 1;
    m.frame_utime = kUtime;
    m.camera = "gimbal";
    m.x = 0.4, m.y = 0.4, m.width = 0.1, m.height = 0.1;
    for (int i = 0; i < 4; ++i) m.corner_x[i] = 0.4 + 0.1 * (i == 1 || i == 2), m.corner_y[i] = 0.4 + 0.1 * (i >= 2);
    uav::SignMessage(signer, kUtime, m);
    Write(out / "vehicle_messages" / "track_target", 3, Encode(m));
  }
  {
    auto m = ForVehicle<uavmsg::heartbeat_t>();
    m.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
    m.source_name = "gcs";
    uav::SignMessage(signer, kUtime, m);
    Write(out / "vehicle_messages" / "gcs_heartbeat", 4, Encode(m));
  }

  // Vehicle -> GCS, selector = the topic's index in GcsLink::Topics() (fuzz_gcs_messages.cpp).
  const fs::path g = out / "gcs_messages";
  const std::vector<uav::Topic> topics = uav::gcs::GcsLink::Topics();
  auto selector = [&](uav::Topic t) {
    return static_cast<uint8_t>(std::find(topics.begin(), topics.end(), t) - topics.begin());
  };
  auto hb = ForVehicle<uavmsg::heartbeat_t>();
  hb.source_name = "UAV1";
  hb.signing = uavmsg::heartbeat_t::SIGNING_ON;
  Write(g / "heartbeat", selector(uav::Topic::kHeartbeat), Encode(hb));
  auto state = ForVehicle<uavmsg::vehicle_state_t>();
  Write(g / "state", selector(uav::Topic::kState), Encode(state));
  auto ack = ForVehicle<uavmsg::command_ack_t>();
  ack.source = "fuzz";
  ack.command = "arm";
  ack.result = uavmsg::command_ack_t::RESULT_COMPLETED;
  Write(g / "command_ack", selector(uav::Topic::kCommandAck), Encode(ack));
  auto text = ForVehicle<uavmsg::status_text_t>();
  text.text = "GPS fix lost";
  Write(g / "status_text", selector(uav::Topic::kStatusText), Encode(text));
  Write(g / "mission_ack", selector(uav::Topic::kMissionAck), Encode(ForVehicle<uavmsg::mission_ack_t>()));
  Write(g / "video_frame", selector(uav::Topic::kVideo), Encode(ForVehicle<uavmsg::video_frame_t>()));
  auto offer = ForVehicle<uavmsg::file_offer_t>();
  offer.name = "map_1.tif";
  Write(g / "file_offer", selector(uav::Topic::kFileOffer), Encode(offer));
  Write(g / "file_chunk", selector(uav::Topic::kFileChunk), Encode(ForVehicle<uavmsg::file_chunk_t>()));
  Write(g / "map_tile", selector(uav::Topic::kMapTile), Encode(ForVehicle<uavmsg::map_tile_t>()));
  Write(g / "track_status", selector(uav::Topic::kTrackStatus), Encode(ForVehicle<uavmsg::track_status_t>()));
  // Every perception report: an empty one (the harness varies it from there).
  uav::ForEachType(uav::VehicleReports{}, [&](auto* type) {
    using T = std::remove_pointer_t<decltype(type)>;
    auto m = uav::ToMessage(T{});
    m.utime = kUtime;
    m.header.vehicle_id = "UAV1";
    m.header.seq = 1;
    const uav::Topic t = uav::Report<T>::kTopic;
    Write(g / uav::TopicName(t), selector(t), Encode(m));
  });
  {
    auto m = ForVehicle<uavmsg::sensing_t>();
    uavmsg::sensing_worker_t w{};
    w.name = "STEREO";
    w.rig = "stereo_left";
    w.camera_rate_hz = 15;
    w.configured_rate_hz = 15;
    w.rate_hz = 7.5;
    w.latency_p50_ms = 60;
    w.latency_p99_ms = 60;
    w.healthy = false;
    w.reason = "behind: 7.5 of 15.0 Hz, 30 frames dropped";
    m.workers = {w};
    m.num_workers = 1;
    constexpr uav::Topic kSensing = uav::Report<uav::SensingReport>::kTopic;
    Write(g / uav::TopicName(kSensing), selector(kSensing), Encode(m));  // one unhealthy worker
  }

  // A short event log, as the onboard EventLog writes it (LCM log format).
  {
    lcm::LogFile log((out / "event_log" / "events.lcmlog").string(), "w");
    for (int i = 0; i < 5; ++i) {
      lcm::LogEvent e{};
      e.eventnum = i;
      e.timestamp = kUtime + i * 100'000;
      std::vector<uint8_t> b;
      if (i % 2 == 0) {
        hb.utime = e.timestamp;
        hb.header.seq = i;
        b = Encode(hb);
        e.channel = uav::Channel("UAV1", uav::Topic::kHeartbeat);
      } else {
        state.utime = e.timestamp;
        state.header.seq = i;
        b = Encode(state);
        e.channel = uav::Channel("UAV1", uav::Topic::kState);
      }
      e.datalen = static_cast<int32_t>(b.size());
      e.data = b.data();
      log.writeEvent(&e);
    }
  }
  // MAVLink: every message we speak as one frame with a payload of varied bytes, signed with the
  // harness's key (0x42 x 32) and unsigned, datagrams of 17 bytes (the harness's first byte);
  // MAVLink 1 for the ids it can carry.
  for (const uav::mavlink::MessageLayout& l : uav::mavlink::Layouts()) {
    uav::mavlink::Frame f;
    f.sysid = 255, f.compid = 190, f.msgid = l.id;
    f.payload.resize(l.length);
    for (std::size_t i = 0; i < f.payload.size(); ++i) f.payload[i] = static_cast<uint8_t>(i * 37 + l.id);
    std::vector<uint8_t> bytes = {16};
    const std::vector<uint8_t> frame = uav::mavlink::Encode(f, l.crc_extra, &key.bytes, 1, 600'000'000'000);
    bytes.insert(bytes.end(), frame.begin(), frame.end());
    WriteBytes(out / "mavlink" / (l.name + "_signed"), bytes);
    bytes.resize(1);
    f.version = l.id < 256 ? 1 : 2;
    if (f.version == 1) f.payload.resize(l.base_length);
    const std::vector<uint8_t> plain = uav::mavlink::Encode(f, l.crc_extra);
    bytes.insert(bytes.end(), plain.begin(), plain.end());
    WriteBytes(out / "mavlink" / (l.name + (f.version == 1 ? "_v1" : "_unsigned")), bytes);
  }
  // The GCS's MAVLink link: a vehicle's session, unsigned, as PX4 and as ArduCopter: heartbeat,
  // home, position, two parameters, a mission of two items offered, acknowledgements, texts,
  // the requests of an upload, progress. Datagrams of 33 bytes.
  for (const uint8_t autopilot : {uint8_t{12}, uint8_t{3}}) {
    using namespace uav::mavlink;
    std::vector<uint8_t> bytes = {32};
    uint8_t seq = 0;
    auto add = [&](const auto& m) {
      Frame f;
      f.seq = seq++, f.sysid = 1, f.compid = 1;
      f.msgid = std::decay_t<decltype(m)>::kId;
      f.payload = Pack(m);
      const std::vector<uint8_t> frame = Encode(f, FindLayout(f.msgid)->crc_extra);
      bytes.insert(bytes.end(), frame.begin(), frame.end());
    };
    Heartbeat hb;
    hb.type = 2, hb.autopilot = autopilot, hb.base_mode = 129, hb.custom_mode = autopilot == 12 ? 0x03040000u : 5u;
    add(hb);
    HomePosition home;
    home.latitude = 12966000, home.longitude = 1037764000, home.altitude = 15000;
    add(home);
    GlobalPositionInt p;
    p.lat = 12966100, p.lon = 1037764100, p.alt = 25000, p.relative_alt = 10000, p.vx = 100;
    add(p);
    ParamValue pv;
    SetText(pv.param_id, "P1");
    pv.param_value = 1.f, pv.param_type = 9, pv.param_count = 2, pv.param_index = 0;
    add(pv);
    SetText(pv.param_id, "P2");
    pv.param_type = 6, pv.param_index = 1;
    add(pv);
    MissionCount mc;
    mc.target_system = 255, mc.count = 2;
    add(mc);
    MissionItemInt item;
    item.target_system = 255, item.command = 16, item.frame = 3, item.x = 12966000, item.y = 1037764000, item.z = 10;
    add(item);
    item.seq = 1;
    add(item);
    MissionRequestInt rq;
    rq.target_system = 255;
    add(rq);
    rq.seq = 1;
    add(rq);
    MissionAck ma;
    ma.target_system = 255;
    add(ma);
    CommandAck ca;
    ca.command = 400, ca.target_system = 255;
    add(ca);
    ca.command = 176;
    add(ca);
    Statustext st;
    st.severity = 4;
    SetText(st.text, "PreArm: fuzz");
    add(st);
    MissionCurrent cur;
    cur.seq = 1;
    add(cur);
    MissionItemReached reached;
    reached.seq = 1;
    add(reached);
    WriteBytes(out / "gcs_mavlink" / (autopilot == 12 ? "px4_session" : "ardupilot_session"), bytes);
  }
  std::printf("make_fuzz_seeds: wrote %s\n", out.c_str());
  return 0;
}
