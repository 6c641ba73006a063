#pragma once
// Everything the operator sees and does, as plain data and actions. Panels read it and call its
// actions; the link feeds it messages as plain structs. No ImGui, no LCM in here.
#include <array>
#include <cmath>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "uav/gcs/signal_series.hpp"
#include "uav/shared/file_transfer.hpp"
#include "uav/gcs/survey_planner.hpp"
#include "uav/waypoints/mission_transfer.hpp"

namespace uav::gcs {

// One telemetry message flattened to named signals (group = message name, e.g. "STATE").
struct TelemetrySample {
  std::string vehicle_id;
  std::string group;
  int64_t seq = 0;
  double t = 0.0;  // [s] vehicle clock
  std::vector<std::pair<std::string, double>> values;
};

struct AckInfo {
  int64_t command_seq = 0;
  std::string command;
  std::string result;   // accepted, rejected, in_progress, completed, failed
  int percent = 0;
  std::string reason;
};

struct SentCommand {
  int64_t command_seq = 0;
  std::string vehicle_id;
  std::string text;
  double first_sent = 0.0;  // [s] GCS monotonic clock
  double last_sent = 0.0;
  int tries = 0;
  bool acknowledged = false;
  bool gave_up = false;
  std::optional<AckInfo> last_ack;
};

struct LogLine {
  double t;  // GCS clock
  std::string vehicle_id;
  std::string text;
  int severity;  // 3 error, 4 warning, 6 info
};

// A JPEG preview frame as received (issue 4 item 6; the video panel of issue 6).
struct VideoFrameIn {
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;
  int source_width = 0, source_height = 0;
  std::vector<uint8_t> jpeg;
};

// The newest decoded frame of a vehicle's camera stream.
struct VideoFeed {
  int64_t frames = 0;    // accepted frames; panels redraw when it changes
  int64_t rejected = 0;  // frames that were not a decodable JPEG of the stated size
  std::deque<double> recent;  // receive times within the last second
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;
  int source_width = 0, source_height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4
  double Rate(double now) const;
};

// A live-map tile as received (map_tile_t).
struct MapTileIn {
  int map_id = 0, tile_x = 0, tile_y = 0, tile_px = 0;
  double gsd_m = 0, origin_north_m = 0, origin_east_m = 0;
  bool georeferenced = false;
  std::vector<uint8_t> jpeg;
};

// The map a vehicle is stitching, as far as its tiles have arrived (the newest map only).
struct LiveMap {
  int map_id = 0;
  int tile_px = 0;
  double gsd_m = 0, origin_north_m = 0, origin_east_m = 0;
  bool georeferenced = false;
  struct Tile {
    std::vector<uint8_t> rgba;  // tile_px^2 * 4, alpha 0 where unmapped
    int64_t version = 0;        // increases with every update (panels re-upload then)
  };
  std::map<std::pair<int, int>, Tile> tiles;  // (tile_x, tile_y)
  int64_t received = 0;
  int64_t rejected = 0;
};

// Receipts of one message type (a group of the telemetry tree): rate and age.
struct SignalGroup {
  double last_receipt = -1.0;  // GCS clock
  std::deque<double> recent;   // receipt times within the last second
  int64_t received = 0;
  double Rate(double now) const;
  double Age(double now) const { return last_receipt < 0 ? 1e9 : now - last_receipt; }
};

// What the vehicle's tracker reports (track_status_t), image coordinates normalised to 0..1.
struct TrackStatus {
  enum State { kIdle = 0, kTracking = 1, kLost = 2 };
  int64_t utime = 0;  // vehicle clock of the frame
  int64_t seq = 0;    // message counter (header.seq)
  int64_t target_seq = 0;
  State state = kIdle;
  double center_x = 0, center_y = 0, width = 0, height = 0, angle_rad = 0;
  double received = -1.0;  // GCS clock
};

// A target picked on a frozen video frame (video panel), normalised image coordinates.
struct TrackTarget {
  enum Method { kDrag = 0, kFourClicks = 1, kCancel = 2 };
  int64_t frame_utime = 0;
  std::string camera;
  Method method = kDrag;
  double x = 0, y = 0, width = 0, height = 0;  // axis-aligned rectangle, top-left and size
  std::array<std::array<double, 2>, 4> corners{};  // clicked corners (x, y) in click order
};

struct OutgoingTrackTarget {
  std::string vehicle_id;
  int64_t target_seq = 0;
  TrackTarget target;
};

// One plot panel: its signals, each on the left or right y axis, and each axis's range.
enum class PlotAxis { kLeft = 0, kRight = 1 };
struct PlotSpec {
  std::map<std::string, PlotAxis> signals;  // "GROUP.signal"
  bool auto_y[2] = {true, true};
  double y_min[2] = {-10, -10}, y_max[2] = {10, 10};
};

struct VehicleModel {
  std::string id;
  // Link quality, measured on the GCS's monotonic clock.
  double last_heartbeat = -1.0;
  double last_message = -1.0;
  int64_t messages_total = 0;
  int64_t sequence_gaps = 0;                 // messages missed, from header.seq jumps
  std::map<std::string, int64_t> last_seq;   // per group
  std::deque<double> recent_receipts;        // receive times within the last second
  // Latest values and histories, by "GROUP.signal".
  std::map<std::string, double> latest;
  std::vector<std::string> signal_order;     // keys in the order the vehicle sends them (Table 2.3)
  std::map<std::string, SignalSeries> history;
  std::map<std::string, SignalGroup> groups;  // by message (group) name
  double first_t = -1.0;                     // vehicle time of the first sample (plot origin)
  std::string task = "unknown";
  bool armed = false;
  std::optional<GeodeticPoint> home;         // origin of the vehicle's x, y, z
  // Mission uploads to this vehicle: the one in progress (or last finished) and the last
  // mission it accepted, which the map draws.
  std::optional<waypoints::MissionUploader> upload;
  std::optional<waypoints::Mission> mission;
  VideoFeed video;
  // Files the vehicle offers (finished maps) and their downloads; saved: id -> path written.
  FileReceiver files;
  std::map<int64_t, std::string> saved;
  LiveMap live_map;
  // Target tracking: the last selection sent to this vehicle and what its tracker reports.
  std::optional<TrackTarget> track_target;
  int64_t track_targets_sent = 0;
  std::optional<TrackStatus> track;

