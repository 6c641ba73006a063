// Outbound translators: acknowledgements, status texts, state, heartbeat, video, the perception
// reports, live-map tiles and file offers and chunks. Each reads the blackboard (or a store) and publishes one topic.
#include "link_translators.hpp"

#include <algorithm>
#include <climits>
#include <chrono>
#include <cmath>
#include <optional>

#include "uav/runtime/reported_state.hpp"
#include "uav/wire/reports.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/heartbeat_t.hpp"

#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"

namespace uav::runtime {
namespace {

int64_t Micros(double seconds) { return static_cast<int64_t>(std::llround(seconds * 1e6)); }

class AckTranslator : public Translator {
 public:
  explicit AckTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    for (const auto& r : c_.board.task_reports.TakeAll()) SendAck(c_, utime, r);
  }

 private:
  LinkContext& c_;
};

class StatusTextTranslator : public Translator {
 public:
  explicit StatusTextTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    for (const auto& s : c_.board.status.TakeAll()) {
      uavmsg::status_text_t m;
      m.utime = utime;
      m.severity = static_cast<int8_t>(s.severity);
      m.text = s.text;
      c_.Publish(Topic::kStatusText, m);
    }
  }

 private:
  LinkContext& c_;
};

class StateTranslator : public Translator {
 public:
  explicit StateTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    VehicleState s = ReportedState(c_.board.Snapshot(), c_.missions.home(), c_.params.attitude_mode);
    if (s.utime == 0) s.utime = utime;  // no navigation solution yet
    uavmsg::vehicle_state_t m;
    ToMessage(s, &m);
    c_.Publish(Topic::kState, m);
  }

 private:
  LinkContext& c_;
};

class HeartbeatTranslator : public Translator {
 public:
  explicit HeartbeatTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    if (start_ < 0) start_ = utime;
    if (last_ >= 0 && utime - last_ < Micros(c_.params.heartbeat_period_s)) return;
    last_ = utime;
    const BlackboardData d = c_.board.Snapshot();
    uavmsg::heartbeat_t hb{};
    hb.utime = utime;
    hb.source_kind = uavmsg::heartbeat_t::SOURCE_VEHICLE;
    hb.signing = c_.signatures.enabled() ? uavmsg::heartbeat_t::SIGNING_ON : uavmsg::heartbeat_t::SIGNING_OFF;
    hb.signature_rejections = static_cast<int32_t>(std::min<int64_t>(c_.signatures.rejections(), INT32_MAX));
    hb.source_name = c_.vehicle_id;
    hb.uptime_us = utime - start_;
    hb.armed = d.armed;
    hb.flight_mode = static_cast<int8_t>(d.sample.rc_manual ? FlightMode::kManual : FlightMode::kAuto);
    hb.task = static_cast<int8_t>(d.task);
    // The simulator's pace, measured: simulated time over wall time since the last heartbeat.
    const auto wall = std::chrono::steady_clock::now();
    hb.sim_rate_asked = static_cast<float>(c_.params.sim_rate_asked);
    hb.sim_rate = hb.sim_rate_asked;
    if (c_.params.sim_rate_asked >= 0 && last_wall_) {
      const double wall_s = std::chrono::duration<double>(wall - *last_wall_).count();
      if (wall_s > 0 && last_sim_ >= 0) hb.sim_rate = static_cast<float>((utime - last_sim_) * 1e-6 / wall_s);
    }
    last_wall_ = wall;
    last_sim_ = utime;
    c_.Publish(Topic::kHeartbeat, hb);
  }

 private:
  LinkContext& c_;
  int64_t start_ = -1, last_ = -1;
  std::optional<std::chrono::steady_clock::time_point> last_wall_;
  int64_t last_sim_ = -1;
};

class VideoTranslator : public Translator {
 public:
  explicit VideoTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    for (VideoFrame& preview : c_.board.previews.TakeAll()) {
      if (preview.jpeg.size() > static_cast<size_t>(uavmsg::video_frame_t::MAX_JPEG_BYTES)) continue;
      uavmsg::video_frame_t v = ToMessage(preview);
      c_.Publish(Topic::kVideo, v);
    }
  }

 private:
  LinkContext& c_;
};

