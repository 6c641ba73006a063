// The MAVLink endpoint's services (mavlink.io: heartbeat, command, mission, parameter and camera
// protocols), translated onto the vehicle's own link messages. PX4's conventions where QGroundControl
// depends on them: custom modes (px4_custom_mode.h), COMMAND_ACK per command, PARAM_VALUE as
// the answer to PARAM_SET, STATUSTEXT for every refusal.
#include "uav/runtime/mavlink_endpoint.hpp"

#include <cmath>
#include <cstdio>
#include <deque>
#include <map>
#include <set>

#include <Eigen/Geometry>

#include "uav/shared/mavlink_transport.hpp"
#include "uav/waypoints/mavlink_items.hpp"
#include "mavlink_video.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "uav/shared/mavlink_px4.hpp"
#include "uav/shared/time.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uav/wire/bus.hpp"
#include "uav/wire/messages.hpp"
#include "uav/wire/reports.hpp"
#include "uav/wire/signed_message.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"

namespace uav::runtime {
namespace {

using namespace uav::mavlink;

// MAVLink enums (common.xml), the values we use.
constexpr uint8_t kCompAutopilot = 1, kCompCamera = 100;
constexpr uint8_t kTypeQuadrotor = 2, kTypeGcs = 6, kTypeVtolTailsitterQuad = 20, kTypeCamera = 30;
constexpr uint8_t kAutopilotPx4 = 12, kAutopilotInvalid = 8;
constexpr uint8_t kModeFlagCustom = 1, kModeFlagAuto = 4, kModeFlagGuided = 8, kModeFlagStabilize = 16,
                  kModeFlagArmed = 128;
constexpr uint8_t kStateStandby = 3, kStateActive = 4, kStateCritical = 5;
enum MavResult : uint8_t { kResultAccepted = 0, kResultTemporarilyRejected = 1, kResultDenied = 2, kResultUnsupported = 3,
                           kResultFailed = 4, kResultInProgress = 5, kResultCancelled = 6 };
enum MissionResult : uint8_t { kMissionAccepted = 0, kMissionError = 1, kMissionUnsupportedFrame = 2,
                               kMissionUnsupported = 3, kMissionInvalid = 5, kMissionInvalidSequence = 13,
                               kMissionDenied = 14, kMissionCancelled = 15 };
enum MissionType : uint8_t { kTypeMission = 0, kTypeFence = 1, kTypeRally = 2, kTypeAll = 255 };
constexpr uint8_t kParamReal32 = 9;
// MAV_CMD
constexpr uint16_t kCmdNavReturn = 20, kCmdNavLand = 21, kCmdNavTakeoff = 22, kCmdDoSetMode = 176,
                   kCmdDoReposition = 192, kCmdMissionStart = 300, kCmdArmDisarm = 400, kCmdSetMessageInterval = 511,
                   kCmdRequestMessage = 512, kCmdRequestCapabilities = 520, kCmdTrackRectangle = 2005,
                   kCmdStopTracking = 2010, kCmdVtolTransition = 3000;
constexpr float kForceDisarm = 21196.f;  // param2 of COMPONENT_ARM_DISARM: disarm in flight (a kill)
// AUTOPILOT_VERSION capabilities: MISSION_FLOAT 1, PARAM_FLOAT 2, MISSION_INT 4, COMMAND_INT 8,
// SET_POSITION_TARGET_GLOBAL_INT 64 (not claimed), MISSION_FENCE 1024, MISSION_RALLY 2048, MAVLINK2 8192.
constexpr uint64_t kCapabilities = 2 | 4 | 8 | 1024 | 2048 | 8192;
// SYS_STATUS sensor bits (MAV_SYS_STATUS_SENSOR).
constexpr uint32_t kSensorGyro = 1, kSensorAccel = 2, kSensorGps = 32, kSensorVisionPosition = 256,
                   kSensorMotorOutputs = 32768, kSensorGeofence = 1u << 20, kSensorAhrs = 1u << 21,
                   kSensorBattery = 1u << 25, kSensorPrearm = 1u << 28;

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", v);
  return buf;
}

// One MAVLink command as the two command messages carry it.
struct MavCommand {
  uint16_t command = 0;
  uint8_t target_component = 0;
  std::array<float, 7> param{};
  bool has_int_position = false;  // COMMAND_INT: x, y in 1e-7 degrees, z in frame `frame`
  int32_t x = 0, y = 0;
  uint8_t frame = 0;
  uint8_t confirmation = 0;
  uint8_t sysid = 0, compid = 0;  // the sender
};

struct Outcome {  // a command as the vehicle's text, or the result it is refused with
  Outcome(std::string t) : text(std::move(t)) {}  // NOLINT: a text is an outcome
  Outcome(std::string t, uint8_t r, std::string w) : text(std::move(t)), refused(r), why(std::move(w)) {}
  std::string text;
  uint8_t refused = kResultAccepted;
  std::string why;
};

struct Said {  // a status text of the vehicle's, to repeat as STATUSTEXT
  Severity severity;
  std::string text;
};

}  // namespace

struct MavlinkEndpoint::Impl {
  Impl(const std::string& id, Bus& b, const MavlinkParams& p, const std::optional<SigningKey>& k, Say s)
      : vehicle_id(id), bus(b), params(p), key(k), say(std::move(s)), transport(OpenMavlinkTransport(p.endpoint)),
        parser(Lookup()), streams(k ? k->bytes : SecretKey{}, p.insecure || !k),
        source("mavlink:" + std::to_string(p.system_id)) {
    if (key) signer.emplace(*key, kLinkId);
    if (p.video_port > 0 && !p.video_host.empty()) video = std::make_unique<MavlinkVideo>(p.video_host, p.video_port);
    Subscribe();
  }

  static constexpr int kLinkId = 200;  // the endpoint's link id on the bus (signing)
  std::string vehicle_id;
  Bus& bus;
  MavlinkParams params;
  std::optional<SigningKey> key;
  Say say;
  std::optional<MessageSigner> signer;
  std::unique_ptr<MavlinkTransport> transport;
  std::unique_ptr<MavlinkVideo> video;
  Parser parser;
  SignedStreams streams;
  std::string source;  // our name on the bus
  Counts counts;
  uint8_t seq = 0;
  int64_t now = 0, start = -1;
  std::map<Topic, int64_t> bus_seq;

  // What the vehicle said last.
  std::optional<VehicleState> state;
  std::optional<PreArmReport> prearm;
  std::optional<ParameterTable> table;
  std::map<std::string, std::string> param_by_id;  // MAVLink id -> our name
  // The camera MAVLink sees (component 100): the tracker's when the vehicle has one (SENSING names
  // it), else the first that streams video; its newest frame's time and size.
  std::optional<VideoFrame> last_frame;
  std::string tracking_camera;
  std::deque<Said> texts;
  int last_item = -1;  // MISSION_CURRENT's last seq
  bool in_mission = false;
  bool finishing = false;  // the mission's last item (a return, a landing) until the vehicle is down

  // The GCS on the other side.
  bool gcs_seen = false;