  double HeartbeatAge(double now) const { return last_heartbeat < 0 ? 1e9 : now - last_heartbeat; }
  double MessageRate(double now) const;
  bool LinkUp(double now) const { return HeartbeatAge(now) < 3.0; }
};

struct OutgoingMissionChunk {
  std::string vehicle_id;
  waypoints::MissionChunk chunk;
};

struct OutgoingFileRequest {
  std::string vehicle_id;
  FileRequest request;
};

// An outgoing message the link must send (commands; heartbeats are the link's own business).
struct OutgoingCommand {
  std::string vehicle_id;
  int64_t command_seq;
  std::string text;
};

class GcsModel {
 public:
  // Commands are identified by (gcs_name, command_seq) on the vehicle, so a restarted GCS must
  // not reuse numbers: start from something that grows across runs (wall-clock microseconds).
  GcsModel(std::string gcs_name, int64_t first_command_seq)
      : gcs_name_(std::move(gcs_name)), planner_(UAV_CAMERA_DIR, kDefaultMapOrigin), next_seq_(first_command_seq) {}

  // Map origin until a vehicle reports its home: the simulator's default home (NUS, Singapore).
  static constexpr GeodeticPoint kDefaultMapOrigin{1.2966, 103.7764, 15.0};

  // ---- Inputs from the link (time `now` is the GCS monotonic clock in seconds).
  void OnHeartbeat(const std::string& vehicle_id, int64_t seq, int task, bool armed, double now);
  void OnTelemetry(const TelemetrySample& s, double now);
  void OnAck(const std::string& vehicle_id, const std::string& source, const AckInfo& ack, double now);
  void OnStatusText(const std::string& vehicle_id, int severity, const std::string& text, double now);
  void OnMissionAck(const std::string& vehicle_id, const std::string& source,
                    const waypoints::MissionUploadAck& ack, double now);
  // Decodes the JPEG; a frame that does not decode to its stated size is counted as rejected
  // (the first one is logged with the reason) and the previous frame stays on screen.
  void OnVideoFrame(const std::string& vehicle_id, const VideoFrameIn& frame, double now);
  // Download protocol (uav::FileReceiver). An invalid offer is logged with the reason.
  void OnFileOffer(const std::string& vehicle_id, const FileOffer& offer, double now);
  void OnFileChunk(const std::string& vehicle_id, const FileChunk& chunk, double now);
  // Decodes the tile; a tile of a newer map replaces the whole live map. A tile that does not
  // decode to tile_px x tile_px is counted as rejected (the first one logged).
  void OnMapTile(const std::string& vehicle_id, const MapTileIn& tile, double now);
  // A status that is not finite, names an unknown state or lies far outside the image is
  // counted in the log and dropped. Also feeds the TRACK group of the telemetry tree.
  void OnTrackStatus(const std::string& vehicle_id, const TrackStatus& status, double now);

