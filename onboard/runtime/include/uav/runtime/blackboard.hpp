#pragma once
// Data shared by the onboard threads. Each field has one writer thread (named); readers take a
// copy under the lock. Stage ordering in the scheduler makes the hand-over deterministic.
#include <array>
#include <memory>
#include <mutex>
#include <tuple>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "uav/avoid/avoidance.hpp"
#include "uav/hal/navigation_estimate.hpp"
#include "uav/control/land_detector.hpp"
#include "uav/control/mixer.hpp"
#include "uav/control/tailsitter_controller.hpp"
#include "uav/control/task_manager.hpp"
#include "uav/hal/vehicle_backend.hpp"
#include "uav/runtime/mailbox.hpp"
#include "uav/shared/operator_messages.hpp"
#include "uav/shared/reports.hpp"
#include "uav/shared/tracking.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav::runtime {

struct StatusText {
  Severity severity;
  std::string text;
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
// where the estimate put the camera when it was exposed, in the odometry frame (nullopt: no
// navigation sample then): depth from motion reads the motion between frames, and O's does
// not jump with a GPS correction.
struct SharedFrame {
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;
  std::vector<uint8_t> bgr;  // width * height * 3, row-major
  std::optional<Eigen::Isometry3d> T_OC_estimate;
  std::optional<Eigen::Vector3d> v_N_estimate;  // [m/s] the vehicle's estimated velocity then
};

// U-Lion's flight state, written by CTL (thesis 2.6).
struct TailSitterStatus {
  control::TailSitterMode mode = control::TailSitterMode::kHover;
  double transition_progress = 1.0;  // 0..1 through a transition; 1 when not transitioning
  double airspeed_mps = 0.0;         // the pitot's reading
  airframe::TailSitterInputs inputs;      // what the controller commands, SVO wires to the channels
};

struct BlackboardData {
  // IMU thread
  hal::SensorSample sample;
  hal::VehicleEstimate estimate;
  // The land detector (control/land_detector.hpp): on the ground, flying, falling or crashed;
  // still for its rest time; the measured gravity's tilt from upright [rad]; why it crashed.
  control::GroundState ground_state = control::GroundState::kOnGround;
  bool at_rest = true;
  double rest_tilt_rad = 0.0;
  std::string crash_reason;
  // CTL thread
  control::ServoCommand servo;
  std::optional<TailSitterStatus> tailsitter;  // U-Lion only
  bool armed = false;
  bool airborne = false;
  bool touched_down = false;  // on the ground after a landing's touchdown (TaskManager::Output)
  control::Task task = control::Task::kIdle;
  int mission_item = -1;
  control::FailsafeAction failsafe = control::FailsafeAction::kNone;
  double fence_radius_m = 0.0, fence_alt_m = 0.0;  // the geofence it enforces
  int chirp_channel = 0;  // servo channel a chirp is exciting (control::ServoChannel), 0: none
  // CMM thread
  double gcs_link_age_s = -1.0;  // [s] wall clock since the last GCS heartbeat; < 0: none heard yet
  std::optional<ManualSticks> sticks;  // the operator's newest sticks; utime: vehicle clock at arrival
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
  std::string obstacle_unhealthy_reason;  // the obstacle pair's last unusable frame ("" while it is healthy)
  // IMU thread: where the INS takes its position from, and the VO+IMU filter's track.
  PositionSource position_source = PositionSource::kGps;
  std::optional<Eigen::Vector3d> vo_track_N;
  TrackedTarget target;
  // CTL -> AVD: where the active task is taking the vehicle (obstacle avoidance plans to it).
  struct AvoidRequest {
    bool active = false;
    Eigen::Vector3d goal_N = Eigen::Vector3d::Zero();  // the task's goal (leg end)
    Eigen::Vector3d via_N = Eigen::Vector3d::Zero();   // the task's own setpoint now
    bool map_only = false;  // the perception is lost: plan through space seen free only
  };
  AvoidRequest avoid_request;
  // AVD: its newest plan (null before the first).
  std::shared_ptr<const avoid::AvoidancePlan> avoid_plan;
  // CTL: what the safety layer is doing, why, and the speed the seen space allows [m/s].
  avoid::AvoidState avoid_state = avoid::AvoidState::kOff;
  std::string avoid_reason;
  double avoid_speed_limit = -1.0;
  // CTL: the parameters as they are now (null: the vehicle does not serve them) and how many
  // changes over the link they carry; a thread with live settings re-reads them on a new version.
  std::shared_ptr<const ParameterSet> params;
  int64_t params_version = 0;
};

// A finished file STITCH offers for download.
struct Download {
  std::string name;
  std::string contents;
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
  // The parameters when they have changed since `*version` (which is then brought up to date),
  // else null: where every thread with live settings takes them, once per change.
  std::shared_ptr<const ParameterSet> ParametersNewerThan(int64_t* version) const {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!data_.params || data_.params_version == *version) return nullptr;
    *version = data_.params_version;
    return data_.params;
  }
  // Any thread -> CMM: a status text for the operator.
  void PushStatus(Severity severity, std::string text) { status.Push({severity, std::move(text)}); }

  // The hand-overs between threads (mailbox.hpp), writer -> reader.
  Queue<control::CommandRequest> commands;  // CMM -> CTL: validated commands
  Queue<CommandAck> task_reports;  // CTL -> CMM: acknowledgements
  Queue<StatusText> status;                 // any -> CMM
  // Camera threads -> CMM: per camera, the newest preview replaces one not yet sent (video is
  // live, not queued).
  KeyedLatest<std::string, VideoFrame> previews;
  Queue<TrackTarget> track_requests;  // CMM -> TRK: targets picked (or cancelled), in order
  // TRK (and CMM, for targets refused at the edge) -> CMM: every report, in order (a rejection
  // must not be overwritten by the next frame's status).
  Queue<TrackStatus> track_reports;
  Latest<SharedFrame> frame;         // CAM or TRK -> MDEPTH: the newest frame of the camera it wants
  Queue<SurveyCapture> captures;     // CAM -> STITCH: every capture (a survey frame is never dropped)
  Queue<Download> downloads;         // STITCH -> CMM: finished files to offer
  // STITCH -> CMM: the newest content of each changed tile; CMM takes the longest-waiting first
  // at its own (bounded) rate.
  KeyedLatest<std::tuple<int, int, int>, MapTile> tiles;
  // STEREO, MDEPTH -> AVD: every perception result for the 3-D map, in the order they become
  // visible (bounded: a planner that falls behind loses the oldest, which newer scans of the
  // same space replace).
  Queue<avoid::PerceptionUpdate> perception{16};
  // Vision workers (and the sensing monitor) -> CMM: each report type's newest replaces one not
  // yet sent (uav/shared/reports.hpp lists them).
  ReportSlots<VehicleReports> reports;

 private:
  mutable std::mutex mutex_;
  BlackboardData data_;
};

}  // namespace uav::runtime