  // Commands in flight: our command_seq -> the MAVLink command it carries.
  struct Pending {
    MavCommand cmd;
    bool param_set = false;
    std::string param_name;
    bool final_sent = false;
    // The bus message and its resends (see ResendUnanswered).
    uavmsg::command_t message{};
    int64_t published_us = 0;  // monotonic
    int publications = 0;
    bool answered = false;
  };
  int64_t command_seq = 0;
  std::map<int64_t, Pending> pending;
  std::map<int64_t, MavCommand> pending_tracks;  // target_seq -> CAMERA_TRACK_RECTANGLE, until the tracker answers
  std::set<std::string> param_echo;  // names to send PARAM_VALUE for with the next table
  std::deque<int> param_list;        // indices still to send for a PARAM_REQUEST_LIST

  // Missions, fence and rally: the vehicle's (seen on the bus, from any GCS) and ours in transfer.
  std::optional<waypoints::Mission> vehicle_mission;
  std::map<std::string, waypoints::MissionAssembler> observed;  // per GCS, uploads on the bus
  std::map<std::string, waypoints::Mission> observed_done;
  struct Upload {
    uint8_t type = kTypeMission;
    uint16_t count = 0;
    std::vector<waypoints::MissionItem> items;
    int64_t last_us = 0;
    int retries = 0;
    uint8_t sysid = 0, compid = 0;
  };
  std::optional<Upload> upload;  // items arriving from the GCS
  std::optional<waypoints::MissionUploader> uploader;  // the combined mission going to the vehicle
  uint8_t uploader_type = kTypeMission;
  std::map<uint8_t, std::vector<waypoints::MissionItem>> download;  // per type: the list being read

  // Telemetry schedule: message id -> period [us] of vehicle time, and when each was last sent.
  std::map<uint32_t, int64_t> period = {{Heartbeat::kId, 1'000'000},     {SysStatus::kId, 1'000'000},
                                        {Attitude::kId, 100'000},        {GlobalPositionInt::kId, 200'000},
                                        {VfrHud::kId, 250'000},          {GpsRawInt::kId, 500'000},
                                        {BatteryStatus::kId, 1'000'000}, {ExtendedSysState::kId, 1'000'000},
                                        {MissionCurrent::kId, 1'000'000}, {HomePosition::kId, 5'000'000}};
  std::map<uint32_t, int64_t> sent_at;
  std::map<std::string, int64_t> refusal_said;  // a refusal reason -> wall clock it was last said

  // ---- sending ----
  template <class M>
  void Send(const M& m, uint8_t compid = kCompAutopilot) {
    Frame f;
    f.seq = seq++;
    f.sysid = static_cast<uint8_t>(params.system_id);
    f.compid = compid;
    f.msgid = M::kId;
    f.payload = Pack(m);
    const uint64_t ts = streams.NextTimestamp(static_cast<uint64_t>(SigningTimestamp(WallTimeMicros())));
    const std::vector<uint8_t> bytes = Encode(f, FindLayout(M::kId)->crc_extra, key ? &key->bytes : nullptr, 0, ts);
    if (transport->Send(bytes)) ++counts.frames_out;
  }
  void Text(Severity s, const std::string& text) {
    // Longer than 50 characters: chunks with one id (MAVLink 2 STATUSTEXT); the last chunk is
    // shorter than 50 (empty when the text fills the others), so its NUL ends the text.
    static uint16_t id = 0;
    ++id;
    const std::size_t chunks = text.size() <= 50 ? 1 : text.size() / 50 + 1;
    for (std::size_t i = 0; i < chunks; ++i) {
      Statustext t;
      t.severity = static_cast<uint8_t>(s);
      SetText(t.text, text.substr(std::min(text.size(), i * 50), 50));
      if (chunks > 1) t.id = id, t.chunk_seq = static_cast<uint8_t>(i);
      Send(t);
    }
  }
  void Ack(const MavCommand& c, uint8_t result, uint8_t progress = 0) {
    mavlink::CommandAck a;
    a.command = c.command;
    a.result = result;
    a.progress = progress;
    a.target_system = c.sysid;
    a.target_component = c.compid;
    Send(a, c.target_component == kCompCamera ? kCompCamera : kCompAutopilot);
  }
  template <class Msg>
  void Publish(Topic t, Msg& m) {
    m.header = uavmsg::header_t{vehicle_id, ++bus_seq[t]};
    if (signer) SignMessage(*signer, WallTimeMicros(), m);
    bus.Publish(Channel(vehicle_id, t), m);
  }

  // ---- from the bus ----
  // One subscription to the vehicle's own channel `t`: a message for another vehicle is ignored,
  // and one that does not convert (anyone on the network can publish on the bus) is counted and
  // dropped without ever stopping the link thread.
  template <class Msg, class F>
  void On(Topic t, F handle) {
    bus.Subscribe<Msg>(Channel(vehicle_id, t), [this, handle](const std::string&, const Msg& m) {
      if (m.header.vehicle_id != vehicle_id) return;
      try {
        handle(m);
      } catch (const std::exception&) {
        ++counts.bad_bus_messages;
      }
    });
  }

  void Subscribe() {
    On<uavmsg::vehicle_state_t>(Topic::kState, [this](const auto& m) { state = FromMessage(m); });
    On<uavmsg::pre_arm_t>(Report<PreArmReport>::kTopic, [this](const auto& m) { prearm = FromMessage(m); });
    On<uavmsg::param_table_t>(Report<ParameterTable>::kTopic, [this](const auto& m) { OnTable(FromMessage(m)); });
    On<uavmsg::status_text_t>(Topic::kStatusText, [this](const auto& m) {
      texts.push_back({static_cast<Severity>(std::clamp<int>(m.severity, 0, 7)), m.text});
    });
    On<uavmsg::command_ack_t>(Topic::kCommandAck, [this](const auto& m) {
      if (m.source == source) OnCommandAck(FromMessage(m));
    });
    // Every upload on the bus, whichever GCS sent it: the mission the vehicle accepts is the one a
    // MAVLink GCS downloads.
    On<uavmsg::mission_upload_t>(Topic::kMissionUpload, [this](const auto& m) {
      observed[m.source].Receive(waypoints::FromMessage(m), [this, &m](const waypoints::Mission& mission) {
        observed_done[m.source] = mission;
        return std::string();
      });
    });
    On<uavmsg::mission_ack_t>(Topic::kMissionAck, [this](const auto& m) { OnMissionAck(m); });
    On<uavmsg::sensing_t>(Report<SensingReport>::kTopic, [this](const auto& m) {
      for (const SensingWorker& w : FromMessage(m).workers)
        if (w.name == "TRK") tracking_camera = w.rig;
    });
    On<uavmsg::track_status_t>(Topic::kTrackStatus, [this](const auto& m) { OnTrackStatus(FromMessage(m)); });
    On<uavmsg::video_frame_t>(Topic::kVideo, [this](const auto& m) {
      VideoFrame f = FromMessage(m);
      const std::string& wanted = !tracking_camera.empty() ? tracking_camera : last_frame ? last_frame->camera : f.camera;
      if (f.camera != wanted) return;
      if (video) video->Push(f);
      f.jpeg.clear();
      last_frame = std::move(f);
    });
  }

