#pragma once
// STEREO: the forward stereo pair on the vehicle clock (WIRES: a second pair for wires alone). A thin shell around hal::StereoCamera
// (simulated or real): takes both images at the pair's rate, rectifies them once, feeds
// vision::StereoObstacleDetector (obstacle cylinders, thesis 3.5: obstacles_t every pair, a
// decimated point_cloud_t at obs_cloud_rate; its points give the nearest obstacle ahead in the
// corridor, vehicle_state_t.obstacle_range_m) and vision::PowerLineStereo (power
// lines in the image and in 3-D, thesis 3.6: power_lines_t, and the nearest wire in
// vehicle_state_t.nearest_wire_m, the median of the last three pairs), and streams the left image to the GCS video panel at its
// preview rate. The wires are placed in NED with the flight stack's estimate, never the truth.
#include <array>
#include <memory>
#include <optional>

#include "uav/runtime/vision_worker.hpp"
#include "uav/avoid/avoidance.hpp"
#include "uav/runtime/preview_stream.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/power_line_stereo.hpp"
#include "uav/vision/stereo_obstacles.hpp"
#include "uav/vision/stereo_range.hpp"

namespace uav::runtime {

struct StereoWorkerParams {
  // What the pair is for: obstacles (and their points for the map) and wires, or one of them (a
  // second pair rolled for wires, pwl_rig: it adds wires only, and does not keep the obstacle
  // perception fresh). Sensing decides from obs_rig and pwl_rig.
  bool detect_obstacles = true;
  bool power_lines = true;             // pwl_enable
  vision::WireRangingParams ranging;   // pwl_min_range, pwl_max_range
  vision::PowerLineParams detection;   // pwl_segments, pwl_verify
  vision::ObstacleParams obstacles;    // obs_matcher, obs_max_sigma, obs_margin, obs_min_voxels
  double cloud_rate_hz = 1.0;          // obs_cloud_rate
  bool to_map = false;                 // avd_enable: every pair's points, obstacles and wires go to the 3-D map
  // From a vehicle parameter file; throws naming a missing or out-of-range parameter.
  static StereoWorkerParams FromParameters(const ParameterSet& p);
};

// What one pair adds to the avoidance map, in N (T_NL: the left camera's pose at the pair, as
// estimated): its points as rays from the camera, its thin obstacle cylinders (not the wide
// ones: crowns, walls), and the runs of its wires whose depth is trusted.
avoid::PerceptionUpdate StereoMapUpdate(int64_t utime, const vision::StereoObstacles& found,
                                        const std::vector<vision::Wire3D>& wires, const Eigen::Isometry3d& T_NL);

class StereoWorker : public VisionWorker {
 public:
  StereoWorker(hal::StereoCamera& camera, Blackboard& board, const StereoWorkerParams& params);
  void Begin(int64_t utime) override;
  // obs_margin: the margin drawn around each obstacle (the planner keeps the same one).
  void ApplyParameters(const ParameterSet& params) override;
  double safety_margin_m() const { return obstacles_.params().safety_margin_m; }
  void Work(Outbox& out) override;
  int frames() const { return frames_; }        // pairs processed
  int unhealthy() const { return unhealthy_; }  // pairs that could not be used

 private:
  // T_NB: the estimate's body pose at this pair (never the truth).
  void ReportPowerLines(const std::vector<vision::Wire3D>& wires, const cv::Size& image, int64_t utime,
                        const Eigen::Isometry3d& T_NB, Outbox& out);
  void ReportObstacles(int64_t utime, const vision::StereoObstacles& found, const Eigen::Isometry3d& T_NB, Outbox& out);
  void ReportUnhealthy(int64_t utime, const std::string& reason, Outbox& out);
  // The pair's reprojected points (for the rays), obstacles and wires, for obstacle avoidance, in
  // the odometry frame (O's origin at p_NO in N then).
  void ReportToMap(int64_t utime, const vision::StereoObstacles& found, const std::vector<vision::Wire3D>& wires,
                   const Eigen::Isometry3d& T_NB, const Eigen::Vector3d& p_NO, Outbox& out) const;

  hal::StereoCamera& camera_;
  vision::StereoRectifier rectifier_;
  vision::StereoObstacleDetector obstacles_;  // its range gate also bounds the wires trusted on the map
  bool detect_obstacles_;
  double cloud_rate_hz_;
  bool to_map_;
  int64_t last_cloud_utime_ = -1;
  std::optional<vision::PowerLineStereo> power_lines_;
  PreviewStream preview_;
  Eigen::Isometry3d T_NB_ = Eigen::Isometry3d::Identity();  // the estimate then
  Eigen::Vector3d p_NO_ = Eigen::Vector3d::Zero();          // and the odometry frame's origin
  static constexpr double kNoWire = 1e9;
  std::array<double, 3> recent_nearest_m_{kNoWire, kNoWire, kNoWire};  // per pair, kNoWire: none ranged
  int frames_ = 0;
  int unhealthy_ = 0;
};

}  // namespace uav::runtime