  // ---- Operator actions.
  // Validates with the shared grammar; on success queues the command for the selected vehicle.
  // Returns false and sets command_error() when the text is invalid or no vehicle is selected.
  bool SubmitCommand(const std::string& text, double now);
  void SelectVehicle(const std::string& id);
  // Plot panels: there is always at least one; ticking puts a signal on the active one.
  int AddPlot();                 // a new, empty, active plot; returns its index
  void RemovePlot(int index);    // the last one stays
  void SetActivePlot(int index);
  void TogglePlotSignal(const std::string& key);  // "GROUP.signal", on the active plot, left axis
  void TogglePlotSignal(int plot, const std::string& key, PlotAxis axis);
  void SetSignalAxis(int plot, const std::string& key, PlotAxis axis);
  // Fixed range of one axis (auto off); refused unless finite with lo < hi.
  bool SetPlotRange(int plot, PlotAxis axis, bool auto_y, double lo, double hi);
  void SetPlotWindow(double seconds);
  // The shared time axis of all plots: following the newest sample, or held at `t_end` (plot
  // time, seconds since the vehicle's first sample) by pause or by panning.
  void HoldPlotTime(double t_end) { if (std::isfinite(t_end)) plot_hold_ = t_end; }
  void FollowPlotTime() { plot_hold_.reset(); }
  const std::optional<double>& plot_hold() const { return plot_hold_; }
  // Freezes the selected vehicle's video on its current frame (target selection picks on it),
  // or goes back to live. Returns false when there is no frame to freeze.
  bool FreezeVideo(bool freeze);
  // The frozen frame, while frozen (of the vehicle that was selected then).
  const std::optional<VideoFeed>& frozen_video() const { return frozen_video_; }
  const std::string& frozen_vehicle() const { return frozen_vehicle_; }
  // Sends the target picked in the video panel to the selected vehicle. Returns false and sets
  // track_error() when no vehicle is selected, or a coordinate is not finite or outside 0..1,
  // or the rectangle is smaller than 0.5 % of the image side.
  bool SelectTarget(const TrackTarget& target, double now);
  // Writes the ticked signals (all plots) of the selected vehicle over [t0, t1] (plot time, seconds since
  // its first sample) as CSV: a column t, then one per signal, a row per sample time (empty
  // where a signal has no sample then). Written to a temporary name and renamed; the outcome
  // goes to the log. Returns false when there is nothing to write or the file cannot be written.
  bool ExportPlotCsv(const std::string& path, double t0, double t1, double now);
  // Uploads the planner's survey mission to the selected vehicle. Returns false and sets
  // upload_error() when there is no vehicle, no valid plan, or an upload is already running.
  bool UploadSurvey(double now);
  SurveyPlanner& planner() { return planner_; }
  // File actions of the planner; the outcome goes to the log.
  bool ExportSurvey(const std::string& path, double now);
  bool ImportSurvey(const std::string& path, double now);
  // Downloads every file the selected vehicle offers into `dir` (created if missing); each is
  // saved under its own name, through a temporary name, once its SHA-256 matched. Returns false
  // and sets download_error() when no vehicle is selected or the directory cannot be made.
  bool StartDownload(const std::string& dir, double now);
  // From now on every file any vehicle offers is downloaded into `dir` as soon as it is offered
  // (uav-gcs --download-dir); StartDownload sets the same directory.
  void SetDownloadDir(const std::string& dir) { download_dir_ = dir; }

