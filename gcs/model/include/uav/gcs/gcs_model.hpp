#pragma once
// Everything the operator sees and does, as plain data and actions: a small facade over the
// concerns (telemetry.hpp, commands.hpp, plots.hpp, video_tracking.hpp, maps_downloads.hpp,
// mission_uploads.hpp, message_log.hpp). The link (or a replayed log) feeds it decoded messages;
// panels read it and call its actions. No ImGui, no LCM in here.
#include <map>
#include <string>

#include "uav/gcs/state_alarms.hpp"
#include "uav/gcs/commands.hpp"
#include "uav/gcs/basemap.hpp"
#include "uav/gcs/maps_downloads.hpp"
#include "uav/gcs/message_log.hpp"
#include "uav/gcs/mission_uploads.hpp"
#include "uav/gcs/stick_input.hpp"
#include "uav/gcs/obstacle_reports.hpp"
#include "uav/gcs/plots.hpp"
#include "uav/gcs/power_line_warnings.hpp"
#include "uav/gcs/telemetry.hpp"
#include "uav/gcs/video_tracking.hpp"

namespace uav::gcs {

// One vehicle as the GCS knows it: each concern's per-vehicle part.
struct VehicleModel : VehicleTelemetry, VehicleVideo, VehicleMaps, VehicleMission, VehiclePowerLines, VehicleObstacles {
  std::string id;
  StateAlarms state_alarms;  // an absurd state said once
  // The depth-from-motion grid drawn over `feed` (the live video or a frozen frame): fresh, and
  // computed on that feed's camera.
  const DepthGrid* DepthGridOver(const VideoFeed& feed, double now, const ObstacleReportParams& p) const {
    const DepthGrid* g = reports.Fresh<DepthGrid>(now, p.stale_after_s);
    return g && g->camera == feed.camera ? g : nullptr;
  }
  // The active stereo dots drawn over `feed`: fresh, and found in that feed's camera.
  const ActiveStereoReport* ActiveStereoOver(const VideoFeed& feed, double now, const ObstacleReportParams& p) const {
    const ActiveStereoReport* r = reports.Fresh<ActiveStereoReport>(now, p.stale_after_s);
    return r && r->camera == feed.camera ? r : nullptr;
  }
};

// The editor's row that `v` is flying, given the editor's mission as made (`made`); -1 when none,
// or when `v` holds another mission.
int FlownRow(const VehicleModel* v, const EditorCheck& made);

// Everything the concerns queued for the links to send, taken at once: each link takes the
// entries of the vehicles it serves (a MAVLink vehicle's go to the MAVLink link), the bus the rest.
struct GcsOutgoing {
  std::vector<OutgoingCommand> commands;
  std::vector<OutgoingMissionChunk> mission_chunks;
  std::vector<OutgoingMission> missions;           // whole, for links with their own transfer
  std::vector<std::string> mission_downloads;      // vehicles asked for the mission they hold
  std::vector<OutgoingFileRequest> file_requests;
  std::vector<std::pair<std::string, ManualSticks>> sticks;
  std::vector<TrackTarget> targets;
};

class GcsModel {
 public:
  GcsModel(std::string gcs_name, int64_t first_command_seq) : commands_(std::move(gcs_name), first_command_seq) {}

  // ---- Inputs from the link, decoded once (time `now` is the GCS clock in seconds).
  void OnHeartbeat(const std::string& vehicle_id, int64_t seq, const HeartbeatInfo& hb, double now);
  void OnState(const std::string& vehicle_id, int64_t seq, const VehicleState& state, double now);
  void OnAck(const std::string& vehicle_id, const CommandAck& ack, double now);
  void OnStatusText(const std::string& vehicle_id, Severity severity, const std::string& text, double now);
  void OnMissionAck(const std::string& vehicle_id, const std::string& source, const waypoints::MissionUploadAck& ack,
                    double now);
  void OnVideoFrame(const std::string& vehicle_id, const VideoFrame& frame, double now);
  void OnFileOffer(const std::string& vehicle_id, const FileOffer& offer, double now);
  void OnFileChunk(const std::string& vehicle_id, const FileChunk& chunk, double now);
  void OnMapTile(const std::string& vehicle_id, const MapTile& tile, double now);
  // A decoded picture (RTP/H.264 video of a MAVLink vehicle), RGBA.
  void OnVideoPixels(const std::string& vehicle_id, const VideoPixels& pixels, double now);
  // A MAVLink vehicle's identity and link (it is a MAVLink vehicle from then on: whole-mission
  // uploads, its own parameter names).
  void OnMavlinkLink(const std::string& vehicle_id, const MavlinkLinkInfo& info, double now);
  // The mission a vehicle holds, downloaded by its link: drawn on the map, and loaded into the
  // editor when the operator asked for it (`for_editor`).
  void OnMissionDownloaded(const std::string& vehicle_id, const waypoints::Mission& mission, bool for_editor, double now);
  // What a link says of itself or of frames it refused, before any vehicle is known by them.
  void OnLinkNote(const std::string& source, const std::string& text, Severity severity, double now);
  // `seq`: the message's header.seq (telemetry counts receipts by it).
  void OnTrackStatus(const std::string& vehicle_id, int64_t seq, const TrackStatus& status, double now);
  // Any vehicle report (uav/shared/reports.hpp): kept as the vehicle's newest of its type
  // (VehicleTelemetry::reports, what panels and overlays draw), its signals sampled, and acted
  // on by the concerns that act on it (warnings, the obstacle map, messages).
  template <class T>
  void OnReport(const std::string& vehicle_id, T report, double now) {
    VehicleModel& v = Vehicle(vehicle_id);
    React(v, vehicle_id, report, now);
    OnReportTelemetry(v, std::move(report), now);
  }