  // A target box is answered when the tracker has it, refuses it or loses it.
  void OnTrackStatus(const TrackStatus& st) {
    const auto it = pending_tracks.find(st.target_seq);
    if (it == pending_tracks.end()) return;
    if (st.state == TrackStatus::kTracking) {
      Ack(it->second, kResultAccepted);
    } else if (st.state == TrackStatus::kRejected || st.state == TrackStatus::kLost) {
      Text(Severity::kWarning, std::string("target ") + (st.state == TrackStatus::kLost ? "lost" : "refused") + ": " + st.reason);
      Ack(it->second, st.state == TrackStatus::kLost ? kResultFailed : kResultDenied);
    } else {
      return;
    }
    pending_tracks.erase(it);
  }


  void OnTable(ParameterTable t) {
    std::map<std::string, std::string> ids;
    for (const ParameterEntry& e : t.entries) {
      const std::string id = ParamIdOf(e.name);
      if (ids.count(id)) Text(Severity::kError, "parameters " + ids[id] + " and " + e.name + " share MAVLink id " + id);
      ids[id] = e.name;
    }
    param_by_id = std::move(ids);
    // A change from any GCS (ours over LCM, or this one) is broadcast as PARAM_VALUE, as PX4
    // does, so that every MAVLink GCS's parameter editor stays current; a PARAM_SET that changed
    // nothing is answered all the same.
    std::set<std::string> changed;
    if (table && t.version != table->version)
      for (const ParameterEntry& e : t.entries)
        if (const ParameterEntry* was = table->Find(e.name); was && was->value != e.value) changed.insert(e.name);
    table = std::move(t);
    changed.insert(param_echo.begin(), param_echo.end());
    for (const std::string& name : changed) SendParam(name);
    param_echo.clear();
  }

  void SendParam(const std::string& name) {
    if (!table) return;
    for (std::size_t i = 0; i < table->entries.size(); ++i)
      if (table->entries[i].name == name) return SendParamAt(static_cast<int>(i));
  }
  void SendParamAt(int i) {
    const ParameterEntry& e = table->entries[static_cast<std::size_t>(i)];
    ParamValue v;
    SetText(v.param_id, ParamIdOf(e.name));
    v.param_value = static_cast<float>(e.value);
    v.param_type = kParamReal32;
    v.param_count = static_cast<uint16_t>(table->entries.size());
    v.param_index = static_cast<uint16_t>(i);
    Send(v);
  }

  void OnCommandAck(const uav::CommandAck& a) {
    const auto it = pending.find(a.command_seq);
    if (it == pending.end()) return;
    Pending& p = it->second;
    p.answered = true;
    if (p.param_set) {
      // PARAM_SET is answered by PARAM_VALUE: the new value once the table has it, the old one
      // (and why) when refused.
      if (a.result == CommandResult::kRejected || a.result == CommandResult::kFailed) {
        Text(Severity::kWarning, "param " + p.param_name + " refused: " + a.reason);
        SendParam(p.param_name);
        pending.erase(it);
      } else if (a.result == CommandResult::kCompleted || a.result == CommandResult::kAccepted) {
        param_echo.insert(p.param_name);
        pending.erase(it);
      }
      return;
    }
    switch (a.result) {
      case CommandResult::kAccepted:
      case CommandResult::kInProgress:
        // The vehicle works on it: MAVLink's IN_PROGRESS with the percentage, the final result follows.
        Ack(p.cmd, kResultInProgress, static_cast<uint8_t>(std::clamp(a.percent, 0, 100)));
        return;
      case CommandResult::kCompleted: Ack(p.cmd, kResultAccepted); break;
      case CommandResult::kRejected:
        ++counts.commands_refused;
        Text(Severity::kWarning, (p.cmd.command == kCmdArmDisarm && p.cmd.param[0] == 1.f ? "Arming denied: " : "") +
                                     a.command + " refused: " + a.reason);
        Ack(p.cmd, kResultDenied);
        break;
      case CommandResult::kFailed:
        Text(Severity::kWarning, a.command + " failed: " + a.reason);
        Ack(p.cmd, kResultFailed);
        break;
      case CommandResult::kReplaced: Ack(p.cmd, kResultCancelled); break;
    }
    pending.erase(it);
  }

  void OnMissionAck(const uavmsg::mission_ack_t& m) {
    const waypoints::MissionUploadAck ack = waypoints::FromMessage(m);
    if (ack.result == waypoints::MissionUploadAck::Result::kAccepted) {
      const auto done = observed_done.find(m.source);
      if (done != observed_done.end() && waypoints::MissionDigest(done->second) == ack.digest)
        vehicle_mission = done->second;
    }
    if (m.source != source || !uploader || ack.upload_id != uploader->upload_id()) return;
    uploader->OnAck(ack, MonotonicMicros() * 1e-6);
    FinishUploadIfDone();
  }

  // ---- inbound MAVLink ----
  void Receive() {
    std::vector<Frame> frames;
    for (const std::vector<uint8_t>& piece : transport->Receive())
      for (Frame& f : transport->datagrams() ? parser.PushDatagram(piece.data(), piece.size())
                                             : parser.Push(piece.data(), piece.size()))
        frames.push_back(std::move(f));
    const Parser::Counts& c = parser.counts();
    counts.bad_checksum = c.bad_checksum, counts.unknown_message = c.unknown_message, counts.bad_flags = c.bad_flags,
    counts.skipped_bytes = c.skipped_bytes;
    for (const Frame& f : frames) {
      ++counts.frames_in;
      const SignedStreams::Verdict v = streams.Check(f, static_cast<uint64_t>(SigningTimestamp(WallTimeMicros())));
      if (v != SignedStreams::Verdict::kAccepted) {
        Refused(v, f);
        continue;
      }
      try {
        Handle(f);
      } catch (const std::exception& e) {
        // Whatever a frame carries, the link thread goes on: the sender is told what was wrong.
        Text(Severity::kWarning, std::string("MAVLink ") + FindLayout(f.msgid)->name + " refused: " + e.what());
      }
    }
  }

  void Refused(SignedStreams::Verdict v, const Frame& f) {
    switch (v) {
      case SignedStreams::Verdict::kUnsigned: ++counts.unsigned_frames; break;
      case SignedStreams::Verdict::kBadSignature: ++counts.bad_signature; break;
      case SignedStreams::Verdict::kReplay: ++counts.replayed; break;
      case SignedStreams::Verdict::kStale: ++counts.stale; break;
      case SignedStreams::Verdict::kAccepted: return;
    }
    // Said once a second per reason, on both links: a stranger or a replay is the operator's business.
    const std::string why = SignedStreams::Name(v);
    const int64_t wall = MonotonicMicros();
    auto& said = refusal_said[why];
    if (said != 0 && wall - said < 1'000'000) return;
    said = wall;
    const std::string text = "MAVLink frame refused: " + why + " (" + FindLayout(f.msgid)->name + " from " +
                             std::to_string(f.sysid) + ":" + std::to_string(f.compid) + ")";
    say(Severity::kWarning, text);  // the vehicle's status text: both links hear it
  }

  bool ForUs(uint8_t target_system, uint8_t target_component) const {
    return (target_system == 0 || target_system == params.system_id) &&
           (target_component == 0 || target_component == kCompAutopilot || target_component == kCompCamera);
  }