  // ---- Periodic: resends unacknowledged commands, gives up after kMaxTries.
  void Tick(double now);
  std::vector<OutgoingCommand> TakeOutgoing();
  std::vector<OutgoingMissionChunk> TakeOutgoingChunks();
  std::vector<OutgoingFileRequest> TakeOutgoingFileRequests();
  std::vector<OutgoingTrackTarget> TakeOutgoingTrackTargets();

  // ---- Views.
  const std::string& gcs_name() const { return gcs_name_; }
  const std::map<std::string, VehicleModel>& vehicles() const { return vehicles_; }
  const VehicleModel* selected() const;
  const std::string& selected_id() const { return selected_; }
  std::set<std::string> plot_signals() const;  // ticked on any plot
  const std::vector<PlotSpec>& plots() const { return plots_; }
  int active_plot() const { return active_plot_; }
  const std::string& track_error() const { return track_error_; }
  double plot_window() const { return plot_window_; }
  const std::string& command_error() const { return command_error_; }
  const std::vector<std::string>& command_history() const { return history_; }
  const std::deque<SentCommand>& sent_commands() const { return sent_; }
  const std::deque<LogLine>& log() const { return log_; }
  const SurveyPlanner& planner() const { return planner_; }
  const std::string& upload_error() const { return upload_error_; }
  const std::string& download_error() const { return download_error_; }
  const std::string& download_dir() const { return download_dir_; }

  static constexpr double kResendTimeout = 1.0;  // [s] without any acknowledgement
  static constexpr int kMaxTries = 5;

 private:
  VehicleModel& Vehicle(const std::string& id);
  void StartDownloads(VehicleModel& v, double now);
  void Log(double now, const std::string& vehicle, const std::string& text, int severity);

  std::string gcs_name_;
  std::map<std::string, VehicleModel> vehicles_;
  std::string selected_;
  std::vector<PlotSpec> plots_ = std::vector<PlotSpec>(1);
  int active_plot_ = 0;
  std::vector<OutgoingTrackTarget> outgoing_track_;
  std::string track_error_;
  int64_t next_target_seq_ = 1;
  std::optional<double> plot_hold_;
  std::optional<VideoFeed> frozen_video_;
  std::string frozen_vehicle_;
  double plot_window_ = 60.0;
  std::string command_error_;
  std::vector<std::string> history_;
  std::deque<SentCommand> sent_;
  std::vector<OutgoingCommand> outgoing_;
  std::deque<LogLine> log_;
  SurveyPlanner planner_;
  std::vector<OutgoingMissionChunk> outgoing_chunks_;
  std::string upload_error_;
  std::vector<OutgoingFileRequest> outgoing_file_requests_;
  std::string download_error_;
  std::string download_dir_;  // where downloads are saved; empty: none started yet
  int64_t next_seq_;
};

}  // namespace uav::gcs
