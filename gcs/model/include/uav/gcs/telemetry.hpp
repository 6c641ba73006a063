#pragma once
// Vehicles and their telemetry: link quality, the newest typed state and vehicle reports, and
// the history of every signal of the signal tables (uav/shared/vehicle_state.hpp for STATE, the
// heartbeat and tracker groups here, one group per vehicle report that declares signals:
// ReportSignals<T>). A signal is addressed by its group and its row in the group's table.
#include <cstdint>
#include <algorithm>
#include <deque>
#include <optional>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "uav/gcs/signal_series.hpp"
#include "uav/shared/reports.hpp"
#include "uav/shared/tracking.hpp"
#include "uav/shared/vehicle_state.hpp"

namespace uav::gcs {

// The telemetry tree's groups, one per message: the operator's three, then one per vehicle
// report (ReportGroup<T>(); empty for a report that declares no signals).
enum class SignalGroupId { kState = 0, kHeartbeat = 1, kTrack = 2 };
inline constexpr int kOperatorSignalGroups = 3;
inline constexpr int kSignalGroups = kOperatorSignalGroups + static_cast<int>(VehicleReports::kSize);
template <class T>
constexpr SignalGroupId ReportGroup() {
  return static_cast<SignalGroupId>(kOperatorSignalGroups + static_cast<int>(IndexOf<T>(VehicleReports{})));
}
std::string_view GroupName(SignalGroupId g);  // "STATE", "HEARTBEAT", "TRACK", "DEPTH"
const std::vector<SignalDef>& GroupSignals(SignalGroupId g);

struct SignalRef {
  SignalGroupId group = SignalGroupId::kState;
  int index = 0;  // row of GroupSignals(group)
  bool operator<(const SignalRef& o) const { return group != o.group ? group < o.group : index < o.index; }
  bool operator==(const SignalRef& o) const { return group == o.group && index == o.index; }
};
const SignalDef& Def(SignalRef s);
std::string Key(SignalRef s);  // "STATE.alt": for scripts, CSV headers and widget labels
// "STATE.alt", or a bare name ("alt") for the STATE group; nullopt when no table has it.
std::optional<SignalRef> FindSignal(std::string_view key);

// What the heartbeat says (heartbeat_t, 1 Hz).
struct HeartbeatInfo {
  Task task = Task::kIdle;
  bool armed = false;
  FlightMode flight_mode = FlightMode::kAuto;
  bool signing = false;               // the vehicle executes only messages signed with its key
  int64_t signature_rejections = 0;   // messages it refused by the signature check since start
  // The simulator's pace (simulated seconds per wall second): asked (0: as fast as it goes) and
  // measured; both < 0 for a real vehicle.
  double sim_rate_asked = -1.0;
  double sim_rate = -1.0;
  // A simulator running below 80 % of the pace asked ("max" asks for none): the GCS says
  // "SIM 0.37x", and judges the link on the vehicle's clock (LinkUp).
  bool SimSlow() const { return sim_rate_asked > 0 && sim_rate >= 0 && sim_rate < 0.8 * sim_rate_asked; }
};

// One group's receipts (rate and age), newest values and histories (one per table row).
struct SignalGroup {
  double last_receipt = -1.0;  // GCS clock
  std::deque<double> recent;   // receipt times within the last second
  int64_t received = 0;
  int64_t last_seq = -1;
  std::vector<double> latest;          // empty until the first message
  std::vector<SignalSeries> history;   // empty for groups without a time base (heartbeat)
  double Rate(double now) const;
  double Age(double now) const { return last_receipt < 0 ? 1e9 : now - last_receipt; }
};

// The newest report of one type and when it came (GCS clock, -1: never).
template <class T>
struct Received {
  std::optional<T> newest;
  double at = -1.0;
};
template <class List>
struct ReceivedReports;
template <class... Ts>
struct ReceivedReports<TypeList<Ts...>> {
  std::tuple<Received<Ts>...> slots;
  template <class T>
  const Received<T>& Get() const { return std::get<Received<T>>(slots); }
  template <class T>
  Received<T>& Get() { return std::get<Received<T>>(slots); }
  // The newest T while it is at most max_age_s old (stale reports must not look current).
  template <class T>
  const T* Fresh(double now, double max_age_s) const {
    const Received<T>& r = Get<T>();
    return r.newest && now - r.at <= max_age_s ? &*r.newest : nullptr;
  }
};

// A vehicle that speaks MAVLink (PX4, ArduPilot) rather than our bus: who it is and how its
// link is, as the GCS's MAVLink link found them.
struct MavlinkLinkInfo {
  std::string endpoint;             // udpin:14550, udp:HOST:PORT, serial:DEVICE
  int system_id = 0;
  std::string autopilot;            // "PX4", "ArduCopter", "ArduPlane", "ArduPlane VTOL", "generic"
  std::string frame;                // "quadrotor", "fixed wing", "VTOL tail-sitter"
  std::string mode;                 // its flight mode's name ("Mission", "Loiter")
  bool signing = false;             // frames checked against our key (and ours signed with it)
  int64_t refused_frames = 0;       // bad signature, unsigned, replayed or stale
  int64_t unknown_messages = 0;     // frames of messages we do not read
  int parameters_received = 0, parameters_total = 0;
};

struct TelemetryParams {
  double link_up_age_s = 3.0;     // a vehicle whose heartbeat is older is shown as LOST
};

struct VehicleTelemetry {
  // Link quality, measured on the GCS's clock.
  double last_heartbeat = -1.0;
  double last_message = -1.0;
  int64_t messages_total = 0;
  int64_t sequence_gaps = 0;               // messages missed, from header.seq jumps
  std::deque<double> recent_receipts;      // receive times within the last second
  SignalGroup groups[kSignalGroups];
  double first_t = -1.0;                   // vehicle time of the first sample (plot origin)
  std::optional<VehicleState> state;       // newest STATE
  std::optional<HeartbeatInfo> heartbeat;  // newest HEARTBEAT
  std::optional<Task> task;                // from the newer of the two
  bool armed = false;
  std::optional<GeodeticPoint> home;       // origin of the vehicle's x, y, z (last valid one)
  // The map's trail: north, east [m] of every kTrailDecimation-th state, the newest kTrailPoints.
  static constexpr int kTrailDecimation = 5;        // 50 Hz state -> 10 Hz trail
  static constexpr std::size_t kTrailPoints = 3000;  // 5 minutes
  std::deque<Eigen::Vector2d> trail;
  // Beside it (thesis ch. 5): the GPS fixes, the VO+IMU filter's track and, in simulation, the
  // truth, north and east [m] from home, at most kTrailPoints each.
  std::deque<Eigen::Vector2d> gps_trail, vo_trail, truth_trail;
  std::optional<PositionSource> position_source;  // where the INS takes its position from
  ReceivedReports<VehicleReports> reports;     // the newest of each vehicle report
  std::optional<MavlinkLinkInfo> mavlink;      // set for a MAVLink vehicle