  void Handle(const Frame& f) {
    switch (f.msgid) {
      case Heartbeat::kId: {
        const Heartbeat hb = Unpack<Heartbeat>(f);
        if (hb.type != kTypeGcs) return;
        if (!gcs_seen) say(Severity::kInfo, "MAVLink GCS " + std::to_string(f.sysid) + " connected");
        gcs_seen = true;
        // The link-loss failsafe counts MAVLink GCSs too: their heartbeats become ours.
        uavmsg::heartbeat_t m{};
        m.utime = now;
        m.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
        m.source_name = source;
        Publish(Topic::kGcsHeartbeat, m);
        return;
      }
      case CommandLong::kId: {
        const CommandLong m = Unpack<CommandLong>(f);
        if (!ForUs(m.target_system, m.target_component)) return;
        MavCommand c;
        c.command = m.command, c.target_component = m.target_component, c.confirmation = m.confirmation;
        c.param = {m.param1, m.param2, m.param3, m.param4, m.param5, m.param6, m.param7};
        c.sysid = f.sysid, c.compid = f.compid;
        return OnCommand(c);
      }
      case CommandInt::kId: {
        const CommandInt m = Unpack<CommandInt>(f);
        if (!ForUs(m.target_system, m.target_component)) return;
        MavCommand c;
        c.command = m.command, c.target_component = m.target_component;
        c.param = {m.param1, m.param2, m.param3, m.param4, NAN, NAN, m.z};
        c.has_int_position = true, c.x = m.x, c.y = m.y, c.frame = m.frame;
        c.sysid = f.sysid, c.compid = f.compid;
        return OnCommand(c);
      }
      case ParamRequestList::kId: {
        const ParamRequestList m = Unpack<ParamRequestList>(f);
        if (!ForUs(m.target_system, m.target_component) || !table) return;
        param_list.clear();
        for (std::size_t i = 0; i < table->entries.size(); ++i) param_list.push_back(static_cast<int>(i));
        return;
      }
      case ParamRequestRead::kId: {
        const ParamRequestRead m = Unpack<ParamRequestRead>(f);
        if (!ForUs(m.target_system, m.target_component) || !table) return;
        if (m.param_index >= 0) {
          if (m.param_index < static_cast<int>(table->entries.size())) SendParamAt(m.param_index);
          return;
        }
        const auto it = param_by_id.find(mavlink::Text(m.param_id));
        if (it != param_by_id.end()) return SendParam(it->second);
        Text(Severity::kWarning, "no parameter " + mavlink::Text(m.param_id));
        return;
      }
      case ParamSet::kId: return OnParamSet(Unpack<ParamSet>(f), f);
      case MissionCount::kId: return OnMissionCount(Unpack<MissionCount>(f), f);
      case MissionItemInt::kId: return OnMissionItem(Unpack<MissionItemInt>(f));
      case MissionRequestList::kId: {
        const MissionRequestList m = Unpack<MissionRequestList>(f);
        if (!ForUs(m.target_system, m.target_component)) return;
        download[m.mission_type] = ListOf(m.mission_type);
        MissionCount c;
        c.target_system = f.sysid, c.target_component = f.compid;
        c.count = static_cast<uint16_t>(download[m.mission_type].size());
        c.mission_type = m.mission_type;
        return Send(c);
      }
      case MissionRequestInt::kId: {
        const MissionRequestInt m = Unpack<MissionRequestInt>(f);
        if (ForUs(m.target_system, m.target_component)) SendItem(m.mission_type, m.seq, f);
        return;
      }
      case MissionRequest::kId: {  // the float protocol's request: answered with the INT item, as PX4 does
        const MissionRequest m = Unpack<MissionRequest>(f);
        if (ForUs(m.target_system, m.target_component)) SendItem(m.mission_type, m.seq, f);
        return;
      }
      case MissionAck::kId: return;  // the GCS has the list we sent
      case MissionClearAll::kId: return OnMissionClear(Unpack<MissionClearAll>(f), f);
      case MissionSetCurrent::kId: {
        Text(Severity::kWarning, "MISSION_SET_CURRENT is not supported: the vehicle resumes a mission from the leg it stopped on");
        return;
      }
      case Timesync::kId: {
        Timesync m = Unpack<Timesync>(f);
        if (m.tc1 != 0) return;
        m.tc1 = WallTimeMicros() * 1000;
        m.target_system = f.sysid, m.target_component = f.compid;
        return Send(m);
      }
      default: return;  // known but not a request (telemetry of another system)
    }
  }

  // ---- commands ----
  Outcome Translate(const MavCommand& c) const {
    const VehicleState* s = state ? &*state : nullptr;
    auto need_state = [&]() -> std::optional<Outcome> {
      if (!s) return Outcome{"", kResultTemporarilyRejected, "no vehicle state yet"};
      return std::nullopt;
    };
    switch (c.command) {
      case kCmdArmDisarm:
        if (c.param[0] == 1.f) return {"arm"};
        if (c.param[1] == kForceDisarm) return {"emergency_stop"};
        return {"disarm"};
      case kCmdNavTakeoff: {
        if (auto o = need_state()) return *o;
        // param7: altitude above mean sea level (QGroundControl sends home + the takeoff height); NaN: 10 m.
        const double alt = std::isfinite(c.param[6]) ? c.param[6] - s->home.altitude_m : 10.0;
        return {"takeoff " + Number(alt)};
      }
      case kCmdNavLand: return {"land"};
      case kCmdNavReturn: return {"return"};
      case kCmdMissionStart: return {"mission"};
      case kCmdDoReposition: {
        if (auto o = need_state()) return *o;
        double lat, lon, alt = c.param[6];
        if (c.has_int_position) {
          lat = c.x * 1e-7, lon = c.y * 1e-7;
        } else {
          lat = c.param[4], lon = c.param[5];
        }
        if (!(std::abs(lat) <= 90 && std::abs(lon) <= 180))
          return {"", kResultDenied, "DO_REPOSITION: latitude " + Number(lat) + ", longitude " + Number(lon) +
                                         " is not a position"};
        // Relative-altitude frames (3, 6) are above home; the global ones (0, 5) above mean sea level.
        const bool relative = c.has_int_position && (c.frame == 3 || c.frame == 6);
        if (!std::isfinite(alt)) alt = s->altitude();
        else if (!relative) alt -= s->home.altitude_m;
        const LocalNedFrame frame(s->home);
        const Eigen::Vector3d p = frame.ToNed({lat, lon, s->home.altitude_m});
        return {"goto " + Number(p.x()) + " " + Number(p.y()) + " " + Number(alt)};
      }
      case kCmdDoSetMode: {
        if (!(static_cast<uint8_t>(c.param[0]) & kModeFlagCustom))
          return {"", kResultUnsupported, "DO_SET_MODE without custom mode: PX4 modes only"};
        const uint8_t main = static_cast<uint8_t>(c.param[1]), sub = static_cast<uint8_t>(c.param[2]);
        const Px4Mode* mode = FindPx4Mode(main, sub);
        if (!mode)
          return {"", kResultUnsupported,
                  "mode " + std::to_string(main) + "/" + std::to_string(sub) + " is not one this vehicle flies"};
        // Mission after an interruption goes on where it stopped, as PX4's does.
        const bool interrupted = last_item >= 0 && last_item < static_cast<int>(ListOf(kTypeMission).size()) && !in_mission;
        if (mode->main_mode == px4::kMainAuto && mode->sub_mode == px4::kAutoMission && interrupted) return {"resume"};
        return {mode->command};
      }
      case kCmdVtolTransition:
        if (c.param[0] == 3.f) return {"transition mc"};
        if (c.param[0] == 4.f) return {"transition fw"};
        return {"", kResultDenied, "VTOL transition to state " + Number(c.param[0]) + " (3 multicopter, 4 fixed wing)"};
    }
    return {"", kResultUnsupported, "command " + std::to_string(c.command) + " is not supported"};
  }

