#include "uav/gcs/telemetry.hpp"

#include <algorithm>
#include <type_traits>

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


// Per report group (in the order of VehicleReports): its name and signal definitions.
struct ReportGroupInfo {
  std::string_view name;
  std::vector<SignalDef> defs;
};
const std::vector<ReportGroupInfo>& ReportGroups() {
  static const std::vector<ReportGroupInfo> k = [] {
    std::vector<ReportGroupInfo> out;
    ForEachType(VehicleReports{}, [&](auto* type) {
      using T = std::remove_pointer_t<decltype(type)>;
      out.push_back({ReportSignals<T>::kGroup, Defs(ReportSignals<T>::Table())});
    });
    return out;
  }();
  return k;
}

}  // namespace

std::string_view GroupName(SignalGroupId g) {
  switch (g) {
    case SignalGroupId::kState: return "STATE";
    case SignalGroupId::kHeartbeat: return "HEARTBEAT";
    case SignalGroupId::kTrack: return "TRACK";
  }
  const int i = static_cast<int>(g) - kOperatorSignalGroups;
  return i >= 0 && i < static_cast<int>(ReportGroups().size()) ? ReportGroups()[i].name : "?";
}

const std::vector<SignalDef>& GroupSignals(SignalGroupId g) {
  static const std::vector<SignalDef> kState = Defs(VehicleStateSignals());
  static const std::vector<SignalDef> kHeartbeat = Defs(HeartbeatSignals());
  static const std::vector<SignalDef> kTrack = Defs(TrackSignals());
  static const std::vector<SignalDef> kNone;
  switch (g) {
    case SignalGroupId::kState: return kState;
    case SignalGroupId::kHeartbeat: return kHeartbeat;
    case SignalGroupId::kTrack: return kTrack;
  }
  const int i = static_cast<int>(g) - kOperatorSignalGroups;
  return i >= 0 && i < static_cast<int>(ReportGroups().size()) ? ReportGroups()[i].defs : kNone;
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

void OnGroupSample(VehicleTelemetry& v, SignalGroupId id, const std::vector<double>& values, double t_s, double now) {
  SignalGroup& g = v.groups[static_cast<int>(id)];
  Receipt(v, g, g.last_seq + 1, now);  // a report's own sequence is not kept
  g.latest = values;
  if (v.first_t < 0.0) v.first_t = t_s;
  g.history.resize(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) g.history[i].Push(t_s - v.first_t, values[i]);
}

void OnVisualOdometryTrack(VehicleTelemetry& v, const VisualOdometryReport& r) {
  v.position_source = r.source;
  auto push = [](std::deque<Eigen::Vector2d>& trail, const std::optional<Eigen::Vector3d>& p_N) {
    if (!p_N) return;
    trail.push_back(p_N->head<2>());
    while (trail.size() > VehicleTelemetry::kTrailPoints) trail.pop_front();
  };
  push(v.vo_trail, r.track_N);
  push(v.truth_trail, r.truth_N);
}

}  // namespace uav::gcs