  const SignalGroup& group(SignalGroupId g) const { return groups[static_cast<int>(g)]; }
  // Newest value and history of a signal; nullopt / nullptr before its first sample.
  std::optional<double> Latest(SignalRef s) const;
  const SignalSeries* History(SignalRef s) const;
  double HeartbeatAge(double now) const { return last_heartbeat < 0 ? 1e9 : now - last_heartbeat; }
  double MessageRate(double now) const;
  // The heartbeat's age on the vehicle's clock: a simulator slower than real time sends its 1 Hz
  // heartbeat less often in wall time, which is not a lost link.
  double HeartbeatAgeOnVehicleClock(double now) const {
    const double rate = heartbeat && heartbeat->sim_rate > 0 ? heartbeat->sim_rate : 1.0;
    return HeartbeatAge(now) * std::min(rate, 1.0);
  }
  bool LinkUp(double now, const TelemetryParams& p = {}) const { return HeartbeatAgeOnVehicleClock(now) < p.link_up_age_s; }
};

// Telemetry inputs; each updates the link statistics and the group's values and histories.
void OnHeartbeat(VehicleTelemetry& v, int64_t seq, const HeartbeatInfo& hb, double now);
void OnState(VehicleTelemetry& v, int64_t seq, const VehicleState& s, double now);
void OnTrackTelemetry(VehicleTelemetry& v, int64_t seq, const TrackStatus& st, double now);
// One sample of a group: its values (the table's rows) at vehicle time t_s [s].
void OnGroupSample(VehicleTelemetry& v, SignalGroupId g, const std::vector<double>& values, double t_s, double now);

// Any vehicle report: kept as the newest of its type, and its signals sampled.
template <class T>
void OnReportTelemetry(VehicleTelemetry& v, T r, double now) {
  const auto& table = ReportSignals<T>::Table();
  if (!table.empty()) {
    std::vector<double> values;
    values.reserve(table.size());
    for (const auto& s : table) values.push_back(s.read(r));
    OnGroupSample(v, ReportGroup<T>(), values, r.utime * 1e-6, now);
  }
  Received<T>& slot = v.reports.Get<T>();
  slot.newest = std::move(r);
  slot.at = now;
}

// The visual odometry's track and truth trails and the INS's position source.
void OnVisualOdometryTrack(VehicleTelemetry& v, const VisualOdometryReport& r);

}  // namespace uav::gcs