  void OnCommand(const MavCommand& c) {
    ++counts.commands;
    // A retransmission of a command still in flight (QGroundControl raises `confirmation`).
    if (c.confirmation > 0)
      for (const auto& [seq_no, p] : pending)
        if (!p.param_set && p.cmd.command == c.command && p.cmd.sysid == c.sysid) return;
    switch (c.command) {
      case kCmdRequestMessage:
      case kCmdRequestCapabilities: {
        const uint32_t id = c.command == kCmdRequestCapabilities ? AutopilotVersion::kId : static_cast<uint32_t>(c.param[0]);
        const bool ok = SendRequested(id, c);
        return Ack(c, ok ? kResultAccepted : kResultUnsupported);
      }
      case kCmdSetMessageInterval: {
        const uint32_t id = static_cast<uint32_t>(c.param[0]);
        if (!period.count(id)) return Ack(c, kResultUnsupported);
        // param2: interval [us]; -1 stops it; 0 the default (kept).
        if (c.param[1] == -1.f) period[id] = -1;
        else if (c.param[1] > 0) period[id] = static_cast<int64_t>(c.param[1]);
        return Ack(c, kResultAccepted);
      }
      case kCmdTrackRectangle:
      case kCmdStopTracking: return OnTrack(c);
    }
    const Outcome o = Translate(c);
    if (o.text.empty()) {
      ++counts.commands_refused;
      Text(Severity::kWarning, o.why);
      return Ack(c, o.refused);
    }
    Pending p;
    p.cmd = c;
    SendCommandText(o.text, std::move(p));
  }

  void SendCommandText(const std::string& text, Pending p) {
    uavmsg::command_t m{};
    m.utime = now;
    m.source = source;
    m.command_seq = ++command_seq;
    m.text = text;
    p.message = m;
    Pending& kept = pending[m.command_seq] = std::move(p);
    PublishCommand(kept);
  }
  void PublishCommand(Pending& p) {
    Publish(Topic::kCommand, p.message);  // a fresh header and signature, the same command_seq
    p.published_us = MonotonicMicros();
    ++p.publications;
  }

  // A command the bus lost (a datagram dropped by a loaded machine or a real network) is published
  // again with its sequence number: the vehicle's intake answers a resend with what it already
  // decided and never runs a command twice. Still unanswered after `command_tries` publications,
  // the GCS is told it failed instead of waiting for an answer that will not come.
  void ResendUnanswered() {
    const int64_t wall = MonotonicMicros();
    const auto resend_us = static_cast<int64_t>(params.command_resend_s * 1e6);
    for (auto it = pending.begin(); it != pending.end();) {
      Pending& p = it->second;
      if (p.answered || wall - p.published_us < resend_us) {
        ++it;
      } else if (p.publications < params.command_tries) {
        PublishCommand(p);
        ++counts.commands_resent;
        ++it;
      } else {
        ++counts.commands_unanswered;
        // A fault inside the vehicle: both links hear it.
        say(Severity::kWarning, "MAVLink command '" + p.message.text + "': no answer from the flight controller in " +
                                     Number(params.command_tries * params.command_resend_s) + " s");
        if (p.param_set) SendParam(p.param_name);
        else Ack(p.cmd, kResultFailed);
        it = pending.erase(it);
      }
    }
  }

  void OnTrack(const MavCommand& c) {
    if (!last_frame) {
      Text(Severity::kWarning, "no video: there is no frame to track in");
      return Ack(c, kResultDenied);
    }
    TrackTarget t;
    t.vehicle_id = vehicle_id;
    t.source = source;
    t.target_seq = ++command_seq;
    t.frame_utime = last_frame->utime;
    t.camera = last_frame->camera;
    if (c.command == kCmdStopTracking) {
      t.method = TrackTarget::kCancel;
    } else {
      // param1..4: top-left x, y and bottom-right x, y, each 0..1 of the image.
      const double x0 = c.param[0], y0 = c.param[1], x1 = c.param[2], y1 = c.param[3];
      if (!(x0 >= 0 && y0 >= 0 && x1 <= 1 && y1 <= 1 && x1 > x0 && y1 > y0)) {
        Text(Severity::kWarning, "CAMERA_TRACK_RECTANGLE: the rectangle must lie in 0..1 with its corners in order");
        return Ack(c, kResultDenied);
      }
      // Our targets are in the same units: fractions of the image from its top-left corner.
      t.method = TrackTarget::kDrag;
      t.x = x0, t.y = y0, t.width = x1 - x0, t.height = y1 - y0;
      t.corners = {Eigen::Vector2d(t.x, t.y), Eigen::Vector2d(t.x + t.width, t.y),
                   Eigen::Vector2d(t.x + t.width, t.y + t.height), Eigen::Vector2d(t.x, t.y + t.height)};
    }
    uavmsg::track_target_t m = ToMessage(t);
    Publish(Topic::kTrackTarget, m);
    // A box is answered when the tracker has it (or refuses it); a stop at once.
    if (c.command == kCmdStopTracking) return Ack(c, kResultAccepted);
    pending_tracks[t.target_seq] = c;
    Ack(c, kResultInProgress);
  }

  bool SendRequested(uint32_t id, const MavCommand& c) {
    switch (id) {
      case AutopilotVersion::kId: {
        AutopilotVersion v;
        v.capabilities = kCapabilities;
        v.flight_sw_version = (1u << 24) | (15u << 16) | (0xFFu);  // reported as PX4 1.15 (release)
        v.vendor_id = 0, v.product_id = 0;
        v.uid = std::hash<std::string>{}(vehicle_id);
        Send(v);
        return true;
      }
      case HomePosition::kId: return SendHome();
      case CameraInformation::kId: {
        if (!last_frame) return false;
        CameraInformation ci;
        ci.time_boot_ms = BootMs();
        const std::string vendor = "uav", model = last_frame->camera;
        std::copy_n(vendor.begin(), std::min<std::size_t>(vendor.size(), 31), ci.vendor_name.begin());
        std::copy_n(model.begin(), std::min<std::size_t>(model.size(), 31), ci.model_name.begin());
        ci.resolution_h = static_cast<uint16_t>(last_frame->source_width);
        ci.resolution_v = static_cast<uint16_t>(last_frame->source_height);
        // HAS_VIDEO_STREAM, and HAS_TRACKING_RECTANGLE when the onboard tracker runs on this camera.
        ci.flags = 256 | (tracking_camera == last_frame->camera ? 1024 : 0);
        Send(ci, kCompCamera);
        return true;
      }
      case VideoStreamInformation::kId: {
        if (!video || !last_frame || video->width() == 0) return false;  // nothing encoded (yet)
        VideoStreamInformation vs;
        vs.stream_id = 1, vs.count = 1;
        vs.type = 1;  // VIDEO_STREAM_TYPE_RTPUDP
        vs.flags = 1; // RUNNING
        vs.framerate = static_cast<float>(video->frame_rate());
        vs.resolution_h = static_cast<uint16_t>(video->width());
        vs.resolution_v = static_cast<uint16_t>(video->height());
        vs.bitrate = static_cast<uint32_t>(video->bitrate_kbps() * 1000);
        vs.hfov = 0;
        SetText(vs.name, last_frame->camera);
        SetText(vs.uri, std::to_string(params.video_port));  // QGroundControl: the UDP port for RTP/UDP
        vs.encoding = 1;  // VIDEO_STREAM_ENCODING_H264
        Send(vs, kCompCamera);
        return true;
      }
    }
    (void)c;
    return false;
  }

