#include "uav/gcs/gcs_link.hpp"

#include <cmath>
#include <functional>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

#include "uav/wire/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/time.hpp"
#include "uav/wire/reports.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uav/wire/signed_message.hpp"
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/manual_control_t.hpp"
#include "uavmsg/track_target_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"

namespace uav::gcs {

static_assert(kMaxJpegBytes == uavmsg::video_frame_t::MAX_JPEG_BYTES &&
              kMaxJpegBytes == uavmsg::map_tile_t::MAX_JPEG_BYTES);

namespace {

// One decoder per topic the GCS listens to: bytes -> typed message -> model input. Throws
// std::invalid_argument naming what was refused.
using Decoder = std::function<void(GcsModel&, const std::string& vehicle, const void*, int, double now)>;

template <class Msg>
Msg Decode(const void* data, int size, const std::string& vehicle) {
  Msg m;
  if (size < 0 || !DecodeDatagram(data, static_cast<size_t>(size), &m)) throw std::invalid_argument("does not decode");
  if (m.header.vehicle_id != vehicle) throw std::invalid_argument("header names vehicle '" + m.header.vehicle_id + "'");
  return m;
}

// A vehicle report (uav/shared/reports.hpp): decoded and checked by its FromMessage.
template <class T>
void DecodeReport(GcsModel& model, const std::string& id, const void* d, int n, double now) {
  model.OnReport(id, FromMessage(Decode<typename Report<T>::Message>(d, n, id)), now);
}

// In a fixed order, that of the fuzz seeds' topic selector (GcsLink::Topics()): the operator's
// topics, then the reports in the order of their list.
std::vector<std::pair<Topic, Decoder>> MakeDecoders() {
  std::vector<std::pair<Topic, Decoder>> k = {
      {Topic::kHeartbeat,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::heartbeat_t>(d, n, id);
         if (m.source_kind != uavmsg::heartbeat_t::SOURCE_VEHICLE) throw std::invalid_argument("not a vehicle heartbeat");
         const auto task = TaskFromWire(m.task);
         const auto mode = FlightModeFromWire(m.flight_mode);
         if (!task || !mode) throw std::invalid_argument("unknown task or flight mode");
         if (!std::isfinite(m.sim_rate) || !std::isfinite(m.sim_rate_asked)) throw std::invalid_argument("simulator rate is not finite");
         model.OnHeartbeat(id, m.header.seq, {*task, m.armed != 0, *mode, m.signing == uavmsg::heartbeat_t::SIGNING_ON,
                                              m.signature_rejections, m.sim_rate_asked, m.sim_rate}, now);
       }},
      {Topic::kState,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::vehicle_state_t>(d, n, id);
         model.OnState(id, m.header.seq, FromMessage(m), now);
       }},
      {Topic::kCommandAck,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         model.OnAck(id, FromMessage(Decode<uavmsg::command_ack_t>(d, n, id)), now);
       }},
      {Topic::kStatusText,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::status_text_t>(d, n, id);
         const auto severity = SeverityFromWire(m.severity);
         if (!severity) throw std::invalid_argument("unknown severity " + std::to_string(m.severity));
         model.OnStatusText(id, *severity, m.text, now);
       }},
      {Topic::kMissionAck,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::mission_ack_t>(d, n, id);
         model.OnMissionAck(id, m.source, waypoints::FromMessage(m), now);
       }},
      {Topic::kVideo,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         model.OnVideoFrame(id, FromMessage(Decode<uavmsg::video_frame_t>(d, n, id)), now);
       }},
      {Topic::kFileOffer,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::file_offer_t>(d, n, id);
         FileOffer o;
         o.transfer_id = m.transfer_id;
         o.name = m.name;
         o.size = m.size;
         o.chunk_bytes = m.chunk_bytes;
         o.chunks = m.chunks;
         o.sha256 = m.sha256;
         model.OnFileOffer(id, o, now);
       }},
      {Topic::kFileChunk,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::file_chunk_t>(d, n, id);
         FileChunk c;
         c.transfer_id = m.transfer_id;
         c.index = m.index;
         c.crc32 = static_cast<uint32_t>(m.crc32);
         c.data = m.data;
         model.OnFileChunk(id, c, now);
       }},
      {Topic::kMapTile,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         model.OnMapTile(id, FromMessage(Decode<uavmsg::map_tile_t>(d, n, id)), now);
       }},
      {Topic::kTrackStatus,
       [](GcsModel& model, const std::string& id, const void* d, int n, double now) {
         const auto m = Decode<uavmsg::track_status_t>(d, n, id);
         model.OnTrackStatus(id, m.header.seq, FromMessage(m), now);
       }},
  };
  ForEachType(VehicleReports{}, [&](auto* type) {
    using T = std::remove_pointer_t<decltype(type)>;
    k.emplace_back(Report<T>::kTopic, &DecodeReport<T>);
  });
  return k;
}

const std::vector<std::pair<Topic, Decoder>>& Decoders() {
  static const std::vector<std::pair<Topic, Decoder>> k = MakeDecoders();
  return k;
}

}  // namespace

