#pragma once
// Data shared by the onboard threads. Each field has one writer thread (named); readers take a
// copy under the lock. Stage ordering in the scheduler makes the hand-over deterministic.
#include <array>
#include <deque>
#include <map>
#include <memory>
#include <tuple>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "uav/avoid/avoidance.hpp"
#include "uav/hal/navigation_estimate.hpp"
#include "uav/control/mixer.hpp"
#include "uav/control/task_manager.hpp"
#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/active_stereo.hpp"
#include "uav/shared/mono_depth.hpp"
#include "uav/shared/obstacles.hpp"
#include "uav/shared/power_lines.hpp"
#include "uav/shared/sensing.hpp"
#include "uav/shared/tracking.hpp"
#include "uav/shared/visual_odometry.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::app {

struct StatusText {
  Severity severity;
  std::string text;
};

// A compressed camera preview for the GCS video panel (issue 4 item 6).
struct PreviewFrame {
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;                // of the JPEG
  int source_width = 0, source_height = 0;  // of the camera image
  std::vector<uint8_t> jpeg;
};

// A survey capture handed from CAM to STITCH: the image and where the flight stack thought the
// camera was (the estimate, never the simulator's truth).
struct SurveyCapture {
  int64_t utime = 0;
  int width = 0, height = 0;
  std::vector<uint8_t> bgr;  // width * height * 3, row-major (OpenCV stays out of this header)
  Eigen::Isometry3d T_NC_estimate = Eigen::Isometry3d::Identity();
};

// A camera's newest frame for a thread that processes another thread's camera (MDEPTH), with
// where the estimate put the camera when it was exposed (nullopt: no navigation sample then).
struct SharedFrame {
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;
  std::vector<uint8_t> bgr;  // width * height * 3, row-major
  std::optional<Eigen::Isometry3d> T_NC_estimate;
  std::optional<Eigen::Vector3d> v_N_estimate;  // [m/s] the vehicle's estimated velocity then
};

// A live-map tile from STITCH for CMM (JPEG, unmapped pixels black).
struct LiveTile {
  int map_id = 0, tx = 0, ty = 0, tile_px = 0;
  double gsd_m = 0, origin_north_m = 0, origin_east_m = 0;
  bool georeferenced = false;
  std::vector<uint8_t> jpeg;
};

struct BlackboardData {
  // IMU thread
  hal::SensorSample sample;
  hal::VehicleEstimate estimate;
  // CTL thread
  control::ServoCommand servo;
  bool armed = false;
  bool airborne = false;
  control::Task task = control::Task::kIdle;
  int mission_item = -1;
  control::FailsafeAction failsafe = control::FailsafeAction::kNone;
  double fence_radius_m = 0.0, fence_alt_m = 0.0;  // the geofence it enforces
  int chirp_channel = 0;  // servo channel a chirp is exciting (control::ServoChannel), 0: none
  bool sim_gps_enabled = true;  // simulator fault: the simulated GPS has a fix (main applies it)
  // CMM thread
  double gcs_link_age_s = -1.0;  // [s] wall clock since the last GCS heartbeat; < 0: none heard yet
  std::optional<double> capture_interval_s;  // survey camera on, by time ...
  std::optional<double> capture_distance_m;  // ... or by distance
  // SVO thread
  std::array<double, 4> rotor_inputs = {-1, -1, -1, -1};
  // STEREO thread: nearest obstacle in the forward corridor [m]; < 0: none seen or no stereo pair
  double obstacle_range_m = -1.0;
  // STEREO thread: nearest ranged power line [m] from the body origin; < 0: none
  double nearest_wire_m = -1.0;
  // STEREO thread: obstacle cylinders in view, nearest surface [m] horizontally; < 0: none
  int obstacle_count = 0;
  double nearest_obstacle_m = -1.0;
  // TRK thread: the camera it tracks in ("" when the vehicle has none) and the tracked target on
  // the ground, for follow.
  std::string tracking_camera;
  // MDEPTH thread: the camera whose frames it wants shared ("" none).
  std::string depth_camera;
  // ASTEREO (the STEREO thread with the dot projector): the newest height over the ground for
  // the INS, when active stereo feeds it; the IMU thread applies each one once (by utime).
  struct VisionHeight {
    int64_t utime = 0;
    double height_m = 0.0, sigma_m = 0.0;
  };
  std::optional<VisionHeight> vision_height;
  // VO (the STEREO thread as visual odometry): the newest body position in its segment's frame
  // tied to N, for the INS and the VO+IMU filter (the IMU thread applies each once, by utime).
  struct VisionPosition {
    int64_t utime = 0;
    Eigen::Vector3d p_N = Eigen::Vector3d::Zero();
    double sigma_m = 0.0;
    int segment = 0;
  };
  std::optional<VisionPosition> vision_position;
  std::string vision_unhealthy_reason;  // the odometry's last refusal ("" while it is healthy)
  // IMU thread: where the INS takes its position from, and the VO+IMU filter's track.
  PositionSource position_source = PositionSource::kGps;
  std::optional<Eigen::Vector3d> vo_track_N;
  TrackedTarget target;
  // The clock's thread (Sensing::Monitor): the vision workers' rates, latencies and drops.
  SensingReport sensing;
  // CTL -> AVD: where the active task is taking the vehicle (obstacle avoidance plans to it).
  struct AvoidRequest {
    bool active = false;
    Eigen::Vector3d goal_N = Eigen::Vector3d::Zero();  // the task's goal (leg end)
    Eigen::Vector3d via_N = Eigen::Vector3d::Zero();   // the task's own setpoint now
  };
  AvoidRequest avoid_request;
  // AVD: its newest plan (null before the first).
  std::shared_ptr<const avoid::AvoidancePlan> avoid_plan;
  // CTL: what the safety layer is doing, why, and the speed the seen space allows [m/s].
  avoid::AvoidState avoid_state = avoid::AvoidState::kOff;
  std::string avoid_reason;
  double avoid_speed_limit = -1.0;
  // The simulator's truth (main writes it each physics step; never read by the flight stack):
  // distance from the body centre to the nearest true surface other than the ground [m], < 0
  // when the world has none.
  double sim_clearance_m = -1.0;
};