  // ---- parameters ----
  void OnParamSet(const ParamSet& m, const Frame& f) {
    if (!ForUs(m.target_system, m.target_component) || !table) return;
    const std::string id = mavlink::Text(m.param_id);
    const auto it = param_by_id.find(id);
    if (it == param_by_id.end()) {
      Text(Severity::kWarning, "no parameter " + id);
      return;
    }
    if (m.param_type != kParamReal32 || !std::isfinite(m.param_value)) {
      Text(Severity::kWarning, "param " + it->second + ": only finite REAL32 values (type 9)");
      return SendParam(it->second);
    }
    Pending p;
    p.param_set = true;
    p.param_name = it->second;
    p.cmd.sysid = f.sysid, p.cmd.compid = f.compid;
    SendCommandText("param " + it->second + " " + Number(m.param_value), std::move(p));
  }

  // ---- missions ----
  std::vector<waypoints::MissionItem> ListOf(uint8_t type) const {
    if (!vehicle_mission) return {};
    return waypoints::ItemsOf(*vehicle_mission, static_cast<waypoints::MavMissionList>(type));
  }

  void SendItem(uint8_t type, uint16_t index, const Frame& f) {
    const auto& list = download[type];
    if (index >= list.size()) {
      MissionAck a;
      a.target_system = f.sysid, a.target_component = f.compid, a.type = kMissionInvalidSequence, a.mission_type = type;
      return Send(a);
    }
    MissionItemInt m = waypoints::ToItemInt(list[index], index, static_cast<waypoints::MavMissionList>(type));
    m.target_system = f.sysid, m.target_component = f.compid;
    Send(m);
  }

  void MissionAckTo(uint8_t sysid, uint8_t compid, uint8_t type, uint8_t result) {
    MissionAck a;
    a.target_system = sysid, a.target_component = compid, a.type = result, a.mission_type = type;
    Send(a);
  }

  void OnMissionCount(const MissionCount& m, const Frame& f) {
    if (!ForUs(m.target_system, m.target_component)) return;
    if (m.mission_type > kTypeRally) return MissionAckTo(f.sysid, f.compid, m.mission_type, kMissionUnsupported);
    if (uploader) {
      Text(Severity::kWarning, "mission upload refused: the previous one is still being checked by the vehicle");
      return MissionAckTo(f.sysid, f.compid, m.mission_type, kMissionDenied);
    }
    upload = Upload{m.mission_type, m.count, {}, MonotonicMicros(), 0, f.sysid, f.compid};
    if (m.count == 0) return Combine();
    RequestNext();
  }

  void RequestNext() {
    MissionRequestInt r;
    r.target_system = upload->sysid, r.target_component = upload->compid;
    r.seq = static_cast<uint16_t>(upload->items.size());
    r.mission_type = upload->type;
    upload->last_us = MonotonicMicros();
    Send(r);
  }

  void OnMissionItem(const MissionItemInt& m) {
    if (!upload || !ForUs(m.target_system, m.target_component) || m.mission_type != upload->type) return;
    if (m.seq != upload->items.size()) return;  // a repeat of one we have: the request for the next stands
    auto fail = [&](uint8_t result, const std::string& why) {
      Text(Severity::kWarning, "mission item " + std::to_string(m.seq) + ": " + why);
      MissionAckTo(upload->sysid, upload->compid, upload->type, result);
      upload.reset();
    };
    std::string why;
    waypoints::ItemProblem problem;
    const waypoints::MissionItem it =
        waypoints::FromItemInt(m, static_cast<waypoints::MavMissionList>(upload->type), &problem, &why);
    if (problem == waypoints::ItemProblem::kFrame) return fail(kMissionUnsupportedFrame, why);
    if (problem != waypoints::ItemProblem::kNone) return fail(kMissionUnsupported, why);
    upload->items.push_back(it);
    if (upload->items.size() < upload->count) return RequestNext();
    Combine();
  }

  // The list just received with the vehicle's other two, uploaded to the vehicle as one mission
  // (our missions carry their fence and rally points); the GCS's MISSION_ACK waits for the verdict.
  void Combine() {
    const uint8_t type = upload->type;
    std::vector<waypoints::MissionItem> lists[3] = {ListOf(kTypeMission), ListOf(kTypeFence), ListOf(kTypeRally)};
    lists[type] = upload->items;
    if (lists[kTypeMission].empty()) {
      if (type == kTypeMission && upload->items.empty()) return OnMissionClear(MissionClearAll{}, upload->sysid, upload->compid, kTypeMission);
      Text(Severity::kWarning, "upload a mission first: the vehicle holds its fence and rally points with its mission");
      MissionAckTo(upload->sysid, upload->compid, type, kMissionDenied);
      upload.reset();
      return;
    }
    if (!state) {
      MissionAckTo(upload->sysid, upload->compid, type, kMissionError);
      upload.reset();
      return;
    }
    waypoints::Mission mission;
    mission.home = state->home;
    if (vehicle_mission) mission.cruise_speed_m_s = vehicle_mission->cruise_speed_m_s;
    for (const auto& list : lists) mission.items.insert(mission.items.end(), list.begin(), list.end());
    try {
      waypoints::ValidateMission(mission);
    } catch (const std::invalid_argument& e) {
      Text(Severity::kWarning, std::string("mission refused: ") + e.what());
      MissionAckTo(upload->sysid, upload->compid, type, kMissionInvalid);
      upload.reset();
      return;
    }
    uploader.emplace(mission, WallTimeMicros());
    uploader_type = type;
    PumpUploader();
  }

  void PumpUploader() {
    if (!uploader) return;
    for (const waypoints::MissionChunk& chunk : uploader->Tick(MonotonicMicros() * 1e-6)) {
      uavmsg::mission_upload_t m = waypoints::ToMessage(chunk);
      m.utime = now;
      m.source = source;
      Publish(Topic::kMissionUpload, m);
    }
    FinishUploadIfDone();
  }