struct GcsLink::Impl {
  Impl(Bus* b, GcsModel& m) : bus(b), model(m) {}
  Bus* bus;
  GcsModel& model;
  std::optional<MessageSigner> signer;  // none: --insecure
  double now = 0.0;
  double last_heartbeat = -1e9;
  std::map<Topic, int64_t> seq;  // header.seq per outgoing topic
  int64_t dropped = 0;
  std::string last_drop_reason;

  template <class Msg>
  void Publish(const std::string& vehicle_id, Topic t, Msg& m) {
    m.utime = WallTimeMicros();
    m.header = {vehicle_id, ++seq[t]};
    if (signer) SignMessage(*signer, m.utime, m);
    else m.signature = uavmsg::signature_t{};  // VERSION_UNSIGNED
    bus->Publish(Channel(vehicle_id, t), m);
  }
};

GcsLink::GcsLink(Bus* bus, GcsModel& model, const std::optional<SigningKey>& key, int link_id)
    : impl_(std::make_unique<Impl>(bus, model)) {
  if (key) impl_->signer.emplace(*key, link_id);
  model.SetSigningKeyId(key ? key->Id() : "");
  if (!bus) return;
  Impl* im = impl_.get();
  // One subscription per topic (each LCM subscription has its own queue).
  for (const auto& [topic, decoder] : Decoders()) {
    bus->SubscribeRaw(std::string("[^/]+/") + TopicName(topic),
                      [this, im](const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
                        Dispatch(channel, rbuf.data, static_cast<int>(rbuf.data_size), im->now);
                      });
  }
}

GcsLink::~GcsLink() = default;

std::vector<Topic> GcsLink::Topics() {
  std::vector<Topic> out;
  for (const auto& [topic, decoder] : Decoders()) out.push_back(topic);
  return out;
}

int64_t GcsLink::dropped_messages() const { return impl_->dropped; }
const std::string& GcsLink::last_drop_reason() const { return impl_->last_drop_reason; }

bool GcsLink::Dispatch(const std::string& channel, const void* data, int size, double now) {
  Impl& im = *impl_;
  const auto slash = channel.find('/');
  const std::string vehicle = channel.substr(0, slash);
  const std::string topic_name = slash == std::string::npos ? "" : channel.substr(slash + 1);
  for (const auto& [topic, decode] : Decoders()) {
    if (topic_name != TopicName(topic)) continue;
    try {
      if (!IsValidVehicleId(vehicle)) throw std::invalid_argument("not a vehicle id");
      decode(im.model, vehicle, data, size, now);
      return true;
    } catch (const std::invalid_argument& e) {
      ++im.dropped;
      im.last_drop_reason = channel + ": " + e.what();
      return false;
    }
  }
  return false;  // a topic the GCS does not read (commands, other GCSs' heartbeats): not ours
}

void GcsLink::Poll(int timeout_ms, double now) {
  Receive(timeout_ms, now);
  if (!impl_->bus || impl_->model.replay()) return;  // a replay watches only
  GcsOutgoing out = impl_->model.TakeOutgoing();
  Send(out, now);
}

void GcsLink::Receive(int timeout_ms, double now) {
  impl_->now = now;
  if (impl_->bus) impl_->bus->Handle(timeout_ms);
}

void GcsLink::Send(GcsOutgoing& out, double now) {
  Impl& im = *impl_;
  if (!im.bus || im.model.replay()) return;
  for (const auto& c : out.commands) {
    uavmsg::command_t m{};
    m.source = im.model.gcs_name();
    m.command_seq = c.command_seq;
    m.text = c.text;
    im.Publish(c.vehicle_id, Topic::kCommand, m);
  }
  for (const auto& c : out.mission_chunks) {
    uavmsg::mission_upload_t m = waypoints::ToMessage(c.chunk);
    m.source = im.model.gcs_name();
    im.Publish(c.vehicle_id, Topic::kMissionUpload, m);
  }
  for (const auto& r : out.file_requests) {
    uavmsg::file_request_t m{};
    m.source = im.model.gcs_name();
    m.transfer_id = r.request.transfer_id;
    m.complete = r.request.complete;
    for (const FileRange& range : r.request.ranges) {
      if (m.first.size() >= 1000) break;  // the rest next time
      m.first.push_back(range.first);
      m.count.push_back(range.count);
    }
    m.n_ranges = static_cast<int16_t>(m.first.size());
    im.Publish(r.vehicle_id, Topic::kFileRequest, m);
  }
  for (const auto& [vehicle_id, sticks] : out.sticks) {
    uavmsg::manual_control_t m = ToMessage(sticks);
    m.source = im.model.gcs_name();
    im.Publish(vehicle_id, Topic::kManualControl, m);
  }
  for (const auto& t : out.targets) {
    uavmsg::track_target_t m = ToMessage(t);
    m.source = im.model.gcs_name();
    im.Publish(t.vehicle_id, Topic::kTrackTarget, m);
  }
  if (now - im.last_heartbeat >= kHeartbeatPeriod) {
    im.last_heartbeat = now;
    for (const auto& [id, v] : im.model.vehicles()) {
      if (v.mavlink) continue;  // its link sends MAVLink's
      uavmsg::heartbeat_t hb{};
      hb.source_kind = uavmsg::heartbeat_t::SOURCE_GCS;
      hb.source_name = im.model.gcs_name();
      im.Publish(id, Topic::kGcsHeartbeat, hb);
    }
  }
}

}  // namespace uav::gcs
