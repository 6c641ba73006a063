#include "uav/gcs/gcs_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "uav/shared/flight_envelope.hpp"

#include "uav/waypoints/mission_file.hpp"

namespace uav::gcs {

VehicleModel& GcsModel::Vehicle(const std::string& id) {
  auto [it, inserted] = vehicles_.try_emplace(id);
  if (inserted) {
    it->second.id = id;
    if (selected_.empty()) selected_ = id;  // the first vehicle heard is shown
  }
  return it->second;
}

const VehicleModel* GcsModel::selected() const {
  auto it = vehicles_.find(selected_);
  return it == vehicles_.end() ? nullptr : &it->second;
}

VehicleModel* GcsModel::Selected() {
  auto it = vehicles_.find(selected_);
  return it == vehicles_.end() ? nullptr : &it->second;
}

void GcsModel::OnHeartbeat(const std::string& vehicle_id, int64_t seq, const HeartbeatInfo& hb, double now) {
  const bool fresh = !vehicles_.count(vehicle_id);
  VehicleModel& v = Vehicle(vehicle_id);
  if (fresh) log_.Add(now, vehicle_id, "vehicle discovered", Severity::kInfo);
  const bool was_slow = v.heartbeat && v.heartbeat->SimSlow();
  gcs::OnHeartbeat(v, seq, hb, now);
  char pace[128];
  std::snprintf(pace, sizeof pace, "simulator at %.2fx of the %.3gx asked", hb.sim_rate, hb.sim_rate_asked);
  if (hb.SimSlow() && !was_slow)
    log_.Add(now, vehicle_id, std::string(pace) + ": the vehicle's clock runs slow, not the link", Severity::kWarning);
  else if (!hb.SimSlow() && was_slow)
    log_.Add(now, vehicle_id, std::string(pace) + ": back to pace", Severity::kInfo);
}

void GcsModel::OnState(const std::string& vehicle_id, int64_t seq, const VehicleState& state, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  const std::optional<VehicleState> previous = v.state;
  gcs::OnState(v, seq, state, now);
  const auto& table = v.reports.Get<ParameterTable>().newest;
  const StateLimits limits = StateLimits::From(table ? &*table : nullptr, state.vehicle_type);
  for (const auto& [text, severity] : v.state_alarms.Update(AbsurdState(previous ? &*previous : nullptr, state, limits)))
    log_.Add(now, vehicle_id, text, severity);
  if (vehicle_id == selected_ && v.home) missions_.planner().SetOrigin(*v.home);
}

void GcsModel::OnAck(const std::string& vehicle_id, const CommandAck& ack, double now) {
  if (replay_) {  // a recorded flight: every GCS's conversation with the vehicle, as it happened
    if (ack.result == CommandResult::kInProgress) return;
    const bool bad = IsFailure(ack.result);
    log_.Add(now, vehicle_id,
             ack.command + ": " + std::string(Name(ack.result)) + (ack.reason.empty() ? "" : " (" + ack.reason + ")") +
                 " [to " + ack.source + "]",
             bad ? Severity::kWarning : Severity::kInfo);
    return;
  }
  commands_.OnAck(vehicle_id, ack, now, log_);
}

void GcsModel::OnStatusText(const std::string& vehicle_id, Severity severity, const std::string& text, double now) {
  Vehicle(vehicle_id);
  log_.Add(now, vehicle_id, text, severity);
}

void GcsModel::OnMissionAck(const std::string& vehicle_id, const std::string& source,
                            const waypoints::MissionUploadAck& ack, double now) {
  if (source != gcs_name()) return;  // another GCS's upload
  auto it = vehicles_.find(vehicle_id);
  if (it != vehicles_.end()) missions_.OnMissionAck(it->second, vehicle_id, ack, now, log_);
}

void GcsModel::OnVideoFrame(const std::string& vehicle_id, const VideoFrame& frame, double now) {
  VideoTracking::OnVideoFrame(Vehicle(vehicle_id), vehicle_id, frame, now, log_);
}

void GcsModel::OnFileOffer(const std::string& vehicle_id, const FileOffer& offer, double now) {
  maps_.OnFileOffer(Vehicle(vehicle_id), vehicle_id, offer, now, log_);
}

void GcsModel::OnFileChunk(const std::string& vehicle_id, const FileChunk& chunk, double /*now*/) {
  auto it = vehicles_.find(vehicle_id);
  if (it != vehicles_.end()) MapsDownloads::OnFileChunk(it->second, chunk);
}

void GcsModel::OnMapTile(const std::string& vehicle_id, const MapTile& tile, double now) {
  MapsDownloads::OnMapTile(Vehicle(vehicle_id), vehicle_id, tile, now, log_);
}

void GcsModel::OnTrackStatus(const std::string& vehicle_id, int64_t seq, const TrackStatus& status, double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  if (VideoTracking::OnTrackStatus(v, vehicle_id, status, now, log_)) gcs::OnTrackTelemetry(v, seq, status, now);
}

void GcsModel::React(VehicleModel& v, const std::string& vehicle_id, const PowerLines& lines, double now) {
  wires_.OnPowerLines(v, vehicle_id, lines, now, log_);
}

void GcsModel::React(VehicleModel& v, const std::string& vehicle_id, const Obstacles& obstacles, double now) {
  obstacles_.OnObstacles(v, vehicle_id, obstacles, now, log_);
}

void GcsModel::React(VehicleModel& v, const std::string& vehicle_id, const DepthGrid& grid, double now) {
  obstacles_.OnDepthGrid(v, vehicle_id, grid, now, log_);
}

void GcsModel::React(VehicleModel& v, const std::string& vehicle_id, const ActiveStereoReport& report, double now) {
  obstacles_.OnActiveStereo(v, vehicle_id, report, now, log_);
}

void GcsModel::React(VehicleModel& v, const std::string& vehicle_id, const VisualOdometryReport& report, double now) {
  const std::optional<PositionSource> before = v.position_source;
  OnVisualOdometryTrack(v, report);
  if (before && *before != report.source)
    log_.Add(now, vehicle_id,
             std::string("position from ") + Name(report.source) +
                 (report.healthy ? std::string() : " (visual odometry: " + report.reason + ")"),
             report.source == PositionSource::kGps ? Severity::kInfo : Severity::kWarning);
}

void GcsModel::SelectVehicle(const std::string& id) {
  if (!vehicles_.count(id) || id == selected_) return;
  selected_ = id;
  // Nothing of one vehicle stays on another's panels.
  video_.Unfreeze();
  plots_.Follow();
}

bool GcsModel::SubmitCommand(const std::string& text, double now) {
  const VehicleModel* v = selected();
  // A MAVLink autopilot's parameters are its own: checked against its table, not our grammar.
  if (v && v->mavlink && text.rfind("param ", 0) == 0) {
    char name[64] = {0}, value[64] = {0}, extra[8] = {0};
    if (std::sscanf(text.c_str() + 6, "%63s %63s %7s", name, value, extra) == 2) return SetParameter(name, value, now);
  }
  return commands_.Submit(text, v ? selected_ : "", now, log_);
}

bool GcsModel::FreezeVideo(bool freeze) { return video_.Freeze(Selected(), selected_, freeze); }

bool GcsModel::ChooseVideoCamera(const std::string& camera) {
  VehicleModel* v = Selected();
  if (!v || !VideoTracking::ChooseCamera(*v, camera)) return false;
  video_.Unfreeze();
  return true;
}

bool GcsModel::SelectTarget(const TrackTarget& target, double now) {
  return video_.SelectTarget(Selected(), selected_, target, now, log_);
}

bool GcsModel::UploadMission(double now) {
  VehicleModel* v = Selected();
  return missions_.UploadMission(v, selected_, v ? v->home : std::nullopt, commands_, now, log_);
}

bool GcsModel::ExportMission(const std::string& path, double now) { return missions_.ExportMission(path, now, log_); }

bool GcsModel::ImportMission(const std::string& path, double now) {
  const VehicleModel* v = selected();
  return missions_.ImportMission(path, v ? v->home : std::nullopt, MissionLimits(), now, log_);
}

int FlownRow(const VehicleModel* v, const EditorCheck& made) {
  if (!v || !v->mission || !v->state || v->state->mission_item < 0) return -1;
  if (!made.mission || made.mission->items != v->mission->items) return -1;
  return made.RowOf(v->state->mission_item);
}

int GcsModel::FlownMissionRow() const {
  const VehicleModel* v = selected();
  if (!v || !v->mission || !v->state || v->state->mission_item < 0) return -1;  // nothing to make
  EditorCheck made;
  made.mission = missions_.editor().MakeMission(missions_.planner(), missions_.planner().origin(), &made.error, &made.origins);
  return FlownRow(v, made);
}

waypoints::VehicleLimits GcsModel::MissionLimits(bool* from_vehicle) const {
  const VehicleModel* v = selected();
  const auto* table = v ? &v->reports.Get<ParameterTable>() : nullptr;
  const bool known = table && table->newest;
  if (from_vehicle) *from_vehicle = known;
  return waypoints::VehicleLimits::Of([&](const std::string& name) {
    const ParameterEntry* e = known ? table->newest->Find(name) : nullptr;
    return e ? e->value : NAN;
  });
}

bool GcsModel::FitSurveyToVehicle(double now) {
  const VehicleModel* v = selected();
  const auto* table = v ? &v->reports.Get<ParameterTable>() : nullptr;
  if (!table || !table->newest) {
    log_.Add(now, selected_, "survey not fitted: no parameter table from the vehicle yet", Severity::kWarning);
    return false;
  }
  auto value = [&](const char* name) {
    const ParameterEntry* e = table->newest->Find(name);
    return e ? e->value : NAN;
  };
  SurveyPlanner& planner = missions_.planner();
  waypoints::SurveyParams& p = planner.params();
  bool wing = value("vehicle_type") == static_cast<double>(VehicleType::kTailSitter);
  double speed = wing ? value("ts_cruise_speed") : std::min(p.speed_m_s, value("ctl_speed_max_xy"));
  double radius = wing ? CoordinatedTurnRadius(speed, value("ts_bank_max"), value("gravity")) : 0.0;
  if (v->mavlink) {  // the autopilot's own names: its mission cruise speed and, on a wing, its bank limit
    const std::string& a = v->mavlink->autopilot;
    constexpr double kDegToRad = 3.14159265358979323846 / 180.0, kGravity = 9.80665;
    wing = a == "ArduPlane" || (a == "PX4" && v->state && v->state->vehicle_type == VehicleType::kTailSitter);
    if (a == "PX4") speed = wing ? value("FW_AIRSPD_TRIM") : value("MPC_XY_CRUISE");
    else if (a == "ArduCopter") speed = value("WPNAV_SPEED") / 100.0;  // [cm/s]
    else speed = std::isfinite(value("AIRSPEED_CRUISE")) ? value("AIRSPEED_CRUISE") : value("TRIM_ARSPD_CM") / 100.0;
    const double bank_deg = a == "PX4" ? value("FW_R_LIM") : value("ROLL_LIMIT_DEG");
    radius = wing ? CoordinatedTurnRadius(speed, bank_deg * kDegToRad, kGravity) : 0.0;
  }
  if (!std::isfinite(speed) || !std::isfinite(radius)) {
    log_.Add(now, selected_, "survey not fitted: the vehicle's parameter table lacks its speed or bank limit", Severity::kWarning);
    return false;
  }
  p.speed_m_s = speed;
  p.turn_radius_m = radius;
  char text[160];
  if (wing)
    std::snprintf(text, sizeof text, "survey fitted to %s, %s: its cruise %.1f m/s, turns of %.1f m radius",
                  selected_.c_str(), v->mavlink ? "a fixed wing" : "a tail-sitter", speed, radius);
  else
    std::snprintf(text, sizeof text, "survey fitted to %s, a multicopter: %.1f m/s, turns on the spot", selected_.c_str(), speed);
  planner.ParamsChanged();
  log_.Add(now, selected_, text, Severity::kInfo);
  return true;
}

bool GcsModel::StartDownload(const std::string& dir, double now) {
  return maps_.StartDownload(Selected(), selected_, dir, now, log_);
}

bool GcsModel::DownloadMission(double now) {
  VehicleModel* v = Selected();
  if (!v) {
    log_.Add(now, "", "no vehicle selected to download a mission from", Severity::kWarning);
    return false;
  }
  if (v->mavlink) {  // through the vehicle's mission service
    missions_.RequestDownload(selected_);
    log_.Add(now, selected_, "downloading the vehicle's mission, fence and rally points into the mission editor", Severity::kInfo);
    return true;
  }
  const FileOffer* newest = nullptr;
  long newest_n = -1;
  const std::vector<FileOffer> offers = v->files.offers();
  for (const FileOffer& o : offers) {
    long n = -1;
    char tail[8] = {0};
    if (std::sscanf(o.name.c_str(), "mission_%ld.%5s", &n, tail) == 2 && std::string(tail) == "plan" && n > newest_n)
      newest = &o, newest_n = n;
  }
  if (!newest) {
    log_.Add(now, selected_, "no mission offered yet (the vehicle offers each mission it accepts)", Severity::kWarning);
    return false;
  }
  std::string error;
  if (!v->files.Start(newest->transfer_id, &error)) {
    log_.Add(now, selected_, "download of " + newest->name + ": " + error, Severity::kError);
    return false;
  }
  v->for_editor.insert(newest->transfer_id);
  log_.Add(now, selected_, "downloading " + newest->name + " into the mission editor", Severity::kInfo);
  return true;
}

bool GcsModel::LoadBasemap(const std::string& path, double now) {
  if (!basemap_.Load(path, now, log_)) return false;
  const VehicleModel* v = selected();
  if (!v || !v->home) {
    GeodeticPoint centre;
    for (const GeodeticPoint& c : basemap_.image()->corners) {
      centre.latitude_deg += 0.25 * c.latitude_deg;
      centre.longitude_deg += 0.25 * c.longitude_deg;
    }
    missions_.planner().SetOrigin(centre);
  }
  return true;
}

bool GcsModel::ExportPlotCsv(const std::string& path, double t0, double t1, double now) {
  return plots_.ExportCsv(selected(), selected_, path, t0, t1, now, log_);
}

void GcsModel::SetReplay(bool replay) {
  replay_ = replay;
  commands_.SetRefusal(replay ? "replaying a log: nothing is sent to any vehicle" : "");
}

void GcsModel::Tick(double now) {
  for (auto& [id, v] : vehicles_) {
    maps_.Tick(v, id, now, log_);
    for (auto it = v.for_editor.begin(); it != v.for_editor.end();) {
      const auto p = v.files.progress(*it);
      const std::string* contents = v.files.Contents(*it);
      if (!p || p->failed) {
        it = v.for_editor.erase(it);  // the failure is logged by the downloads
      } else if (contents) {
        try {
          missions_.LoadMission(waypoints::ParsePlan(*contents, id + ":" + p->offer.name), id + ":" + p->offer.name,
                                v.home, MissionLimits(), now, log_);
        } catch (const std::exception& e) {
          log_.Add(now, id, e.what(), Severity::kWarning);
        }
        it = v.for_editor.erase(it);
      } else {
        ++it;
      }
    }
    missions_.Tick(v, id, v.mavlink.has_value(), now, log_);
    wires_.Tick(v, id, v.reports.Get<PowerLines>().at, now, log_);
  }
  commands_.Tick(now, log_);
  sticks_.Tick(selected_, now);
  if (replay_) TakeOutgoing();  // a replay only watches: whatever the concerns queued goes nowhere
}

GcsOutgoing GcsModel::TakeOutgoing() {
  GcsOutgoing out;
  out.commands = commands_.TakeOutgoing();
  out.mission_chunks = missions_.TakeOutgoing();
  out.missions = missions_.TakeOutgoingWhole();
  out.mission_downloads = missions_.TakeDownloadRequests();
  out.file_requests = maps_.TakeOutgoing();
  out.sticks = sticks_.TakeOutgoing();
  out.targets = video_.TakeOutgoing();
  return out;
}

void GcsModel::OnVideoPixels(const std::string& vehicle_id, const VideoPixels& pixels, double now) {
  VideoTracking::OnVideoPixels(Vehicle(vehicle_id), pixels, now);
}

void GcsModel::OnMavlinkLink(const std::string& vehicle_id, const MavlinkLinkInfo& info, double now) {
  const bool fresh = !vehicles_.count(vehicle_id);
  VehicleModel& v = Vehicle(vehicle_id);
  if (fresh || !v.mavlink)
    log_.Add(now, vehicle_id,
             info.autopilot + " " + info.frame + " (MAVLink system " + std::to_string(info.system_id) + " on " +
                 info.endpoint + (info.signing ? ", signed" : ", unsigned") + ")",
             Severity::kInfo);
  v.mavlink = info;
}

void GcsModel::OnMissionDownloaded(const std::string& vehicle_id, const waypoints::Mission& mission, bool for_editor,
                                   double now) {
  VehicleModel& v = Vehicle(vehicle_id);
  v.mission = mission;
  if (!for_editor) return;
  if (mission.items.empty()) {
    log_.Add(now, vehicle_id, "the vehicle holds no mission: the editor is left as it is", Severity::kWarning);
    return;
  }
  missions_.LoadMission(mission, vehicle_id + ":mission", v.home, MissionLimits(), now, log_);
}

void GcsModel::OnLinkNote(const std::string& source, const std::string& text, Severity severity, double now) {
  log_.Add(now, source, text, severity);
}

}  // namespace uav::gcs