  void FinishUploadIfDone() {
    if (!uploader || !upload) return;
    using State = waypoints::MissionUploader::State;
    const State s = uploader->state();
    if (s == State::kSending) return;
    if (s == State::kAccepted) {
      vehicle_mission = uploader->mission();
      MissionAckTo(upload->sysid, upload->compid, uploader_type, kMissionAccepted);
    } else {
      Text(Severity::kWarning, "mission refused: " + uploader->reason());
      MissionAckTo(upload->sysid, upload->compid, uploader_type,
                   s == State::kRejected ? kMissionInvalid : kMissionError);
    }
    uploader.reset();
    upload.reset();
  }

  void OnMissionClear(const MissionClearAll& m, const Frame& f) {
    if (!ForUs(m.target_system, m.target_component)) return;
    OnMissionClear(m, f.sysid, f.compid, m.mission_type);
  }
  void OnMissionClear(const MissionClearAll&, uint8_t sysid, uint8_t compid, uint8_t type) {
    upload.reset();
    if (type == kTypeFence || type == kTypeRally) {
      // The mission again without them.
      if (ListOf(kTypeMission).empty() || ListOf(type).empty()) return MissionAckTo(sysid, compid, type, kMissionAccepted);
      upload = Upload{type, 0, {}, MonotonicMicros(), 0, sysid, compid};
      return Combine();
    }
    // The vehicle keeps a mission until another replaces it (the command "mission" must always
    // find one it has checked): a clear is refused, and said.
    if (!vehicle_mission) return MissionAckTo(sysid, compid, type, kMissionAccepted);
    Text(Severity::kWarning, "the vehicle keeps its mission until a new one is uploaded");
    MissionAckTo(sysid, compid, type, kMissionDenied);
  }

  void CheckUploadTimeout() {
    if (!upload || uploader) return;
    // The GCS owes us an item: ask again after 1.5 s, give up after five tries (mavlink.io's
    // mission protocol timeouts), leaving the vehicle's mission as it was.
    if (MonotonicMicros() - upload->last_us < 1'500'000) return;
    if (++upload->retries > 5) {
      Text(Severity::kWarning, "mission upload stopped at item " + std::to_string(upload->items.size()) + " of " +
                                   std::to_string(upload->count) + ": the vehicle keeps its mission");
      MissionAckTo(upload->sysid, upload->compid, upload->type, kMissionCancelled);
      upload.reset();
      return;
    }
    RequestNext();
  }

  // ---- telemetry ----
  uint32_t BootMs() const { return static_cast<uint32_t>((now - start) / 1000); }
  bool Due(uint32_t id) {
    const int64_t p = period[id];
    if (p < 0) return false;
    auto it = sent_at.find(id);
    if (it != sent_at.end() && now - it->second < p) return false;
    sent_at[id] = now;
    return true;
  }

  bool SendHome() {
    if (!state) return false;
    HomePosition h;
    h.latitude = static_cast<int32_t>(std::lround(state->home.latitude_deg * 1e7));
    h.longitude = static_cast<int32_t>(std::lround(state->home.longitude_deg * 1e7));
    h.altitude = static_cast<int32_t>(std::lround(state->home.altitude_m * 1e3));
    h.q = {1, 0, 0, 0};
    h.time_usec = static_cast<uint64_t>(now);
    Send(h);
    return true;
  }