class TrackStatusTranslator : public Translator {
 public:
  explicit TrackStatusTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    for (const TrackStatus& r : c_.board.track_reports.TakeAll()) {
      uavmsg::track_status_t m = ToMessage(r);
      c_.Publish(Topic::kTrackStatus, m);
    }
  }

 private:
  LinkContext& c_;
};

// Every vehicle report (uav/shared/reports.hpp): each type's newest, when there is one.
template <class T>
class ReportTranslator : public Translator {
 public:
  explicit ReportTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    if (auto report = c_.board.reports.Take<T>()) {
      typename Report<T>::Message m = ToMessage(*report);
      c_.Publish(Report<T>::kTopic, m);
    }
  }

 private:
  LinkContext& c_;
};

class MapTileTranslator : public Translator {
 public:
  explicit MapTileTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    // One tile per period at most, the longest-waiting first.
    if (last_ >= 0 && utime - last_ < Micros(c_.params.tile_period_s)) return;
    auto tile = c_.board.tiles.TakeOldest();
    if (!tile) return;
    last_ = utime;
    uavmsg::map_tile_t m = ToMessage(*tile);
    m.utime = utime;
    c_.Publish(Topic::kMapTile, m);
  }

 private:
  LinkContext& c_;
  int64_t last_ = -1;
};

class FileTransferTranslator : public Translator {
 public:
  FileTransferTranslator(LinkContext& c, FileSender& files) : c_(c), files_(files) {}
  void Tick(int64_t utime) override {
    for (auto& [name, contents] : c_.board.downloads.TakeAll()) files_.Offer(name, contents);
    const FileSender::Output out = files_.Poll(utime * 1e-6);
    for (const FileOffer& o : out.offers) {
      uavmsg::file_offer_t m;
      m.utime = utime;
      m.transfer_id = o.transfer_id;
      m.name = o.name;
      m.size = o.size;
      m.chunk_bytes = o.chunk_bytes;
      m.chunks = o.chunks;
      m.sha256 = o.sha256;
      c_.Publish(Topic::kFileOffer, m);
    }
    for (const FileChunk& ch : out.chunks) {
      uavmsg::file_chunk_t m;
      m.utime = utime;
      m.transfer_id = ch.transfer_id;
      m.index = ch.index;
      m.crc32 = static_cast<int32_t>(ch.crc32);
      m.size = static_cast<int32_t>(ch.data.size());
      m.data = ch.data;
      c_.Publish(Topic::kFileChunk, m);
    }
  }

 private:
  LinkContext& c_;
  FileSender& files_;
};

}  // namespace

std::unique_ptr<Translator> MakeAckTranslator(LinkContext& c) { return std::make_unique<AckTranslator>(c); }
std::unique_ptr<Translator> MakeStatusTextTranslator(LinkContext& c) { return std::make_unique<StatusTextTranslator>(c); }
std::unique_ptr<Translator> MakeStateTranslator(LinkContext& c) { return std::make_unique<StateTranslator>(c); }
std::unique_ptr<Translator> MakeHeartbeatTranslator(LinkContext& c) { return std::make_unique<HeartbeatTranslator>(c); }
std::unique_ptr<Translator> MakeVideoTranslator(LinkContext& c) { return std::make_unique<VideoTranslator>(c); }
std::unique_ptr<Translator> MakeTrackStatusTranslator(LinkContext& c) { return std::make_unique<TrackStatusTranslator>(c); }
std::vector<std::unique_ptr<Translator>> MakeReportTranslators(LinkContext& c) {
  std::vector<std::unique_ptr<Translator>> out;
  ForEachType(VehicleReports{}, [&](auto* type) {
    using T = std::remove_pointer_t<decltype(type)>;
    out.push_back(std::make_unique<ReportTranslator<T>>(c));
  });
  return out;
}
std::unique_ptr<Translator> MakeMapTileTranslator(LinkContext& c) { return std::make_unique<MapTileTranslator>(c); }
std::unique_ptr<Translator> MakeFileTransferTranslator(LinkContext& c, FileSender& files) {
  return std::make_unique<FileTransferTranslator>(c, files);
}

}  // namespace uav::runtime
