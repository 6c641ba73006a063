#include "uav/gcs/telemetry.hpp"

#include <algorithm>

#include "uav/shared/geodesy.hpp"

namespace uav::gcs {
namespace {

// The tables of the two GCS-side groups, read from their typed messages.
const std::vector<Signal<HeartbeatInfo>>& HeartbeatSignals() {
  static const std::vector<Signal<HeartbeatInfo>> k = {
      {{"task", "task", "1", "", SignalFormat::kTask}, [](const HeartbeatInfo& h) { return double(static_cast<int>(h.task)); }},
      {{"armed", "armed", "1", "", SignalFormat::kBool}, [](const HeartbeatInfo& h) { return h.armed ? 1.0 : 0.0; }},
      {{"signing", "signing", "1", "1 only signed messages executed, 0 insecure", SignalFormat::kBool},
       [](const HeartbeatInfo& h) { return h.signing ? 1.0 : 0.0; }},
      {{"rejected", "signature_rejections", "1", "refused by the signature check", SignalFormat::kInteger},
       [](const HeartbeatInfo& h) { return double(h.signature_rejections); }},
      {{"sim_rate", "sim_rate", "1", "simulated seconds per wall second (measured; -1: a real vehicle)", SignalFormat::kNormalised},
       [](const HeartbeatInfo& h) { return h.sim_rate; }},
  };
  return k;
}

const std::vector<Signal<TrackStatus>>& TrackSignals() {
  static const std::vector<Signal<TrackStatus>> k = {
      {{"state", "state", "1", "", SignalFormat::kInteger}, [](const TrackStatus& t) { return double(t.state); }},
      {{"center_x", "center_x", "1", "image", SignalFormat::kNormalised}, [](const TrackStatus& t) { return t.center_x; }},
      {{"center_y", "center_y", "1", "image", SignalFormat::kNormalised}, [](const TrackStatus& t) { return t.center_y; }},
      {{"width", "width", "1", "image", SignalFormat::kNormalised}, [](const TrackStatus& t) { return t.width; }},
      {{"height", "height", "1", "image", SignalFormat::kNormalised}, [](const TrackStatus& t) { return t.height; }},
  };
  return k;
}

// Depth from motion: every cell of the thesis's 4x3 grid (Fig. 3.11) by row and column from the
// top-left, 0 while unknown, and the feature counts.
template <int kCell>
double CellDepth(const DepthGrid& g) {
  const int r = kCell / 4, c = kCell % 4;
  return r < g.rows && c < g.cols ? g.at(r, c).depth_m : 0.0;
}

const std::vector<Signal<DepthGrid>>& DepthSignals() {
  using F = SignalFormat;
  static const std::vector<Signal<DepthGrid>> k = {
      {{"r0c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<0>},
      {{"r0c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<1>},
      {{"r0c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<2>},
      {{"r0c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<3>},
      {{"r1c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<4>},
      {{"r1c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<5>},
      {{"r1c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<6>},
      {{"r1c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<7>},
      {{"r2c0", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<8>},
      {{"r2c1", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<9>},
      {{"r2c2", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<10>},
      {{"r2c3", "depth_m", "m", "C, 0 unknown", F::kMetres}, CellDepth<11>},
      {{"tracked", "tracked", "1", "", F::kInteger}, [](const DepthGrid& g) { return double(g.tracked); }},
      {{"measured", "measured", "1", "", F::kInteger}, [](const DepthGrid& g) { return double(g.measured); }},
  };
  return k;
}

// Active stereo: the height over the ground cluster (0 while there is none), its standard
// error, and the dot counts behind it.
// Visual odometry: health, counts, where the INS's position comes from, and the VO+IMU track's
// horizontal distance from the truth (simulation; 0 without one).
const std::vector<Signal<VisualOdometryReport>>& VisualOdometrySignals() {
  using F = SignalFormat;
  using R = VisualOdometryReport;
  static const std::vector<Signal<R>> k = {
      {{"healthy", "healthy", "1", "1 a motion, 0 none", F::kBool}, [](const R& r) { return double(r.healthy); }},
      {{"source", "source", "1", "0 GPS, 1 vision, 2 inertial", F::kInteger}, [](const R& r) { return double(r.source); }},
      {{"inliers", "inliers", "1", "", F::kInteger}, [](const R& r) { return double(r.inliers); }},
      {{"tracked", "tracked", "1", "", F::kInteger}, [](const R& r) { return double(r.tracked); }},
      {{"segment", "segment", "1", "", F::kInteger}, [](const R& r) { return double(r.segment); }},
      {{"rms", "rms_px", "px", "", F::kMetres}, [](const R& r) { return r.rms_px; }},
      {{"track_n", "track_n_m", "m", "VO+IMU north", F::kMetres}, [](const R& r) { return r.track_N ? r.track_N->x() : 0.0; }},
      {{"track_e", "track_e_m", "m", "VO+IMU east", F::kMetres}, [](const R& r) { return r.track_N ? r.track_N->y() : 0.0; }},
      {{"truth_n", "truth_n_m", "m", "simulation", F::kMetres}, [](const R& r) { return r.truth_N ? r.truth_N->x() : 0.0; }},
      {{"truth_e", "truth_e_m", "m", "simulation", F::kMetres}, [](const R& r) { return r.truth_N ? r.truth_N->y() : 0.0; }},
      {{"error", "error_m", "m", "VO+IMU from truth, horizontal", F::kMetres}, [](const R& r) {
         return r.track_N && r.truth_N ? (r.track_N->head<2>() - r.truth_N->head<2>()).norm() : 0.0;
       }},
      {{"truth_alt", "truth_alt_m", "m", "simulation, up from home", F::kMetres}, [](const R& r) { return r.truth_N ? -r.truth_N->z() : 0.0; }},
      {{"error_alt", "error_alt_m", "m", "VO+IMU from truth, vertical (up +)", F::kMetres}, [](const R& r) {
         return r.track_N && r.truth_N ? r.truth_N->z() - r.track_N->z() : 0.0;
       }},
  };
  return k;
}

const std::vector<Signal<ActiveStereoReport>>& ActiveStereoSignals() {
  using F = SignalFormat;
  using R = ActiveStereoReport;
  static const std::vector<Signal<R>> k = {
      {{"height", "height_m", "m", "over the ground, 0 none", F::kMetres}, [](const R& r) { return r.height_m; }},
      {{"height_sigma", "height_sigma_m", "m", "", F::kMetres}, [](const R& r) { return r.height_sigma_m; }},
      {{"points", "points", "1", "", F::kInteger}, [](const R& r) { return double(r.dots.size()); }},
      {{"left_dots", "left_dots", "1", "", F::kInteger}, [](const R& r) { return double(r.left_dots); }},
      {{"right_dots", "right_dots", "1", "", F::kInteger}, [](const R& r) { return double(r.right_dots); }},
      {{"ambiguous", "ambiguous", "1", "", F::kInteger}, [](const R& r) { return double(r.ambiguous); }},
      {{"clusters", "clusters", "1", "", F::kInteger}, [](const R& r) { return double(r.clusters.size()); }},
  };
  return k;
}

template <class T>
std::vector<SignalDef> Defs(const std::vector<Signal<T>>& table) {
  std::vector<SignalDef> out;
  for (const auto& s : table) out.push_back(s.def);
  return out;
}

void Receipt(VehicleTelemetry& v, SignalGroup& g, int64_t seq, double now) {
  ++v.messages_total;
  v.last_message = now;
  v.recent_receipts.push_back(now);
  while (!v.recent_receipts.empty() && now - v.recent_receipts.front() > 1.0) v.recent_receipts.pop_front();
  if (g.last_seq >= 0 && seq > g.last_seq + 1) v.sequence_gaps += seq - g.last_seq - 1;
  if (seq > g.last_seq) g.last_seq = seq;
  g.last_receipt = now;
  ++g.received;
  g.recent.push_back(now);
  while (!g.recent.empty() && now - g.recent.front() > 1.0) g.recent.pop_front();
}

// Reads every row of `table` from `msg`; `t` < 0: no time base, newest values only.
template <class T>
void Store(VehicleTelemetry& v, SignalGroup& g, const std::vector<Signal<T>>& table, const T& msg, double t) {
  g.latest.resize(table.size());
  for (std::size_t i = 0; i < table.size(); ++i) g.latest[i] = table[i].read(msg);
  if (t < 0) return;
  if (v.first_t < 0.0) v.first_t = t;
  g.history.resize(table.size());
  for (std::size_t i = 0; i < table.size(); ++i) g.history[i].Push(t - v.first_t, g.latest[i]);
}

}  // namespace

namespace {

// Sensing: how many vision workers run and how many are unhealthy, their drops, and the control
// loop's wall-clock period (vision must never stretch it).
const std::vector<Signal<SensingReport>>& SensingSignals() {
  using F = SignalFormat;
  using R = SensingReport;
  static const std::vector<Signal<R>> k = {
      {{"workers", "workers", "1", "vision workers running", F::kInteger}, [](const R& r) { return double(r.workers.size()); }},
      {{"unhealthy", "unhealthy", "1", "behind or stalled", F::kInteger}, [](const R& r) {
         return double(std::count_if(r.workers.begin(), r.workers.end(), [](const SensingWorker& w) { return !w.healthy; }));
       }},
      {{"dropped", "dropped", "1", "frames dropped, all workers", F::kInteger}, [](const R& r) {
         double n = 0;
         for (const SensingWorker& w : r.workers) n += w.dropped;
         return n;
       }},
      {{"ctl_p50", "control_period_p50_ms", "ms", "nominal 20", F::kMetres}, [](const R& r) { return r.control_period_p50_ms; }},
      {{"ctl_p99", "control_period_p99_ms", "ms", "", F::kMetres}, [](const R& r) { return r.control_period_p99_ms; }},
      {{"ctl_max", "control_period_max_ms", "ms", "", F::kMetres}, [](const R& r) { return r.control_period_max_ms; }},
  };
  return k;
}

}  // namespace

std::string_view GroupName(SignalGroupId g) {
  switch (g) {
    case SignalGroupId::kState: return "STATE";
    case SignalGroupId::kHeartbeat: return "HEARTBEAT";
    case SignalGroupId::kTrack: return "TRACK";
    case SignalGroupId::kDepth: return "DEPTH";
    case SignalGroupId::kActiveStereo: return "ASTEREO";
    case SignalGroupId::kVisualOdometry: return "VO";
    case SignalGroupId::kSensing: return "SENSING";
  }
  return "?";
}

const std::vector<SignalDef>& GroupSignals(SignalGroupId g) {
  static const std::vector<SignalDef> kState = Defs(VehicleStateSignals());
  static const std::vector<SignalDef> kHeartbeat = Defs(HeartbeatSignals());
  static const std::vector<SignalDef> kTrack = Defs(TrackSignals());
  static const std::vector<SignalDef> kDepth = Defs(DepthSignals());
  static const std::vector<SignalDef> kActiveStereo = Defs(ActiveStereoSignals());
  static const std::vector<SignalDef> kVisualOdometry = Defs(VisualOdometrySignals());
  static const std::vector<SignalDef> kSensing = Defs(SensingSignals());
  switch (g) {
    case SignalGroupId::kState: return kState;
    case SignalGroupId::kHeartbeat: return kHeartbeat;
    case SignalGroupId::kTrack: return kTrack;
    case SignalGroupId::kDepth: return kDepth;
    case SignalGroupId::kActiveStereo: return kActiveStereo;
    case SignalGroupId::kVisualOdometry: return kVisualOdometry;
    case SignalGroupId::kSensing: return kSensing;
  }
  return kState;
}

const SignalDef& Def(SignalRef s) { return GroupSignals(s.group).at(s.index); }

std::string Key(SignalRef s) { return std::string(GroupName(s.group)) + "." + std::string(Def(s).name); }

std::optional<SignalRef> FindSignal(std::string_view key) {
  const auto dot = key.find('.');
  const std::string_view group = dot == std::string_view::npos ? "STATE" : key.substr(0, dot);
  const std::string_view name = dot == std::string_view::npos ? key : key.substr(dot + 1);
  for (int g = 0; g < kSignalGroups; ++g) {
    const auto id = static_cast<SignalGroupId>(g);
    if (GroupName(id) != group) continue;
    const auto& defs = GroupSignals(id);
    for (std::size_t i = 0; i < defs.size(); ++i)
      if (defs[i].name == name) return SignalRef{id, static_cast<int>(i)};
  }
  return std::nullopt;
}

double SignalGroup::Rate(double now) const {
  int n = 0;
  for (double t : recent) n += now - t <= 1.0;
  return n;
}

std::optional<double> VehicleTelemetry::Latest(SignalRef s) const {
  const SignalGroup& g = group(s.group);
  if (s.index < 0 || s.index >= static_cast<int>(g.latest.size())) return std::nullopt;
  return g.latest[s.index];
}

const SignalSeries* VehicleTelemetry::History(SignalRef s) const {
  const SignalGroup& g = group(s.group);
  if (s.index < 0 || s.index >= static_cast<int>(g.history.size())) return nullptr;
  return &g.history[s.index];
}

double VehicleTelemetry::MessageRate(double now) const {
  int n = 0;
  for (double t : recent_receipts) n += now - t <= 1.0;
  return n;
}

void OnHeartbeat(VehicleTelemetry& v, int64_t seq, const HeartbeatInfo& hb, double now) {
  SignalGroup& g = v.groups[static_cast<int>(SignalGroupId::kHeartbeat)];
  Receipt(v, g, seq, now);
  v.last_heartbeat = now;
  v.heartbeat = hb;
  v.task = hb.task;
  v.armed = hb.armed;
  Store(v, g, HeartbeatSignals(), hb, -1.0);
}

void OnState(VehicleTelemetry& v, int64_t seq, const VehicleState& s, double now) {
  SignalGroup& g = v.groups[static_cast<int>(SignalGroupId::kState)];
  Receipt(v, g, seq, now);
  v.state = s;
  v.task = s.task;  // the 50 Hz state is fresher than the heartbeat
  v.armed = s.armed;
  try {
    ValidateGeodetic(s.home);
    v.home = s.home;
  } catch (const std::invalid_argument&) {
    // no or bad home in this sample: keep the last good one
  }
  Store(v, g, VehicleStateSignals(), s, s.utime * 1e-6);
  if ((g.received - 1) % VehicleTelemetry::kTrailDecimation == 0) {
    v.trail.push_back(s.p_N.head<2>());
    while (v.trail.size() > VehicleTelemetry::kTrailPoints) v.trail.pop_front();
    if (v.home && s.gps_fix >= 3) {
      try {
        v.gps_trail.push_back(LocalNedFrame(*v.home).ToNed(s.gps).head<2>());
        while (v.gps_trail.size() > VehicleTelemetry::kTrailPoints) v.gps_trail.pop_front();
      } catch (const std::exception&) {
        // a fix that is not a place on Earth: not drawn
      }
    }
  }
}

void OnTrackTelemetry(VehicleTelemetry& v, int64_t seq, const TrackStatus& st, double now) {
  SignalGroup& g = v.groups[static_cast<int>(SignalGroupId::kTrack)];
  Receipt(v, g, seq, now);
  Store(v, g, TrackSignals(), st, st.utime * 1e-6);
}

void OnDepthTelemetry(VehicleTelemetry& v, const DepthGrid& g, double now) {
  SignalGroup& group = v.groups[static_cast<int>(SignalGroupId::kDepth)];
  Receipt(v, group, group.last_seq + 1, now);  // mono_depth_t's own sequence is not kept
  Store(v, group, DepthSignals(), g, g.utime * 1e-6);
}

void OnActiveStereoTelemetry(VehicleTelemetry& v, const ActiveStereoReport& r, double now) {
  SignalGroup& group = v.groups[static_cast<int>(SignalGroupId::kActiveStereo)];
  Receipt(v, group, group.last_seq + 1, now);  // active_stereo_t's own sequence is not kept
  Store(v, group, ActiveStereoSignals(), r, r.utime * 1e-6);
}

void OnVisualOdometryTelemetry(VehicleTelemetry& v, const VisualOdometryReport& r, double now) {
  SignalGroup& group = v.groups[static_cast<int>(SignalGroupId::kVisualOdometry)];
  Receipt(v, group, group.last_seq + 1, now);  // visual_odometry_t's own sequence is not kept
  Store(v, group, VisualOdometrySignals(), r, r.utime * 1e-6);
  v.position_source = r.source;
  auto push = [](std::deque<Eigen::Vector2d>& trail, const std::optional<Eigen::Vector3d>& p_N) {
    if (!p_N) return;
    trail.push_back(p_N->head<2>());
    while (trail.size() > VehicleTelemetry::kTrailPoints) trail.pop_front();
  };
  push(v.vo_trail, r.track_N);
  push(v.truth_trail, r.truth_N);
}

void OnSensingTelemetry(VehicleTelemetry& v, const SensingReport& r, double now) {
  SignalGroup& group = v.groups[static_cast<int>(SignalGroupId::kSensing)];
  Receipt(v, group, group.last_seq + 1, now);  // sensing_t's own sequence is not kept
  Store(v, group, SensingSignals(), r, r.utime * 1e-6);
  v.sensing = r;
  v.sensing_received = now;
}

}  // namespace uav::gcs