  void Telemetry() {
    if (Due(Heartbeat::kId)) {
      Heartbeat hb;
      hb.autopilot = kAutopilotPx4;
      hb.mavlink_version = 3;
      if (state) {
        hb.type = state->vehicle_type == VehicleType::kTailSitter ? kTypeVtolTailsitterQuad : kTypeQuadrotor;
        hb.custom_mode = Px4ModeOf(state->task).custom_mode();
        hb.base_mode = kModeFlagCustom | kModeFlagStabilize | kModeFlagGuided | kModeFlagAuto |
                       (state->armed ? kModeFlagArmed : 0);
        hb.system_status = state->failsafe != FailsafeAction::kNone ? kStateCritical
                           : state->armed                           ? kStateActive
                                                                    : kStateStandby;
      } else {
        hb.type = kTypeQuadrotor;
        hb.system_status = 0;  // UNINIT: no state yet
      }
      Send(hb);
      if (last_frame) {
        Heartbeat cam;
        cam.type = kTypeCamera, cam.autopilot = kAutopilotInvalid, cam.system_status = kStateActive, cam.mavlink_version = 3;
        Send(cam, kCompCamera);
      }
    }
    if (!state) return;
    const VehicleState& s = *state;
    const Eigen::Matrix3d R_NB = (Eigen::AngleAxisd(s.euler.psi, Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(s.euler.theta, Eigen::Vector3d::UnitY()) *
                                  Eigen::AngleAxisd(s.euler.phi, Eigen::Vector3d::UnitX()))
                                     .toRotationMatrix();
    const Eigen::Vector3d v_N = R_NB * s.v_B;
    if (Due(Attitude::kId)) {
      Attitude a;
      a.time_boot_ms = BootMs();
      a.roll = static_cast<float>(s.euler.phi), a.pitch = static_cast<float>(s.euler.theta);
      a.yaw = static_cast<float>(std::remainder(s.euler.psi, 2 * M_PI));
      a.rollspeed = static_cast<float>(s.w_B.x()), a.pitchspeed = static_cast<float>(s.w_B.y());
      a.yawspeed = static_cast<float>(s.w_B.z());
      Send(a);
    }
    if (Due(GlobalPositionInt::kId)) {
      const LocalNedFrame frame(s.home);
      const GeodeticPoint g = frame.ToGeodetic(s.p_N);
      GlobalPositionInt p;
      p.time_boot_ms = BootMs();
      p.lat = static_cast<int32_t>(std::lround(g.latitude_deg * 1e7));
      p.lon = static_cast<int32_t>(std::lround(g.longitude_deg * 1e7));
      p.alt = static_cast<int32_t>(std::lround(g.altitude_m * 1e3));  // the ellipsoid: we carry no geoid
      p.relative_alt = static_cast<int32_t>(std::lround(s.altitude() * 1e3));
      p.vx = static_cast<int16_t>(std::lround(v_N.x() * 100));
      p.vy = static_cast<int16_t>(std::lround(v_N.y() * 100));
      p.vz = static_cast<int16_t>(std::lround(v_N.z() * 100));
      p.hdg = static_cast<uint16_t>(std::lround(s.heading() * 18000 / M_PI)) % 36000;
      Send(p);
    }
    if (Due(VfrHud::kId)) {
      VfrHud h;
      h.airspeed = static_cast<float>(s.airspeed_m_s >= 0 ? s.airspeed_m_s : s.ground_speed());
      h.groundspeed = static_cast<float>(s.ground_speed());
      h.heading = static_cast<int16_t>(std::lround(s.heading() * 180 / M_PI) % 360);
      h.throttle = static_cast<uint16_t>(std::lround(std::clamp((s.servo_input[2] + 1) * 50, 0.0, 100.0)));
      h.alt = static_cast<float>(s.gps.altitude_m);
      h.climb = static_cast<float>(-v_N.z());
      Send(h);
    }
    if (Due(GpsRawInt::kId)) {
      GpsRawInt g;
      g.time_usec = static_cast<uint64_t>(s.utime);
      g.fix_type = static_cast<uint8_t>(s.gps_fix);
      g.lat = static_cast<int32_t>(std::lround(s.gps.latitude_deg * 1e7));
      g.lon = static_cast<int32_t>(std::lround(s.gps.longitude_deg * 1e7));
      g.alt = static_cast<int32_t>(std::lround(s.gps.altitude_m * 1e3));
      g.alt_ellipsoid = g.alt;
      g.eph = g.epv = UINT16_MAX;  // unknown
      g.vel = static_cast<uint16_t>(std::lround(s.ground_speed() * 100));
      g.cog = static_cast<uint16_t>(std::lround(std::atan2(v_N.y(), v_N.x()) * 18000 / M_PI + 36000)) % 36000;
      g.satellites_visible = static_cast<uint8_t>(s.gps_satellites);
      Send(g);
    }
    if (Due(SysStatus::kId)) {
      SysStatus st;
      uint32_t present = kSensorGyro | kSensorAccel | kSensorAhrs | kSensorGps | kSensorMotorOutputs | kSensorBattery |
                         kSensorGeofence | kSensorPrearm | kSensorVisionPosition;
      uint32_t health = present;
      if (prearm) {
        for (const PreArmCheck& c : prearm->checks) {
          if (c.passed) continue;
          if (c.name == "gps") health &= ~kSensorGps;
          else if (c.name == "ins") health &= ~(kSensorGyro | kSensorAccel | kSensorAhrs);
          else if (c.name == "battery") health &= ~kSensorBattery;
          else if (c.name == "geofence") health &= ~kSensorGeofence;
          else if (c.name == "sensors") health &= ~kSensorVisionPosition;
        }
        if (!prearm->Ready()) health &= ~kSensorPrearm;
      }
      st.onboard_control_sensors_present = present;
      st.onboard_control_sensors_enabled = present;
      st.onboard_control_sensors_health = health;
      st.voltage_battery = static_cast<uint16_t>(std::lround(s.battery_voltage_v * 1000));
      st.current_battery = -1;
      st.battery_remaining = static_cast<int8_t>(std::lround(s.battery_remaining * 100));
      Send(st);
    }
    if (Due(BatteryStatus::kId)) {
      BatteryStatus b;
      b.battery_function = 1;  // ALL
      b.type = 3;              // LIPO
      b.temperature = INT16_MAX;
      b.voltages.fill(UINT16_MAX);
      b.voltages[0] = static_cast<uint16_t>(std::lround(s.battery_voltage_v * 1000));
      b.voltages_ext.fill(0);
      b.current_battery = -1, b.current_consumed = -1, b.energy_consumed = -1;
      b.battery_remaining = static_cast<int8_t>(std::lround(s.battery_remaining * 100));
      Send(b);
    }
    if (Due(ExtendedSysState::kId)) {
      ExtendedSysState e;
      if (s.vehicle_type == VehicleType::kTailSitter) {
        // MAV_VTOL_STATE: 1 to fixed wing, 2 to multicopter, 3 multicopter, 4 fixed wing.
        switch (s.vtol_mode) {
          case VtolMode::kHover: e.vtol_state = 3; break;
          case VtolMode::kTransitionToWing: e.vtol_state = 1; break;
          case VtolMode::kCruise: e.vtol_state = 4; break;
          case VtolMode::kTransitionToHover: e.vtol_state = 2; break;
        }
      }
      // MAV_LANDED_STATE: 1 on ground, 2 in air, 3 taking off, 4 landing.
      e.landed_state = s.landed ? 1 : s.task == Task::kTakeoff ? 3 : s.task == Task::kLand ? 4 : 2;
      Send(e);
    }
    MissionProgress();
    if (Due(HomePosition::kId)) SendHome();
  }

  void MissionProgress() {
    const VehicleState& s = *state;
    const int total = static_cast<int>(ListOf(kTypeMission).size());
    const bool flying_mission = s.task == Task::kMission;
    // Items the vehicle moved past are reached; the last one when the mission ends on the ground.
    if (flying_mission && s.mission_item > last_item) {
      for (int i = std::max(last_item, 0); i < s.mission_item; ++i) {
        MissionItemReached r;
        r.seq = static_cast<uint16_t>(i);
        Send(r);
      }
      last_item = s.mission_item;
      sent_at.erase(MissionCurrent::kId);
    }
    // The last item when the mission hands over: a return or a landing once on the ground.
    const std::vector<waypoints::MissionItem> list = ListOf(kTypeMission);
    auto reached_last = [&] {
      MissionItemReached r;
      r.seq = static_cast<uint16_t>(total - 1);
      Send(r);
      last_item = total;  // done
      finishing = false;
    };
    if (in_mission && !flying_mission && total > 0 && last_item == total - 1) {
      const int last = list.back().command;
      if (last == waypoints::mav_cmd::kNavReturnToLaunch || last == waypoints::mav_cmd::kNavLand) finishing = true;
      else reached_last();
    }
    if (finishing && s.landed && !s.armed) reached_last();
    if (flying_mission) finishing = false;
    if (flying_mission && !in_mission && s.mission_item >= 0 && s.mission_item < last_item) last_item = s.mission_item;
    in_mission = flying_mission;
    if (Due(MissionCurrent::kId)) {
      MissionCurrent c;
      c.seq = static_cast<uint16_t>(std::clamp(last_item, 0, std::max(total - 1, 0)));
      c.total = static_cast<uint16_t>(total);
      // MISSION_STATE: 1 none, 2 not started, 3 active, 5 complete.
      c.mission_state = total == 0 ? 1 : flying_mission ? 3 : last_item >= total ? 5 : 2;
      c.mission_mode = flying_mission ? 1 : 0;
      Send(c);
    }
  }

  void StatusTexts() {
    while (!texts.empty()) {
      Text(texts.front().severity, texts.front().text);
      texts.pop_front();
    }
  }

  void Tick(int64_t utime) {
    now = utime;
    if (start < 0) start = utime;
    Receive();
    ResendUnanswered();
    CheckUploadTimeout();
    PumpUploader();
    StatusTexts();
    Telemetry();
    // The parameter list, paced: on a network 40 a tick; on a radio half of what the line
    // carries (a PARAM_VALUE frame, signed, is 50 bytes), so the telemetry keeps flowing and the
    // serial driver's buffer never overflows.
    const int bps = transport->bytes_per_second();
    const int per_tick = bps > 0 ? std::max(1, bps / 50 / 2 / 50) : 40;
    for (int i = 0; i < per_tick && !param_list.empty() && table; ++i) {
      if (param_list.front() < static_cast<int>(table->entries.size())) SendParamAt(param_list.front());
      param_list.pop_front();
    }
  }
};

MavlinkEndpoint::MavlinkEndpoint(const std::string& vehicle_id, Bus& bus, const MavlinkParams& params,
                                 const std::optional<SigningKey>& key, Say say)
    : impl_(std::make_unique<Impl>(vehicle_id, bus, params, key, std::move(say))) {}
MavlinkEndpoint::~MavlinkEndpoint() = default;
void MavlinkEndpoint::Tick(int64_t utime) { impl_->Tick(utime); }
MavlinkEndpoint::Counts MavlinkEndpoint::counts() const { return impl_->counts; }

}  // namespace uav::runtime