class Blackboard {
 public:
  BlackboardData Snapshot() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return data_;
  }
  template <class F>
  void Update(F&& f) {
    std::lock_guard<std::mutex> lock(mutex_);
    f(data_);
  }

  // CMM -> CTL: validated commands.
  void PushCommand(const control::CommandRequest& r) {
    std::lock_guard<std::mutex> lock(mutex_);
    commands_.push_back(r);
  }
  std::vector<control::CommandRequest> TakeCommands() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<control::CommandRequest> out(commands_.begin(), commands_.end());
    commands_.clear();
    return out;
  }
  // CTL -> CMM: acknowledgements and status texts.
  void PushReports(const std::vector<control::TaskReport>& r) {
    std::lock_guard<std::mutex> lock(mutex_);
    reports_.insert(reports_.end(), r.begin(), r.end());
  }
  std::vector<control::TaskReport> TakeReports() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<control::TaskReport> out(reports_.begin(), reports_.end());
    reports_.clear();
    return out;
  }
  void PushStatus(Severity severity, std::string text) {
    std::lock_guard<std::mutex> lock(mutex_);
    status_.push_back({severity, std::move(text)});
  }
  // Camera threads -> CMM: per camera, the newest preview replaces one not yet sent (video is
  // live, not queued).
  void PutPreview(PreviewFrame f) {
    std::lock_guard<std::mutex> lock(mutex_);
    previews_[f.camera] = std::move(f);
  }
  std::vector<PreviewFrame> TakePreviews() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<PreviewFrame> out;
    for (auto& [camera, f] : previews_) out.push_back(std::move(f));
    previews_.clear();
    return out;
  }
  // CMM -> TRK: targets the operator picked (or cancelled), in order.
  void PushTrackRequest(TrackRequest r) {
    std::lock_guard<std::mutex> lock(mutex_);
    track_requests_.push_back(std::move(r));
  }
  std::vector<TrackRequest> TakeTrackRequests() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<TrackRequest> out(std::make_move_iterator(track_requests_.begin()), std::make_move_iterator(track_requests_.end()));
    track_requests_.clear();
    return out;
  }
  // TRK (and CMM, for targets refused at the edge) -> CMM: every report, in order (a rejection
  // must not be overwritten by the next frame's status).
  void PushTrackReport(TrackReport r) {
    std::lock_guard<std::mutex> lock(mutex_);
    track_reports_.push_back(std::move(r));
  }
  std::vector<TrackReport> TakeTrackReports() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<TrackReport> out(std::make_move_iterator(track_reports_.begin()), std::make_move_iterator(track_reports_.end()));
    track_reports_.clear();
    return out;
  }
  // STEREO -> CMM: the newest pair's power lines replace ones not yet sent.
  void PutPowerLines(PowerLines r) {
    std::lock_guard<std::mutex> lock(mutex_);
    power_lines_ = std::move(r);
  }
  std::optional<PowerLines> TakePowerLines() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<PowerLines> out = std::move(power_lines_);
    power_lines_.reset();
    return out;
  }
  // STEREO -> CMM: the newest pair's obstacles and the newest decimated cloud replace ones not
  // yet sent.
  void PutObstacles(Obstacles o) {
    std::lock_guard<std::mutex> lock(mutex_);
    obstacles_ = std::move(o);
  }
  std::optional<Obstacles> TakeObstacles() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<Obstacles> out = std::move(obstacles_);
    obstacles_.reset();
    return out;
  }
  void PutPointCloud(PointCloud c) {
    std::lock_guard<std::mutex> lock(mutex_);
    point_cloud_ = std::move(c);
  }
  std::optional<PointCloud> TakePointCloud() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<PointCloud> out = std::move(point_cloud_);
    point_cloud_.reset();
    return out;
  }
  // CAM or TRK -> MDEPTH: the newest frame of the camera MDEPTH wants.
  void PutFrame(SharedFrame f) {
    std::lock_guard<std::mutex> lock(mutex_);
    frame_ = std::move(f);
  }
  std::optional<SharedFrame> TakeFrame() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<SharedFrame> out = std::move(frame_);
    frame_.reset();
    return out;
  }
  // MDEPTH -> CMM: the newest depth grid replaces one not yet sent.
  void PutDepthGrid(DepthGrid g) {
    std::lock_guard<std::mutex> lock(mutex_);
    depth_grid_ = std::move(g);
  }
  std::optional<DepthGrid> TakeDepthGrid() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<DepthGrid> out = std::move(depth_grid_);
    depth_grid_.reset();
    return out;
  }
  // ASTEREO -> CMM: the newest active stereo report replaces one not yet sent.
  void PutActiveStereo(ActiveStereoReport r) {
    std::lock_guard<std::mutex> lock(mutex_);
    active_stereo_ = std::move(r);
  }
  std::optional<ActiveStereoReport> TakeActiveStereo() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<ActiveStereoReport> out = std::move(active_stereo_);
    active_stereo_.reset();
    return out;
  }
  // VO -> CMM: the newest report replaces one not yet sent.
  void PutVisualOdometry(VisualOdometryReport r) {
    std::lock_guard<std::mutex> lock(mutex_);
    visual_odometry_ = std::move(r);
  }
  std::optional<VisualOdometryReport> TakeVisualOdometry() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::optional<VisualOdometryReport> out = std::move(visual_odometry_);
    visual_odometry_.reset();
    return out;
  }
  // CAM -> STITCH: every capture, in order (a survey frame is never dropped).
  void PushCapture(SurveyCapture c) {
    std::lock_guard<std::mutex> lock(mutex_);
    captures_.push_back(std::move(c));
  }
  std::vector<SurveyCapture> TakeCaptures() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<SurveyCapture> out(std::make_move_iterator(captures_.begin()), std::make_move_iterator(captures_.end()));
    captures_.clear();
    return out;
  }
  // STITCH -> CMM: finished files to offer for download (name, contents).
  void PushDownload(std::string name, std::string contents) {
    std::lock_guard<std::mutex> lock(mutex_);
    downloads_.emplace_back(std::move(name), std::move(contents));
  }
  std::vector<std::pair<std::string, std::string>> TakeDownloads() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<std::pair<std::string, std::string>> out(std::make_move_iterator(downloads_.begin()),
                                                         std::make_move_iterator(downloads_.end()));
    downloads_.clear();
    return out;
  }
  // STITCH -> CMM: the newest content of each changed tile replaces the one still waiting; CMM
  // takes them oldest-waiting first at its own (bounded) rate.
  void PutTile(LiveTile t) {
    std::lock_guard<std::mutex> lock(mutex_);
    const std::tuple<int, int, int> key(t.map_id, t.tx, t.ty);
    if (!tiles_.count(key)) tile_order_.push_back(key);
    tiles_[key] = std::move(t);
  }
  std::optional<LiveTile> TakeTile() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (tile_order_.empty()) return std::nullopt;
    const auto key = tile_order_.front();
    tile_order_.pop_front();
    LiveTile t = std::move(tiles_.at(key));
    tiles_.erase(key);
    return t;
  }
  // STEREO -> AVD: every perception result for the 3-D map, in capture order (bounded: a
  // planner that falls behind loses the oldest, which newer scans of the same space replace).
  void PushPerception(avoid::PerceptionUpdate u) {
    std::lock_guard<std::mutex> lock(mutex_);
    perception_.push_back(std::move(u));
    while (perception_.size() > kMaxPerceptionQueued) perception_.pop_front();
  }
  std::vector<avoid::PerceptionUpdate> TakePerception() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<avoid::PerceptionUpdate> out(std::make_move_iterator(perception_.begin()), std::make_move_iterator(perception_.end()));
    perception_.clear();
    return out;
  }
  std::vector<StatusText> TakeStatus() {
    std::lock_guard<std::mutex> lock(mutex_);
    std::vector<StatusText> out(status_.begin(), status_.end());
    status_.clear();
    return out;
  }

 private:
  mutable std::mutex mutex_;
  BlackboardData data_;
  std::deque<control::CommandRequest> commands_;
  std::deque<control::TaskReport> reports_;
  std::deque<StatusText> status_;
  std::map<std::string, PreviewFrame> previews_;
  std::deque<TrackRequest> track_requests_;
  std::deque<TrackReport> track_reports_;
  std::optional<PowerLines> power_lines_;
  std::optional<Obstacles> obstacles_;
  std::optional<PointCloud> point_cloud_;
  std::optional<SharedFrame> frame_;
  std::optional<DepthGrid> depth_grid_;
  std::optional<ActiveStereoReport> active_stereo_;
  std::optional<VisualOdometryReport> visual_odometry_;
  std::deque<SurveyCapture> captures_;
  std::deque<std::pair<std::string, std::string>> downloads_;
  std::map<std::tuple<int, int, int>, LiveTile> tiles_;
  std::deque<std::tuple<int, int, int>> tile_order_;
  static constexpr std::size_t kMaxPerceptionQueued = 8;
  std::deque<avoid::PerceptionUpdate> perception_;
};

}  // namespace uav::app