  // ---- Operator actions on the selected vehicle (false: error() of the concern says why).
  void SelectVehicle(const std::string& id);
  bool SubmitCommand(const std::string& text, double now);
  bool FreezeVideo(bool freeze);
  // The selected vehicle's video shows `camera` (one it streams); false otherwise.
  bool ChooseVideoCamera(const std::string& camera);
  bool SelectTarget(const TrackTarget& target, double now);
  bool UploadMission(double now);
  bool ExportMission(const std::string& path, double now);
  bool ImportMission(const std::string& path, double now);
  // The survey planner's speed and turn radius from the selected vehicle's parameters: a
  // tail-sitter's cruise speed and the radius of its turns at ts_bank_max; a multicopter turns on
  // the spot (radius 0) and keeps the planned speed up to ctl_speed_max_xy. False (logged) without
  // a parameter table from the vehicle.
  bool FitSurveyToVehicle(double now);
  // What the selected vehicle allows a mission (its speed, ceiling and range) from its parameter
  // table; the vehicle schema's defaults until a table has come (*from_vehicle false then).
  waypoints::VehicleLimits MissionLimits(bool* from_vehicle = nullptr) const;
  // The mission editor's row the selected vehicle is flying now; -1 when none, or when the
  // vehicle holds another mission than the editor's.
  int FlownMissionRow() const;  // FlownRow(selected(), the editor's mission)
  bool StartDownload(const std::string& dir, double now);
  // Fetches the mission the selected vehicle holds (the newest it offers, mission_N.plan) and
  // loads it into the mission editor when it has arrived, verified. False (logged) when there is
  // no vehicle or it has offered no mission.
  bool DownloadMission(double now);
  // Parameters of the selected vehicle (its newest ParameterTable): a typed value checked against
  // the table and sent as a signed `param NAME VALUE` command; the table saved to a file (ours or
  // QGroundControl's .params); a file loaded: the values that differ and may change now are sent,
  // the rest are logged with why not. False (and why in the log) when nothing could be done.
  bool SetParameter(const std::string& name, const std::string& text, double now);
  bool SaveParameters(const std::string& path, ParameterFileFormat format, double now);
  bool LoadParameters(const std::string& path, double now);
  bool ExportPlotCsv(const std::string& path, double t0, double t1, double now);
  // A GeoTIFF under the map (basemap.hpp); the reason in the log when it cannot be shown.
  // Without a vehicle's home, the map's origin moves to the basemap's centre (planning over it).
  bool LoadBasemap(const std::string& path, double now);
  void ClearBasemap() { basemap_.Clear(); }
  const Basemap& basemap() const { return basemap_; }
  // Replay: nothing is sent on any bus; commands are refused saying so; every GCS's
  // acknowledgements go to the messages, naming the GCS they answered.
  void SetReplay(bool replay);
  bool replay() const { return replay_; }
  // The id of this GCS's signing key (SigningKey::Id); empty: it sends unsigned (--insecure).
  void SetSigningKeyId(std::string id) { signing_key_id_ = std::move(id); }
  const std::string& signing_key_id() const { return signing_key_id_; }

  // ---- Periodic: resends, uploads, download requests and saves.
  void Tick(double now);
  // What the concerns queued since the last call, for the links.
  GcsOutgoing TakeOutgoing();

  // ---- The concerns.
  PlotSet& plots() { return plots_; }
  const PlotSet& plots() const { return plots_; }
  CommandCenter& commands() { return commands_; }
  const CommandCenter& commands() const { return commands_; }
  StickInput& sticks() { return sticks_; }
  const StickInput& sticks() const { return sticks_; }
  VideoTracking& video() { return video_; }
  const VideoTracking& video() const { return video_; }
  MapsDownloads& maps() { return maps_; }
  const MapsDownloads& maps() const { return maps_; }
  MissionUploads& missions() { return missions_; }
  const MissionUploads& missions() const { return missions_; }
  const MessageLog& log() const { return log_; }
  WireWarnings& wires() { return wires_; }
  const WireWarnings& wires() const { return wires_; }
  const ObstacleReports& obstacles() const { return obstacles_; }

  // ---- Vehicles.
  const std::map<std::string, VehicleModel>& vehicles() const { return vehicles_; }
  const VehicleModel* selected() const;
  const std::string& selected_id() const { return selected_; }
  const std::string& gcs_name() const { return commands_.gcs_name(); }
  TelemetryParams& telemetry_params() { return telemetry_params_; }
  const TelemetryParams& telemetry_params() const { return telemetry_params_; }

 private:
  VehicleModel& Vehicle(const std::string& id);
  VehicleModel* Selected();
  // The reports a concern acts on; any other is only kept.
  template <class T>
  void React(VehicleModel&, const std::string&, const T&, double) {}
  void React(VehicleModel& v, const std::string& vehicle_id, const PowerLines& lines, double now);
  void React(VehicleModel& v, const std::string& vehicle_id, const Obstacles& obstacles, double now);
  void React(VehicleModel& v, const std::string& vehicle_id, const DepthGrid& grid, double now);
  void React(VehicleModel& v, const std::string& vehicle_id, const ActiveStereoReport& report, double now);
  void React(VehicleModel& v, const std::string& vehicle_id, const VisualOdometryReport& report, double now);

  std::map<std::string, VehicleModel> vehicles_;
  std::string selected_;
  bool replay_ = false;
  std::string signing_key_id_;
  TelemetryParams telemetry_params_;
  MessageLog log_;
  CommandCenter commands_;
  PlotSet plots_;
  VideoTracking video_;
  StickInput sticks_;
  MapsDownloads maps_;
  Basemap basemap_;
  MissionUploads missions_;
  WireWarnings wires_;
  ObstacleReports obstacles_;
};

}  // namespace uav::gcs
