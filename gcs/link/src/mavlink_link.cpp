#include "uav/gcs/mavlink_link.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <set>
#include <stdexcept>

#include "rtp_video_receiver.hpp"
#include "uav/gcs/mavlink_commands.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/mavlink_frame.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "uav/shared/mavlink_transport.hpp"
#include "uav/shared/parameter_table.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/pre_arm.hpp"
#include "uav/shared/time.hpp"
#include "uav/waypoints/mavlink_items.hpp"
#include "uav/waypoints/mission_transfer.hpp"

namespace uav::gcs {
namespace {

using namespace uav::mavlink;
using waypoints::MavMissionList;

constexpr uint8_t kGcsSystem = 255, kGcsComponent = 190;  // QGroundControl's ids
constexpr uint8_t kCompAutopilot = 1, kCompCamera = 100;
constexpr uint8_t kModeFlagArmed = 128;
constexpr uint8_t kMavTypeGcs = 6, kMavAutopilotInvalid = 8;
constexpr uint8_t kResultAccepted = 0, kResultInProgress = 5;
constexpr uint8_t kMissionAccepted = 0;
constexpr double kHomeRequestPeriod = 3.0;  // [s] until HOME_POSITION has come
// What the GCS asks ArduPilot to stream (SET_MESSAGE_INTERVAL; ArduPilot streams only what a
// GCS asks for or its SRn_ parameters set): message id and interval [us].
constexpr std::pair<uint32_t, float> kArduPilotStreams[] = {
    {Attitude::kId, 100'000},       {GlobalPositionInt::kId, 100'000}, {VfrHud::kId, 250'000},
    {GpsRawInt::kId, 500'000},      {SysStatus::kId, 1'000'000},       {ExtendedSysState::kId, 1'000'000},
    {MissionCurrent::kId, 1'000'000}, {BatteryStatus::kId, 1'000'000}};
// SYS_STATUS sensor bits (MAV_SYS_STATUS_SENSOR) shown as pre-arm checks, as QGroundControl's.
struct SensorBit {
  uint32_t bit;
  const char* name;
};
constexpr SensorBit kSensors[] = {{1, "gyro"},           {2, "accelerometer"}, {4, "magnetometer"},
                                  {8, "barometer"},      {32, "gps"},          {1u << 21, "ahrs"},
                                  {1u << 20, "geofence"}, {1u << 25, "battery"}, {1u << 15, "motor outputs"},
                                  {1u << 16, "rc receiver"}};
constexpr uint32_t kSensorPrearm = 1u << 28;

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

Severity SeverityOf(uint8_t mav_severity) {  // MAV_SEVERITY: 0-3 errors, 4 warning, 5-7 notices
  return mav_severity <= 3 ? Severity::kError : mav_severity == 4 ? Severity::kWarning : Severity::kInfo;
}

const char* ParamTypeName(uint8_t t) {
  static const char* const kNames[] = {"?", "UINT8", "INT8", "UINT16", "INT16", "UINT32", "INT32", "UINT64", "INT64", "REAL32", "REAL64"};
  return t < 11 ? kNames[t] : "?";
}

// One parameter as the vehicle sent it: decoded when read, in the encoding known then.
struct Param {
  std::string id;
  float wire = 0;
  uint8_t type = kParamReal32;
};

// A command of the operator's in flight: its MAVLink steps, which one waits for an answer, and
// what was last said about it (repeated when the GCS resends).
struct PendingCommand {
  int64_t command_seq = 0;
  std::string name;          // "takeoff"
  MavlinkPlan plan;
  std::size_t step = 0;
  int confirmation = 0;
  bool finished = false;     // the final answer given
  bool watching = false;     // accepted, waiting for the vehicle to get there
  uav::CommandAck last;
};

// A parameter change in flight.
struct PendingParam {
  int64_t command_seq = 0;
  std::string id;
  double value = 0;
  float wire = 0;
  uint8_t type = kParamReal32;
  double sent = -1;
  int tries = 0;
  bool finished = false;
  uav::CommandAck last;
};

// One mission-service transfer: an upload of the three lists or a download of them.
struct Transfer {
  bool upload = true;
  bool for_editor = false;
  int64_t upload_id = 0;
  waypoints::Mission mission;       // upload: what goes; download: what came so far
  uint64_t digest = 0;
  std::vector<MavMissionList> lists;  // still to do, the current one first
  std::vector<waypoints::MissionItem> items;  // of the current list (upload: with ArduPilot's home first)
  int expected = -1;                // download: the count the vehicle said
  int next = 0;                     // download: the item asked for; upload: the highest item asked for + 1
  int sent_before = 0;              // upload: items of earlier lists (progress)
  double last = -1;                 // when we last sent, or the vehicle last asked
  int tries = 0;
  std::vector<std::string> done;    // "mission of 28 items" for the log
};

struct MavVehicle {
  uint8_t sysid = 0, compid = kCompAutopilot;
  Autopilot autopilot = Autopilot::kOther;
  uint8_t mav_type = 0;
  std::string id;
  ParamEncoding encoding = ParamEncoding::kCCast;
  // link quality
  bool seq_known = false;
  uint8_t last_seq = 0;
  int64_t lost = 0;              // frames missing from the autopilot's sequence numbers
  int64_t lost_counted = 0;      // of which already folded into state_seq
  int64_t state_seq = 0;         // per state: 1 + the frames lost since the previous one
  int64_t heartbeats = 0;
  // state
  uint32_t custom_mode = 0;
  bool armed = false;
  std::optional<GeodeticPoint> home;
  std::unique_ptr<LocalNedFrame> frame;  // N at home, made once per home (positions are from it)
  double last_home_request = -1e9;
  VehicleState state;
  int landed_state = 0;          // EXTENDED_SYS_STATE: 0 unknown, 1 on ground, 2 in air, 3 taking off, 4 landing
  int mission_seq = -1;          // MISSION_CURRENT as the vehicle counts
  int mission_items = -1;        // of the mission list (ours, without ArduPilot's home)
  int last_reached = -1;
  std::map<uint16_t, std::string> text_chunks;  // STATUSTEXT id -> the chunks so far
  std::string last_warning;      // the newest warning text, for the reason of a refusal
  double last_warning_at = -1e9;
  // parameters
  std::map<int, Param> params;   // by index
  int param_count = -1;
  double param_last = -1;
  int param_tries = 0;
  bool params_complete = false;
  int64_t param_version = 0;
  std::vector<PendingParam> param_sets;
  // commands, missions
  std::map<int64_t, PendingCommand> commands;
  std::optional<Transfer> transfer;
  std::vector<Transfer> queued;  // transfers waiting for the current one
  bool first_download_done = false;
  bool said_no_sticks = false;
  bool video_announced = false;
};

}  // namespace

std::string MavlinkLink::VehicleIdOf(Autopilot a, int system_id) {
  std::string name = Lower(std::string(Name(a)));
  for (char& c : name)
    if (c == ' ') c = '-';
  return name + "-" + std::to_string(system_id);
}

struct MavlinkLink::Impl {
  Impl(const MavlinkLinkParams& p, GcsModel& m)
      : params(p), model(m), transport(p.endpoint.empty() ? nullptr : OpenMavlinkTransport(p.endpoint)),
        parser([this](uint32_t id) {
          const auto info = Lookup()(id);
          if (!info) unknown_ids.insert(id);
          return info;
        }),
        streams(p.key ? p.key->bytes : SecretKey{}, !p.key) {
    if (p.video_port > 0) video = std::make_unique<RtpVideoReceiver>(p.video_port);
  }

  MavlinkLinkParams params;
  GcsModel& model;
  std::unique_ptr<MavlinkTransport> transport;
  Parser parser;
  SignedStreams streams;
  std::unique_ptr<RtpVideoReceiver> video;
  std::map<uint8_t, MavVehicle> vehicles;  // by system id
  std::set<uint32_t> unknown_ids;
  std::set<uint32_t> unknown_said;
  std::map<std::string, double> refusal_said;
  uint8_t seq = 0;
  double now = 0;
  double last_heartbeat = -1e9;
  Counts counts;

  // ---- sending ----
  template <class M>
  void Send(const M& m) {
    Frame f;
    f.seq = seq++;
    f.sysid = kGcsSystem;
    f.compid = kGcsComponent;
    f.msgid = M::kId;
    f.payload = Pack(m);
    const uint64_t ts = streams.NextTimestamp(static_cast<uint64_t>(SigningTimestamp(WallTimeMicros())));
    const auto bytes = Encode(f, FindLayout(M::kId)->crc_extra, params.key ? &params.key->bytes : nullptr, 0, ts);
    if (transport && transport->Send(bytes)) ++counts.frames_out;
  }
  void SendStep(const MavVehicle& v, const MavlinkStep& s, int confirmation) {
    if (s.command_int) {
      CommandInt c;
      c.target_system = v.sysid, c.target_component = s.component;
      c.frame = s.frame, c.command = s.command;
      c.param1 = s.param[0], c.param2 = s.param[1], c.param3 = s.param[2], c.param4 = s.param[3];
      c.x = s.x, c.y = s.y, c.z = s.param[6];
      return Send(c);
    }
    CommandLong c;
    c.target_system = v.sysid, c.target_component = s.component;
    c.command = s.command;
    c.confirmation = static_cast<uint8_t>(std::min(confirmation, 255));
    c.param1 = s.param[0], c.param2 = s.param[1], c.param3 = s.param[2], c.param4 = s.param[3];
    c.param5 = s.param[4], c.param6 = s.param[5], c.param7 = s.param[6];
    Send(c);
  }
  void RequestMessage(const MavVehicle& v, uint32_t id) {
    MavlinkStep s;
    s.command = mav_cmd::kRequestMessage;
    s.param[0] = static_cast<float>(id);
    SendStep(v, s, 0);
  }

  void Say(const MavVehicle& v, const std::string& text, Severity s) { model.OnLinkNote(v.id, text, s, now); }

  // ---- receiving ----
  void Receive(double t, const uint8_t* extra = nullptr, std::size_t extra_size = 0) {
    now = t;
    if (extra) Ingest(extra, extra_size);
    if (transport)
      for (const std::vector<uint8_t>& piece : transport->Receive()) Ingest(piece.data(), piece.size());
    Periodic();
  }

  void Ingest(const uint8_t* data, std::size_t size) {
    {
      for (const Frame& f : transport && transport->datagrams() ? parser.PushDatagram(data, size)
                                                                : parser.Push(data, size)) {
        ++counts.frames_in;
        const auto verdict = streams.Check(f, static_cast<uint64_t>(SigningTimestamp(WallTimeMicros())));
        if (verdict != SignedStreams::Verdict::kAccepted) {
          Refused(verdict, f);
          continue;
        }
        try {
          Handle(f);
        } catch (const std::exception& e) {  // a frame that does not decode names itself and is dropped
          model.OnLinkNote("mavlink", std::string("MAVLink ") + FindLayout(f.msgid)->name + " from system " +
                                          std::to_string(f.sysid) + " dropped: " + e.what(),
                           Severity::kWarning, now);
        }
      }
    }
  }

  void Periodic() {
    const Parser::Counts& c = parser.counts();
    counts.unknown_messages = c.unknown_message;
    counts.bad_checksum = c.bad_checksum;
    for (uint32_t id : unknown_ids) {
      if (!unknown_said.insert(id).second) continue;
      model.OnLinkNote("mavlink", "MAVLink message id " + std::to_string(id) +
                                      " is not one this GCS reads: skipped, and counted in the link's unknown messages",
                       Severity::kInfo, now);
    }
    for (auto& [sysid, v] : vehicles) Tick(v);
    PollVideo();
    // Always, as QGroundControl: a vehicle that listens (udp: here, its udpin:) hears us first.
    if (now - last_heartbeat >= 1.0) {
      last_heartbeat = now;
      Heartbeat h;
      h.type = kMavTypeGcs, h.autopilot = kMavAutopilotInvalid, h.system_status = 4, h.mavlink_version = 3;
      Send(h);
    }
  }

  void Refused(SignedStreams::Verdict verdict, const Frame& f) {
    ++counts.refused;
    auto it = vehicles.find(f.sysid);
    const std::string why = SignedStreams::Name(verdict);
    double& said = refusal_said[why];
    if (said != 0 && now - said < 5.0) return;
    said = now;
    std::string hint;
    if (verdict == SignedStreams::Verdict::kBadSignature) hint = ": the vehicle signs with another key";
    else if (verdict == SignedStreams::Verdict::kUnsigned) hint = ": this GCS has a key and takes only frames signed with it";
    model.OnLinkNote(it != vehicles.end() && !it->second.id.empty() ? it->second.id : "mavlink",
                     "MAVLink frames from system " + std::to_string(f.sysid) + " refused (" + why + ")" + hint,
                     Severity::kWarning, now);
  }

  MavlinkLinkInfo Info(const MavVehicle& v) const {
    MavlinkLinkInfo i;
    i.endpoint = params.endpoint;
    i.system_id = v.sysid;
    i.autopilot = std::string(Name(v.autopilot));
    i.frame = std::string(VehicleTypeName(v.mav_type));
    i.mode = ModeName(v.autopilot, v.custom_mode);
    i.signing = params.key.has_value();
    i.refused_frames = counts.refused;
    i.unknown_messages = counts.unknown_messages;
    i.parameters_received = static_cast<int>(v.params.size());
    i.parameters_total = std::max(v.param_count, 0);
    return i;
  }

  void Handle(const Frame& f) {
    if (f.msgid == Heartbeat::kId) {
      const Heartbeat h = Unpack<Heartbeat>(f);
      if (h.type == kMavTypeGcs || f.compid != kCompAutopilot) return;  // other GCSs, cameras, gimbals
      OnHeartbeat(f, h);
      return;
    }
    auto it = vehicles.find(f.sysid);
    if (it == vehicles.end()) return;  // nothing until its autopilot's heartbeat says who it is
    MavVehicle& v = it->second;
    CountSeq(v, f);
    switch (f.msgid) {
      case SysStatus::kId: return OnSysStatus(v, Unpack<SysStatus>(f));
      case GlobalPositionInt::kId: return OnPosition(v, Unpack<GlobalPositionInt>(f));
      case Attitude::kId: {
        const Attitude a = Unpack<Attitude>(f);
        v.state.euler = {a.roll, a.pitch, a.yaw};
        v.state.w_B = Eigen::Vector3d(a.rollspeed, a.pitchspeed, a.yawspeed);
        return;
      }
      case GpsRawInt::kId: {
        const GpsRawInt g = Unpack<GpsRawInt>(f);
        v.state.gps_fix = std::min<int>(g.fix_type, 3);
        v.state.gps_satellites = g.satellites_visible == 255 ? 0 : g.satellites_visible;
        return;
      }
      case VfrHud::kId: {
        const VfrHud h = Unpack<VfrHud>(f);
        if (IsFixedWingType(v.mav_type) || IsVtolType(v.mav_type)) v.state.airspeed_m_s = h.airspeed;
        return;
      }
      case HomePosition::kId: return OnHome(v, Unpack<HomePosition>(f));
      case ExtendedSysState::kId: {
        const ExtendedSysState e = Unpack<ExtendedSysState>(f);
        v.landed_state = e.landed_state;
        // MAV_VTOL_STATE: 1, 2 transitions, 3 multicopter, 4 fixed wing.
        v.state.vtol_mode = e.vtol_state == 4 ? VtolMode::kCruise : e.vtol_state == 1 ? VtolMode::kTransitionToWing
                            : e.vtol_state == 2 ? VtolMode::kTransitionToHover : VtolMode::kHover;
        return;
      }
      case BatteryStatus::kId: {
        const BatteryStatus b = Unpack<BatteryStatus>(f);
        if (b.battery_remaining >= 0) v.state.battery_remaining = b.battery_remaining / 100.0;
        return;
      }
      case Statustext::kId: {
        const Statustext s = Unpack<Statustext>(f);
        // MAVLink 2 splits a long text into 50-character chunks sharing an id; the last is shorter.
        std::string text = Text(s.text);
        if (s.id != 0) {
          std::string& so_far = v.text_chunks[s.id];
          so_far += text;
          if (text.size() == s.text.size() && so_far.size() < 1000) return;
          text = std::move(so_far);
          v.text_chunks.erase(s.id);
        }
        if (s.severity <= 4) v.last_warning = text, v.last_warning_at = now;
        model.OnStatusText(v.id, SeverityOf(s.severity), text, now);
        return;
      }
      case mavlink::CommandAck::kId: return OnCommandAck(v, Unpack<mavlink::CommandAck>(f), f);
      case AutopilotVersion::kId: {
        const AutopilotVersion a = Unpack<AutopilotVersion>(f);
        // Parameters are kept as they came (wire value and type), so one that arrived before this
        // is read again in the right encoding.
        if (a.capabilities & kCapabilityParamBytewise) v.encoding = ParamEncoding::kBytewise;
        else if (a.capabilities & kCapabilityParamCCast) v.encoding = ParamEncoding::kCCast;
        if (v.params_complete) PublishTable(v);
        return;
      }
      case ParamValue::kId: return OnParamValue(v, Unpack<ParamValue>(f));
      case MissionCurrent::kId: return OnMissionCurrent(v, Unpack<MissionCurrent>(f).seq);
      case MissionItemReached::kId: return OnReached(v, Unpack<MissionItemReached>(f).seq);
      case MissionRequestInt::kId: {
        const MissionRequestInt r = Unpack<MissionRequestInt>(f);
        if (r.target_system == kGcsSystem) OnMissionRequest(v, r.seq, r.mission_type);
        return;
      }
      case MissionRequest::kId: {  // the float protocol's request: answered with the INT item, as QGC does
        const MissionRequest r = Unpack<MissionRequest>(f);
        if (r.target_system == kGcsSystem) OnMissionRequest(v, r.seq, r.mission_type);
        return;
      }
      case MissionAck::kId: {
        const MissionAck a = Unpack<MissionAck>(f);
        if (a.target_system == kGcsSystem) OnMissionAck(v, a);
        return;
      }
      case MissionCount::kId: {
        const MissionCount c = Unpack<MissionCount>(f);
        if (c.target_system == kGcsSystem) OnMissionCount(v, c);
        return;
      }
      case MissionItemInt::kId: {
        const MissionItemInt m = Unpack<MissionItemInt>(f);
        if (m.target_system == kGcsSystem) OnMissionItem(v, m);
        return;
      }
      case VideoStreamInformation::kId:
        v.video_announced = true;
        return;
      default: return;
    }
  }

  void CountSeq(MavVehicle& v, const Frame& f) {
    if (f.compid != v.compid) return;
    if (v.seq_known) v.lost += static_cast<uint8_t>(f.seq - v.last_seq - 1);
    v.seq_known = true;
    v.last_seq = f.seq;
  }

  void OnHeartbeat(const Frame& f, const Heartbeat& h) {
    auto [it, fresh] = vehicles.try_emplace(f.sysid);
    MavVehicle& v = it->second;
    if (fresh) {
      v.sysid = f.sysid;
      v.compid = f.compid;
      v.autopilot = RecognizeAutopilot(h.autopilot, h.type);
      v.mav_type = h.type;
      v.id = MavlinkLink::VehicleIdOf(v.autopilot, f.sysid);
      v.encoding = ParamEncodingOf(v.autopilot);
      v.state.vehicle_type = IsVtolType(h.type) || IsFixedWingType(h.type) ? VehicleType::kTailSitter : VehicleType::kQuadrotor;
      if (IsFixedWingType(h.type)) v.state.vtol_mode = VtolMode::kCruise;
      model.OnMavlinkLink(v.id, Info(v), now);
      RequestMessage(v, AutopilotVersion::kId);
      if (IsArduPilot(v.autopilot))
        for (const auto& [id, interval_us] : kArduPilotStreams) {
          MavlinkStep s;
          s.command = mav_cmd::kSetMessageInterval;
          s.param[0] = static_cast<float>(id), s.param[1] = interval_us;
          SendStep(v, s, 0);
        }
      StartParamList(v);
    }
    CountSeq(v, f);
    ++v.heartbeats;
    const std::string mode_before = ModeName(v.autopilot, v.custom_mode);
    v.custom_mode = h.custom_mode;
    v.armed = (h.base_mode & kModeFlagArmed) != 0;
    const AutopilotMode* mode = FindMode(v.autopilot, h.custom_mode);
    HeartbeatInfo hb;
    hb.task = mode && mode->task ? *mode->task : Task::kIdle;
    if (!v.armed && hb.task != Task::kSticks) hb.task = Task::kIdle;  // Hold or Guided on the ground: nothing flown
    hb.armed = v.armed;
    hb.flight_mode = mode && mode->task == Task::kSticks ? FlightMode::kManual : FlightMode::kAuto;
    hb.signing = params.key.has_value();
    hb.signature_rejections = counts.refused;
    v.state.task = hb.task;
    v.state.flight_mode = hb.flight_mode;
    v.state.armed = v.armed;
    model.OnHeartbeat(v.id, v.heartbeats, hb, now);
    model.OnMavlinkLink(v.id, Info(v), now);
    if (!fresh && ModeName(v.autopilot, h.custom_mode) != mode_before)
      Say(v, "mode " + ModeName(v.autopilot, h.custom_mode), Severity::kInfo);
  }

  void OnSysStatus(MavVehicle& v, const SysStatus& s) {
    if (s.voltage_battery != UINT16_MAX) v.state.battery_voltage_v = s.voltage_battery * 1e-3;
    if (s.battery_remaining >= 0) v.state.battery_remaining = s.battery_remaining / 100.0;
    PreArmReport r;
    r.utime = WallTimeMicros();
    for (const SensorBit& b : kSensors) {
      if (!(s.onboard_control_sensors_present & b.bit) || !(s.onboard_control_sensors_enabled & b.bit)) continue;
      const bool healthy = (s.onboard_control_sensors_health & b.bit) != 0;
      r.checks.push_back({b.name, healthy, healthy ? "healthy" : "unhealthy (SYS_STATUS)"});
    }
    // MAV_SYS_STATUS_PREARM_CHECK: the autopilot's own verdict, with its newest warning as why.
    if (s.onboard_control_sensors_present & kSensorPrearm) {
      const bool ok = (s.onboard_control_sensors_health & kSensorPrearm) != 0;
      r.checks.push_back({"pre-arm", ok, ok ? "the autopilot's checks pass"
                                            : (v.last_warning.empty() ? "the autopilot's checks fail" : v.last_warning)});
    }
    model.OnReport(v.id, std::move(r), now);
  }

  void OnHome(MavVehicle& v, const HomePosition& h) {
    GeodeticPoint home{h.latitude * 1e-7, h.longitude * 1e-7, h.altitude * 1e-3};
    try {
      ValidateGeodetic(home);
    } catch (const std::invalid_argument& e) {
      Say(v, std::string("HOME_POSITION ignored: ") + e.what(), Severity::kWarning);
      return;
    }
    const bool first = !v.home;
    if (!v.home || v.home->latitude_deg != home.latitude_deg || v.home->longitude_deg != home.longitude_deg ||
        v.home->altitude_m != home.altitude_m)
      v.frame = std::make_unique<LocalNedFrame>(home);
    v.home = home;
    v.state.home = home;
    if (first) {
      char text[128];
      std::snprintf(text, sizeof text, "home at %.7f, %.7f, %.1f m", home.latitude_deg, home.longitude_deg, home.altitude_m);
      Say(v, text, Severity::kInfo);
    }
  }

  void OnPosition(MavVehicle& v, const GlobalPositionInt& p) {
    if (!v.home) {
      if (now - v.last_home_request >= kHomeRequestPeriod) {
        v.last_home_request = now;
        RequestMessage(v, HomePosition::kId);
      }
      return;  // positions are from home: none to show until the vehicle says where it is
    }
    VehicleState& s = v.state;
    s.utime = int64_t{p.time_boot_ms} * 1000;
    s.gps = {p.lat * 1e-7, p.lon * 1e-7, p.alt * 1e-3};
    s.p_N = v.frame->ToNed(s.gps);
    s.p_N.z() = -p.relative_alt * 1e-3;  // the autopilot's own height above home
    const Eigen::Vector3d v_N(p.vx * 1e-2, p.vy * 1e-2, p.vz * 1e-2);
    s.v_B = RotationNBFromEuler(s.euler).transpose() * v_N;
    s.armed = v.armed;
    s.landed = v.landed_state ? v.landed_state == 1 : (!v.armed || s.altitude() < 0.3);
    s.mission_item = s.task == Task::kMission && v.mission_seq >= 0 ? MissionIndex(v, v.mission_seq) : -1;
    // The model counts a jump in a group's sequence as messages missed: the frames this vehicle
    // sent that never came (MAVLink's sequence counts every frame, not each message).
    v.state_seq += 1 + (v.lost - v.lost_counted);
    v.lost_counted = v.lost;
    model.OnState(v.id, v.state_seq, s, now);
    WatchCommands(v);
  }

  int MissionIndex(const MavVehicle& v, int seq) const { return HomeIsMissionItemZero(v.autopilot) ? seq - 1 : seq; }

  void OnMissionCurrent(MavVehicle& v, int seq) { v.mission_seq = seq; }

  void OnReached(MavVehicle& v, int seq) {
    const int index = MissionIndex(v, seq);
    if (index < 0 || index == v.last_reached) return;
    v.last_reached = index;
    const int total = v.mission_items;
    char text[96];
    if (total > 0 && index == total - 1)
      std::snprintf(text, sizeof text, "mission item %d of %d reached: the last", index + 1, total);
    else if (total > 0)
      std::snprintf(text, sizeof text, "mission item %d of %d reached", index + 1, total);
    else
      std::snprintf(text, sizeof text, "mission item %d reached", index + 1);
    Say(v, text, Severity::kInfo);
    if (total > 0 && index == total - 1) Complete(v, MavlinkPlan::Completion::kMissionEnd, "the mission's last item reached");
  }

  // ---- commands ----
  uav::CommandAck AckOf(const PendingCommand& c, CommandResult r, const std::string& reason, int percent = 0) {
    uav::CommandAck a;
    a.source = model.gcs_name();
    a.command_seq = c.command_seq;
    a.command = c.name;
    a.result = r;
    a.reason = reason;
    a.percent = percent;
    return a;
  }
  void Answer(MavVehicle& v, PendingCommand& c, CommandResult r, const std::string& reason, int percent = 0) {
    c.last = AckOf(c, r, reason, percent);
    if (r != CommandResult::kInProgress && r != CommandResult::kAccepted) c.finished = true;
    model.OnAck(v.id, c.last, now);
  }

  void OnCommand(MavVehicle& v, const OutgoingCommand& out) {
    auto existing = v.commands.find(out.command_seq);
    if (existing != v.commands.end()) {  // the GCS resends: the vehicle has not answered this step
      PendingCommand& c = existing->second;
      if (c.finished || c.watching) return model.OnAck(v.id, c.last, now);
      if (c.step < c.plan.steps.size()) SendStep(v, c.plan.steps[c.step], ++c.confirmation);
      return;
    }
    if (out.text.rfind("param ", 0) == 0) return OnParamSet(v, out);
    PendingCommand c;
    c.command_seq = out.command_seq;
    c.name = out.text.substr(0, out.text.find(' '));
    if (!v.home) {
      c.plan.refusal = "no home position from the vehicle yet";
    } else {
      c.plan = PlanMavlinkCommand(out.text, v.autopilot, IsVtolType(v.mav_type), *v.home);
    }
    if (!c.plan.refusal.empty()) {
      PendingCommand& kept = v.commands[c.command_seq] = c;
      return Answer(v, kept, CommandResult::kRejected, c.plan.refusal);
    }
    // A new command replaces one that was still being flown.
    for (auto& [seq, other] : v.commands)
      if (other.watching) {
        other.watching = false;
        Answer(v, other, CommandResult::kReplaced, c.name);
      }
    PendingCommand& kept = v.commands[c.command_seq] = c;
    SendStep(v, kept.plan.steps[0], 0);
    while (v.commands.size() > 50) v.commands.erase(v.commands.begin());
  }

  void OnCommandAck(MavVehicle& v, const mavlink::CommandAck& a, const Frame&) {
    if (a.target_system != 0 && a.target_system != kGcsSystem) return;
    for (auto& [seq, c] : v.commands) {
      if (c.finished || c.watching || c.step >= c.plan.steps.size() || c.plan.steps[c.step].command != a.command) continue;
      const MavlinkStep& step = c.plan.steps[c.step];
      if (a.result == kResultInProgress) return Answer(v, c, CommandResult::kInProgress, step.what, a.progress <= 100 ? a.progress : 0);
      if (a.result != kResultAccepted) {
        std::string why = step.what + ": " + MavResultName(a.result);
        if (now - v.last_warning_at < 2.0) why += " (" + v.last_warning + ")";
        return Answer(v, c, a.result == 4 || a.result == 6 ? CommandResult::kFailed : CommandResult::kRejected, why);
      }
      if (++c.step < c.plan.steps.size()) {  // the next step at once
        c.confirmation = 0;
        Answer(v, c, CommandResult::kInProgress, step.what + " accepted",
               static_cast<int>(100 * c.step / c.plan.steps.size()));
        return SendStep(v, c.plan.steps[c.step], 0);
      }
      if (c.plan.completion == MavlinkPlan::Completion::kOnAccept) return Answer(v, c, CommandResult::kCompleted, "");
      c.watching = true;
      return Answer(v, c, CommandResult::kAccepted, "");
    }
    if (a.command == mav_cmd::kTrackRectangle || a.command == mav_cmd::kStopTracking) {
      const bool ok = a.result == kResultAccepted || a.result == kResultInProgress;
      Say(v, std::string("camera: tracking ") + (a.command == mav_cmd::kStopTracking ? "stop " : "rectangle ") +
                 MavResultName(a.result),
          ok ? Severity::kInfo : Severity::kWarning);
    }
  }

  // The commands accepted and being flown: done when the vehicle gets there.
  void WatchCommands(MavVehicle& v) {
    const VehicleState& s = v.state;
    for (auto& [seq, c] : v.commands) {
      if (!c.watching) continue;
      const MavlinkPlan& p = c.plan;
      bool done = false;
      switch (p.completion) {
        case MavlinkPlan::Completion::kAltitude: done = std::abs(s.altitude() - p.target_alt_m) <= std::max(0.5, 0.05 * p.target_alt_m); break;
        case MavlinkPlan::Completion::kPosition:
          done = std::hypot(s.p_N.x() - p.target_north_m, s.p_N.y() - p.target_east_m) <= 1.5 &&
                 std::abs(s.altitude() - p.target_alt_m) <= 1.0;
          break;
        case MavlinkPlan::Completion::kLanded: done = s.landed && !v.armed; break;
        default: break;
      }
      if (done) {
        c.watching = false;
        Answer(v, c, CommandResult::kCompleted, "");
      }
    }
  }
  void Complete(MavVehicle& v, MavlinkPlan::Completion kind, const std::string& why) {
    for (auto& [seq, c] : v.commands)
      if (c.watching && c.plan.completion == kind) {
        c.watching = false;
        Answer(v, c, CommandResult::kCompleted, why);
      }
  }

  // ---- parameters ----
  void StartParamList(MavVehicle& v) {
    ParamRequestList r;
    r.target_system = v.sysid, r.target_component = v.compid;
    Send(r);
    v.param_last = now;
    ++v.param_tries;
  }

  void OnParamValue(MavVehicle& v, const ParamValue& m) {
    const std::string id = Text(m.param_id);
    const std::optional<double> value = DecodeParamValue(m.param_value, m.param_type, v.encoding);
    v.param_last = now;
    v.param_tries = 0;
    if (m.param_count > 0 && m.param_count != 65535) v.param_count = m.param_count;
    int index = m.param_index;
    if (index == 65535) {  // an answer to a set or a read by name: find it by its id
      index = -1;
      for (const auto& [i, p] : v.params)
        if (p.id == id) index = i;
    }
    if (index >= 0) v.params[index] = {id, m.param_value, m.param_type};  // counted even when not shown (64-bit)
    for (PendingParam& p : v.param_sets) {
      if (p.finished || p.id != id) continue;
      p.finished = true;
      const bool took = value && static_cast<float>(*value) == static_cast<float>(p.value);
      p.last = ParamAck(p, took ? CommandResult::kCompleted : CommandResult::kRejected,
                        took ? "" : "the vehicle kept " + id + " at " + (value ? FormatParameterValue(*value) : "?"));
      model.OnAck(v.id, p.last, now);
    }
    const bool complete = v.param_count >= 0 && static_cast<int>(v.params.size()) >= v.param_count;
    if (complete && !v.params_complete) {
      v.params_complete = true;
      Say(v, std::to_string(v.param_count) + " parameters received (" +
                 (v.encoding == ParamEncoding::kBytewise ? "byte-wise" : "C-cast") + " encoding)",
          Severity::kInfo);
      if (!v.first_download_done) {  // as QGroundControl: the parameters, then the mission
        v.first_download_done = true;
        QueueTransfer(v, DownloadTransfer(false));
      }
    }
    if (v.params_complete) PublishTable(v);
  }

  void PublishTable(MavVehicle& v) {
    ParameterTable t;
    t.utime = WallTimeMicros();
    t.version = ++v.param_version;
    for (const auto& [i, p] : v.params) {
      const std::optional<double> value = DecodeParamValue(p.wire, p.type, v.encoding);
      if (!value) continue;  // a type the float cannot carry: not shown, never made up
      ParameterEntry e;
      e.name = p.id;
      e.value = *value;
      e.default_value = NAN;
      e.unit = ParamTypeName(p.type);
      e.description = std::string(Name(v.autopilot)) + " parameter";
      e.min = -1e30, e.max = 1e30;
      e.apply = ParamApply::kInFlight;  // the autopilot says what it refuses
      e.mavlink_type = p.type;
      t.entries.push_back(std::move(e));
    }
    std::sort(t.entries.begin(), t.entries.end(), [](const ParameterEntry& a, const ParameterEntry& b) { return a.name < b.name; });
    model.OnReport(v.id, std::move(t), now);
  }

  uav::CommandAck ParamAck(const PendingParam& p, CommandResult r, const std::string& reason) {
    uav::CommandAck a;
    a.source = model.gcs_name();
    a.command_seq = p.command_seq;
    a.command = "param";
    a.result = r;
    a.reason = reason;
    return a;
  }

  void OnParamSet(MavVehicle& v, const OutgoingCommand& out) {
    for (PendingParam& p : v.param_sets)
      if (p.command_seq == out.command_seq) {
        if (p.finished) return model.OnAck(v.id, p.last, now);
        return SendParamSet(v, p);
      }
    PendingParam p;
    p.command_seq = out.command_seq;
    char name[64] = {0}, value[64] = {0};
    std::sscanf(out.text.c_str(), "param %63s %63s", name, value);
    p.id = name;
    const Param* known = nullptr;
    for (const auto& [i, q] : v.params)
      if (q.id == p.id) known = &q;
    std::string why;
    const std::optional<double> parsed = ParseDecimal(value);
    std::optional<float> wire;
    if (!known) why = "the vehicle has no parameter '" + p.id + "'";
    else if (!parsed) why = std::string("'") + value + "' is not a number";
    else wire = EncodeParamValue(*parsed, known->type, v.encoding, &why);
    if (!wire) {
      p.finished = true;
      p.last = ParamAck(p, CommandResult::kRejected, p.id + ": " + why);
      v.param_sets.push_back(p);
      return model.OnAck(v.id, p.last, now);
    }
    p.value = *parsed;
    p.wire = *wire;
    p.type = known->type;
    v.param_sets.push_back(p);
    SendParamSet(v, v.param_sets.back());
    while (v.param_sets.size() > 50) v.param_sets.erase(v.param_sets.begin());
  }

  void SendParamSet(MavVehicle& v, PendingParam& p) {
    ParamSet m;
    m.target_system = v.sysid, m.target_component = v.compid;
    SetText(m.param_id, p.id);
    m.param_value = p.wire;
    m.param_type = p.type;
    p.sent = now;
    ++p.tries;
    Send(m);
  }

  void TickParams(MavVehicle& v) {
    if (v.params_complete || now - v.param_last < params.retry_s) return;
    if (v.param_tries >= params.max_tries) {
      if (v.param_tries == params.max_tries) {
        ++v.param_tries;
        Say(v, "parameters: " + std::to_string(v.params.size()) + " of " +
                   (v.param_count >= 0 ? std::to_string(v.param_count) : std::string("?")) + " after " +
                   std::to_string(params.max_tries) + " requests: the vehicle does not answer",
            Severity::kWarning);
      }
      return;
    }
    if (v.param_count < 0) return StartParamList(v);
    // The ones missing, by index (at most 20 a round, as a radio would carry them).
    int asked = 0;
    for (int i = 0; i < v.param_count && asked < 20; ++i) {
      if (v.params.count(i)) continue;
      ParamRequestRead r;
      r.target_system = v.sysid, r.target_component = v.compid;
      r.param_index = static_cast<int16_t>(i);
      Send(r);
      ++asked;
    }
    v.param_last = now;
    ++v.param_tries;
  }

  // ---- missions ----
  Transfer DownloadTransfer(bool for_editor) {
    Transfer t;
    t.upload = false;
    t.for_editor = for_editor;
    t.lists = {MavMissionList::kMission, MavMissionList::kFence, MavMissionList::kRally};
    return t;
  }

  void QueueTransfer(MavVehicle& v, Transfer t) {
    if (v.transfer) return v.queued.push_back(std::move(t));
    v.transfer = std::move(t);
    StartList(v);
  }

  void OnUpload(MavVehicle& v, const OutgoingMission& m) {
    if (!v.home) {
      waypoints::MissionUploadAck a;
      a.upload_id = m.upload_id;
      a.total_items = static_cast<int>(m.mission.items.size());
      a.result = waypoints::MissionUploadAck::Result::kRejected;
      a.reason = "no home position from the vehicle yet";
      return model.OnMissionAck(v.id, model.gcs_name(), a, now);
    }
    Transfer t;
    t.upload = true;
    t.upload_id = m.upload_id;
    t.mission = m.mission;
    t.digest = waypoints::MissionDigest(m.mission);
    t.lists = {MavMissionList::kMission, MavMissionList::kFence, MavMissionList::kRally};
    QueueTransfer(v, std::move(t));
  }

  void StartList(MavVehicle& v) {
    Transfer& t = *v.transfer;
    const MavMissionList list = t.lists.front();
    t.items.clear();
    t.next = 0;
    t.tries = 0;
    t.last = now;
    t.expected = -1;
    if (t.upload) {
      t.items = waypoints::ItemsOf(t.mission, list);
      if (list == MavMissionList::kMission && HomeIsMissionItemZero(v.autopilot)) {
        // ArduPilot's item 0 is home (it sets its own; this one is the mission's planned home).
        waypoints::MissionItem home;
        home.command = waypoints::mav_cmd::kNavWaypoint;
        home.frame = waypoints::mav_frame::kGlobal;
        home.latitude_deg = v.home->latitude_deg, home.longitude_deg = v.home->longitude_deg;
        home.altitude_m = v.home->altitude_m;
        t.items.insert(t.items.begin(), home);
      }
      MissionCount c;
      c.target_system = v.sysid, c.target_component = v.compid;
      c.count = static_cast<uint16_t>(t.items.size());
      c.mission_type = static_cast<uint8_t>(list);
      Send(c);
    } else {
      MissionRequestList r;
      r.target_system = v.sysid, r.target_component = v.compid;
      r.mission_type = static_cast<uint8_t>(list);
      Send(r);
    }
  }

  void UploadProgress(MavVehicle& v) {
    Transfer& t = *v.transfer;
    waypoints::MissionUploadAck a;
    a.upload_id = t.upload_id;
    a.total_items = static_cast<int>(t.mission.items.size());
    const int home = t.lists.front() == MavMissionList::kMission && HomeIsMissionItemZero(v.autopilot) ? 1 : 0;
    a.received_items = std::min(a.total_items, t.sent_before + std::max(0, t.next - home));
    a.result = waypoints::MissionUploadAck::Result::kInProgress;
    model.OnMissionAck(v.id, model.gcs_name(), a, now);
  }

  void OnMissionRequest(MavVehicle& v, int seq, uint8_t type) {
    if (!v.transfer || !v.transfer->upload || type != static_cast<uint8_t>(v.transfer->lists.front())) return;
    Transfer& t = *v.transfer;
    if (seq < 0 || seq >= static_cast<int>(t.items.size())) return;
    MissionItemInt m = waypoints::ToItemInt(t.items[seq], static_cast<uint16_t>(seq), t.lists.front());
    m.target_system = v.sysid, m.target_component = v.compid;
    Send(m);
    t.last = now;
    t.tries = 0;
    t.next = std::max(t.next, seq + 1);
    UploadProgress(v);
  }

  void OnMissionAck(MavVehicle& v, const MissionAck& a) {
    if (!v.transfer || a.mission_type != static_cast<uint8_t>(v.transfer->lists.front())) return;
    Transfer& t = *v.transfer;
    const MavMissionList list = t.lists.front();
    if (!t.upload) return;  // a download's acks are ours to send
    if (a.type != kMissionAccepted) {
      // An empty fence or rally list that the autopilot does not keep is no loss.
      if (a.type == 3 && list != MavMissionList::kMission && t.items.empty()) return NextList(v, std::string(Name(list)) + " not kept");
      std::string why = std::string("the vehicle refused the ") + Name(list) + ": " + MissionResultName(a.type);
      if (now - v.last_warning_at < 3.0) why += " (" + v.last_warning + ")";
      return FinishUpload(v, false, why);
    }
    if (static_cast<int>(t.items.size()) > 0 && t.next < static_cast<int>(t.items.size()))
      return FinishUpload(v, false, std::string("the vehicle accepted the ") + Name(list) + " before asking for all of it");
    t.sent_before += static_cast<int>(waypoints::ItemsOf(t.mission, list).size());
    NextList(v, std::string(Name(list)) + " of " + std::to_string(waypoints::ItemsOf(t.mission, list).size()));
  }

  void NextList(MavVehicle& v, const std::string& done) {
    Transfer& t = *v.transfer;
    t.done.push_back(done);
    t.lists.erase(t.lists.begin());
    if (!t.lists.empty()) return StartList(v);
    if (t.upload) return FinishUpload(v, true, "");
    FinishDownload(v, true, "");
  }

  void FinishUpload(MavVehicle& v, bool ok, const std::string& why) {
    Transfer t = std::move(*v.transfer);
    v.transfer.reset();
    waypoints::MissionUploadAck a;
    a.upload_id = t.upload_id;
    a.total_items = static_cast<int>(t.mission.items.size());
    if (ok) {
      a.result = waypoints::MissionUploadAck::Result::kAccepted;
      a.received_items = a.total_items;
      a.digest = t.digest;
      v.mission_items = static_cast<int>(waypoints::ItemsOf(t.mission, MavMissionList::kMission).size());
      v.last_reached = -1;
      std::string lists;
      for (const std::string& d : t.done) lists += (lists.empty() ? "" : ", ") + d;
      Say(v, "uploaded by the mission service: " + lists, Severity::kInfo);
    } else {
      a.result = waypoints::MissionUploadAck::Result::kRejected;
      a.reason = why;
      // Lists already replaced stay replaced on the vehicle: say which, and show what it holds.
      if (!t.done.empty()) {
        std::string lists;
        for (const std::string& d : t.done) lists += (lists.empty() ? "" : ", ") + d;
        a.reason += "; the vehicle already holds the new " + lists + ": its mission is downloaded to show it";
        v.queued.insert(v.queued.begin(), DownloadTransfer(false));
      }
    }
    model.OnMissionAck(v.id, model.gcs_name(), a, now);
    NextTransfer(v);
  }

  void NextTransfer(MavVehicle& v) {
    if (v.transfer || v.queued.empty()) return;
    v.transfer = std::move(v.queued.front());
    v.queued.erase(v.queued.begin());
    StartList(v);
  }

  void OnMissionCount(MavVehicle& v, const MissionCount& c) {
    if (!v.transfer || v.transfer->upload || c.mission_type != static_cast<uint8_t>(v.transfer->lists.front())) return;
    Transfer& t = *v.transfer;
    if (t.expected >= 0) return;  // a repeat
    t.expected = c.count;
    t.tries = 0;
    t.last = now;
    if (c.count == 0) return EndDownloadList(v);
    RequestItem(v);
  }

  void RequestItem(MavVehicle& v) {
    Transfer& t = *v.transfer;
    MissionRequestInt r;
    r.target_system = v.sysid, r.target_component = v.compid;
    r.seq = static_cast<uint16_t>(t.next);
    r.mission_type = static_cast<uint8_t>(t.lists.front());
    Send(r);
    t.last = now;
  }

  void OnMissionItem(MavVehicle& v, const MissionItemInt& m) {
    if (!v.transfer || v.transfer->upload || m.mission_type != static_cast<uint8_t>(v.transfer->lists.front())) return;
    Transfer& t = *v.transfer;
    if (m.seq != t.next || t.expected < 0) return;  // a repeat: our request for the next stands
    const MavMissionList list = t.lists.front();
    std::string why;
    waypoints::ItemProblem problem;
    const waypoints::MissionItem it = waypoints::FromItemInt(m, list, &problem, &why);
    const bool home_item = list == MavMissionList::kMission && m.seq == 0 && HomeIsMissionItemZero(v.autopilot);
    if (problem != waypoints::ItemProblem::kNone && !home_item)
      return FinishDownload(v, false, std::string(Name(list)) + " item " + std::to_string(m.seq) + ": " + why);
    if (!home_item) t.items.push_back(it);
    t.tries = 0;
    if (++t.next < t.expected) return RequestItem(v);
    EndDownloadList(v);
  }

  void EndDownloadList(MavVehicle& v) {
    Transfer& t = *v.transfer;
    MissionAck a;
    a.target_system = v.sysid, a.target_component = v.compid;
    a.type = kMissionAccepted;
    a.mission_type = static_cast<uint8_t>(t.lists.front());
    Send(a);
    t.mission.items.insert(t.mission.items.end(), t.items.begin(), t.items.end());
    const MavMissionList list = t.lists.front();
    NextList(v, std::string(Name(list)) + " of " + std::to_string(t.items.size()));
  }

  void FinishDownload(MavVehicle& v, bool ok, const std::string& why) {
    Transfer t = std::move(*v.transfer);
    v.transfer.reset();
    if (!ok) {
      Say(v, "mission download failed: " + why + (t.for_editor ? "; the editor is left as it is" : ""), Severity::kWarning);
    } else {
      t.mission.home = *v.home;
      v.mission_items = static_cast<int>(waypoints::ItemsOf(t.mission, MavMissionList::kMission).size());
      std::string lists;
      for (const std::string& d : t.done) lists += (lists.empty() ? "" : ", ") + d;
      Say(v, "downloaded from the mission service: " + lists, Severity::kInfo);
      model.OnMissionDownloaded(v.id, t.mission, t.for_editor, now);
    }
    NextTransfer(v);
  }

  void TickTransfer(MavVehicle& v) {
    if (!v.transfer) {
      NextTransfer(v);
      return;
    }
    Transfer& t = *v.transfer;
    if (now - t.last < params.retry_s) return;
    const MavMissionList list = t.lists.front();
    if (t.tries >= params.max_tries) {
      const std::string where = t.upload ? (t.next == 0 ? "it never asked for an item"
                                                        : "it stopped asking at item " + std::to_string(t.next) + " of " +
                                                              std::to_string(t.items.size()))
                                         : (t.expected < 0 ? "it never said how many items it holds"
                                                           : "it stopped sending at item " + std::to_string(t.next) + " of " +
                                                                 std::to_string(t.expected));
      const bool home_counted = list == MavMissionList::kMission && HomeIsMissionItemZero(v.autopilot) && t.next > 0;
      const std::string why = std::string("no answer from the vehicle about its ") + Name(list) + " for " +
                              FormatParameterValue(params.retry_s * params.max_tries) + " s: " + where +
                              (home_counted ? " (its numbering: home is item 0)" : "");
      if (t.upload) return FinishUpload(v, false, why);
      // A fence or rally list that never comes: the autopilot may not keep one.
      if (list != MavMissionList::kMission && t.expected < 0) return NextList(v, std::string(Name(list)) + " not kept");
      return FinishDownload(v, false, why);
    }
    ++t.tries;
    t.last = now;
    if (t.upload) {
      if (t.next == 0) {  // the count again
        MissionCount c;
        c.target_system = v.sysid, c.target_component = v.compid;
        c.count = static_cast<uint16_t>(t.items.size());
        c.mission_type = static_cast<uint8_t>(list);
        Send(c);
      } else {  // the last item asked for, again
        MissionItemInt m = waypoints::ToItemInt(t.items[t.next - 1], static_cast<uint16_t>(t.next - 1), list);
        m.target_system = v.sysid, m.target_component = v.compid;
        Send(m);
      }
    } else if (t.expected < 0) {
      MissionRequestList r;
      r.target_system = v.sysid, r.target_component = v.compid;
      r.mission_type = static_cast<uint8_t>(list);
      Send(r);
    } else {
      RequestItem(v);
    }
  }

  // ---- the rest ----
  void Tick(MavVehicle& v) {
    TickParams(v);
    TickTransfer(v);
    for (PendingParam& p : v.param_sets)
      if (!p.finished && p.tries >= params.max_tries && now - p.sent >= params.retry_s) {
        p.finished = true;
        p.last = ParamAck(p, CommandResult::kFailed, "no PARAM_VALUE from the vehicle after " + std::to_string(p.tries) + " tries");
        model.OnAck(v.id, p.last, now);
      }
  }

  void PollVideo() {
    if (!video) return;
    VideoPixels pixels;
    if (!video->Take(&pixels)) return;
    // The stream is the vehicle's that announced one, else the first MAVLink vehicle's.
    const MavVehicle* owner = nullptr;
    for (const auto& [sysid, v] : vehicles)
      if (!owner || (v.video_announced && !owner->video_announced)) owner = &v;
    if (!owner) return;
    model.OnVideoPixels(owner->id, pixels, now);
  }

  MavVehicle* VehicleNamed(const std::string& id) {
    for (auto& [sysid, v] : vehicles)
      if (v.id == id) return &v;
    return nullptr;
  }

  void SendTarget(MavVehicle& v, const TrackTarget& t) {
    MavlinkStep s;
    s.component = kCompCamera;
    if (t.method == TrackTarget::kCancel) {
      s.command = mav_cmd::kStopTracking;
    } else {  // CAMERA_TRACK_RECTANGLE: top-left and bottom-right corners, 0..1 of the image
      s.command = mav_cmd::kTrackRectangle;
      s.param[0] = static_cast<float>(t.x), s.param[1] = static_cast<float>(t.y);
      s.param[2] = static_cast<float>(t.x + t.width), s.param[3] = static_cast<float>(t.y + t.height);
    }
    SendStep(v, s, 0);
    Say(v, s.command == mav_cmd::kStopTracking ? "camera: stop tracking sent" : "camera: CAMERA_TRACK_RECTANGLE sent",
        Severity::kInfo);
  }

  template <class T, class F>
  void TakeMine(std::vector<T>& all, F&& handle) {
    std::vector<T> rest;
    for (T& e : all) {
      MavVehicle* v = VehicleNamed(VehicleOf(e));
      if (v) handle(*v, e);
      else rest.push_back(std::move(e));
    }
    all = std::move(rest);
  }
  static const std::string& VehicleOf(const OutgoingCommand& c) { return c.vehicle_id; }
  static const std::string& VehicleOf(const OutgoingMissionChunk& c) { return c.vehicle_id; }
  static const std::string& VehicleOf(const OutgoingMission& c) { return c.vehicle_id; }
  static const std::string& VehicleOf(const std::string& c) { return c; }
  static const std::string& VehicleOf(const OutgoingFileRequest& c) { return c.vehicle_id; }
  static const std::string& VehicleOf(const std::pair<std::string, ManualSticks>& c) { return c.first; }
  static const std::string& VehicleOf(const TrackTarget& c) { return c.vehicle_id; }

  void Send(GcsOutgoing& out, double t) {
    now = t;
    TakeMine(out.commands, [&](MavVehicle& v, const OutgoingCommand& c) { OnCommand(v, c); });
    TakeMine(out.missions, [&](MavVehicle& v, const OutgoingMission& m) { OnUpload(v, m); });
    TakeMine(out.mission_downloads, [&](MavVehicle& v, const std::string&) { QueueTransfer(v, DownloadTransfer(true)); });
    TakeMine(out.mission_chunks, [](MavVehicle&, const OutgoingMissionChunk&) {});  // whole missions only
    TakeMine(out.file_requests, [](MavVehicle&, const OutgoingFileRequest&) {});    // it offers no files
    TakeMine(out.sticks, [&](MavVehicle& v, const std::pair<std::string, ManualSticks>&) {
      if (!std::exchange(v.said_no_sticks, true))
        Say(v, "sticks are not sent to a MAVLink vehicle: fly it with its own radio", Severity::kWarning);
    });
    TakeMine(out.targets, [&](MavVehicle& v, const TrackTarget& target) { SendTarget(v, target); });
  }
};

MavlinkLink::MavlinkLink(const MavlinkLinkParams& params, GcsModel& model) : impl_(std::make_unique<Impl>(params, model)) {}
MavlinkLink::~MavlinkLink() = default;
void MavlinkLink::Receive(double now) { impl_->Receive(now); }
void MavlinkLink::ReceiveBytes(const uint8_t* data, std::size_t size, double now) { impl_->Receive(now, data, size); }
void MavlinkLink::Send(GcsOutgoing& out, double now) { impl_->Send(out, now); }
MavlinkLink::Counts MavlinkLink::counts() const { return impl_->counts; }

}  // namespace uav::gcs
