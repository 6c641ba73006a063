// Outbound translators: acknowledgements, status texts, state, heartbeat, video, power lines, live-map tiles
// and file offers and chunks. Each reads the blackboard (or a store) and publishes one topic.
#include "link_translators.hpp"

#include <algorithm>
#include <climits>
#include <chrono>
#include <cmath>
#include <optional>

#include "uav/app/reported_state.hpp"
#include "uavmsg/file_chunk_t.hpp"
#include "uavmsg/file_offer_t.hpp"
#include "uavmsg/heartbeat_t.hpp"

#include <chrono>
#include <optional>
#include "uavmsg/map_tile_t.hpp"
#include "uavmsg/active_stereo_t.hpp"
#include "uavmsg/visual_odometry_t.hpp"
#include "uavmsg/sensing_t.hpp"
#include "uavmsg/mono_depth_t.hpp"
#include "uavmsg/obstacles_t.hpp"
#include "uavmsg/point_cloud_t.hpp"
#include "uavmsg/power_lines_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/track_status_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uavmsg/video_frame_t.hpp"

namespace uav::app {
namespace {

int64_t Micros(double seconds) { return static_cast<int64_t>(std::llround(seconds * 1e6)); }

class AckTranslator : public Translator {
 public:
  explicit AckTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    for (const auto& r : c_.board.TakeReports()) SendAck(c_, utime, r);
  }

 private:
  LinkContext& c_;
};

class StatusTextTranslator : public Translator {
 public:
  explicit StatusTextTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    for (const auto& s : c_.board.TakeStatus()) {
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
    for (PreviewFrame& preview : c_.board.TakePreviews()) {
      if (preview.jpeg.size() > static_cast<size_t>(uavmsg::video_frame_t::MAX_JPEG_BYTES)) continue;
      uavmsg::video_frame_t v;
      v.utime = preview.utime;
      v.camera = preview.camera;
      v.width = static_cast<int16_t>(preview.width);
      v.height = static_cast<int16_t>(preview.height);
      v.source_width = static_cast<int16_t>(preview.source_width);
      v.source_height = static_cast<int16_t>(preview.source_height);
      v.size = static_cast<int32_t>(preview.jpeg.size());
      v.jpeg = std::move(preview.jpeg);
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
    for (const TrackReport& r : c_.board.TakeTrackReports()) {
      uavmsg::track_status_t m = ToMessage(r);
      c_.Publish(Topic::kTrackStatus, m);
    }
  }

 private:
  LinkContext& c_;
};

class PowerLinesTranslator : public Translator {
 public:
  explicit PowerLinesTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    auto lines = c_.board.TakePowerLines();
    if (!lines) return;
    uavmsg::power_lines_t m = ToMessage(*lines);
    c_.Publish(Topic::kPowerLines, m);
  }

 private:
  LinkContext& c_;
};

// MDEPTH's newest grid.
class MonoDepthTranslator : public Translator {
 public:
  explicit MonoDepthTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    if (auto grid = c_.board.TakeDepthGrid()) {
      uavmsg::mono_depth_t m = ToMessage(*grid);
      c_.Publish(Topic::kMonoDepth, m);
    }
  }

 private:
  LinkContext& c_;
};

// ASTEREO's newest report.
class ActiveStereoTranslator : public Translator {
 public:
  explicit ActiveStereoTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    if (auto report = c_.board.TakeActiveStereo()) {
      uavmsg::active_stereo_t m = ToMessage(*report);
      c_.Publish(Topic::kActiveStereo, m);
    }
  }

 private:
  LinkContext& c_;
};

// VO's newest report, with the VO+IMU filter's track and the INS's position source.
class VisualOdometryTranslator : public Translator {
 public:
  explicit VisualOdometryTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    if (auto report = c_.board.TakeVisualOdometry()) {
      const BlackboardData d = c_.board.Snapshot();
      report->track_N = d.vo_track_N;
      report->source = d.position_source;
      uavmsg::visual_odometry_t m = ToMessage(*report);
      c_.Publish(Topic::kVisualOdometry, m);
    }
  }

 private:
  LinkContext& c_;
};

// The vision workers' health at 1 Hz (while there are any).
class SensingTranslator : public Translator {
 public:
  explicit SensingTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t utime) override {
    if (last_utime_ >= 0 && utime - last_utime_ < 1'000'000) return;
    const BlackboardData d = c_.board.Snapshot();
    if (d.sensing.workers.empty()) return;
    last_utime_ = utime;
    uavmsg::sensing_t m = ToMessage(d.sensing);
    c_.Publish(Topic::kSensing, m);
  }

 private:
  LinkContext& c_;
  int64_t last_utime_ = -1;
};

class ObstaclesTranslator : public Translator {
 public:
  explicit ObstaclesTranslator(LinkContext& c) : c_(c) {}
  void Tick(int64_t) override {
    if (auto obstacles = c_.board.TakeObstacles()) {
      uavmsg::obstacles_t m = ToMessage(*obstacles);
      c_.Publish(Topic::kObstacles, m);
    }
    if (auto cloud = c_.board.TakePointCloud()) {
      uavmsg::point_cloud_t m = ToMessage(*cloud);
      c_.Publish(Topic::kPointCloud, m);
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
    auto tile = c_.board.TakeTile();
    if (!tile) return;
    last_ = utime;
    uavmsg::map_tile_t m;
    m.utime = utime;
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
    for (auto& [name, contents] : c_.board.TakeDownloads()) files_.Offer(name, contents);
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
std::unique_ptr<Translator> MakePowerLinesTranslator(LinkContext& c) { return std::make_unique<PowerLinesTranslator>(c); }
std::unique_ptr<Translator> MakeObstaclesTranslator(LinkContext& c) { return std::make_unique<ObstaclesTranslator>(c); }
std::unique_ptr<Translator> MakeMonoDepthTranslator(LinkContext& c) { return std::make_unique<MonoDepthTranslator>(c); }
std::unique_ptr<Translator> MakeActiveStereoTranslator(LinkContext& c) { return std::make_unique<ActiveStereoTranslator>(c); }
std::unique_ptr<Translator> MakeVisualOdometryTranslator(LinkContext& c) { return std::make_unique<VisualOdometryTranslator>(c); }
std::unique_ptr<Translator> MakeSensingTranslator(LinkContext& c) { return std::make_unique<SensingTranslator>(c); }
std::unique_ptr<Translator> MakeMapTileTranslator(LinkContext& c) { return std::make_unique<MapTileTranslator>(c); }
std::unique_ptr<Translator> MakeFileTransferTranslator(LinkContext& c, FileSender& files) {
  return std::make_unique<FileTransferTranslator>(c, files);
}

}  // namespace uav::app
