#pragma once
// Monocular depth from motion (thesis 3.4): features tracked by pyramidal Lucas-Kanade, a depth
// measurement per feature from its flow and the camera's motion (Eq. 3.22-3.25), one extended
// Kalman filter per feature (process Eq. 3.26, measurement Eq. 3.27), and the depths averaged
// over a grid whose cells are free beyond a depth threshold and obstacles below it (Fig. 3.11).
// Static scenes only, as the thesis says. Plain class: images and navigation poses in, a grid
// out; no threads or messages.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core/types.hpp>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/mono_depth.hpp"

namespace cv {
class Mat;
}

namespace uav::vision {

struct MonoDepthParams {
  int max_features = 240;             // features kept, spread evenly over the grid's cells
  double feature_quality = 0.01;      // goodFeaturesToTrack quality level
  double min_feature_distance_px = 10;
  int border_px = 8;                  // features nearer the edge are dropped
  int lk_window_px = 21;              // pyramidal Lucas-Kanade window and levels
  int lk_levels = 4;
  double max_forward_backward_px = 1.0;  // a feature tracked back must land this close to where it was
  double flow_noise_px = 0.35;        // sigma of a tracked feature's position (sets R, Eq. 3.27)
  double process_noise = 0.02;        // sigma of Z's random walk relative to Z, per sqrt(s) (eps_1, Eq. 3.26)
  double gate_sigma = 3.0;            // measurements further than this from the prediction are outliers
  int max_outliers = 3;               // consecutive outliers before a feature is renewed
  double min_parallax_px = 0.5;       // translation-induced flow below this gives no measurement
  double converged_rel_sigma = 0.05;  // a feature counts in the grid once sigma_Z / Z is below this ...
  int converged_updates = 5;          // ... after at least this many measurements
  double max_measurement_age_s = 1.0; // ... and with a measurement this recent
  int grid_cols = 4, grid_rows = 3;   // Fig. 3.11
  int min_cell_features = 3;          // fewer converged features: the cell is unknown
  double obstacle_depth_m = 10.0;     // a cell nearer than this is an obstacle, beyond it free
  // Throws std::invalid_argument naming the first value out of range.
  void Validate() const;
};

using uav::CellState;
using uav::DepthCell;
using uav::DepthGrid;

struct DepthFeature {
  cv::Point2f px;           // in the newest frame
  double depth_m = 0.0;     // filter state (0: not yet measured)
  double sigma_m = 0.0;
  bool converged = false;
};

class MonoDepthEstimator {
 public:
  // Throws std::invalid_argument for bad intrinsics or parameters.
  MonoDepthEstimator(const CameraIntrinsics& camera, const MonoDepthParams& params);
  ~MonoDepthEstimator();
  MonoDepthEstimator(MonoDepthEstimator&&) noexcept;
  MonoDepthEstimator& operator=(MonoDepthEstimator&&) noexcept;

  // One frame (8-bit grey or BGR, the calibration's size) exposed at `utime` [us], with the
  // camera's pose in the local NED frame from the navigation solution at that time (nullopt:
  // no navigation sample for this frame). The camera's linear and angular velocity between
  // frames come from consecutive poses. A frame that cannot be used (wrong size, time not after
  // the previous, pose missing or not finite) gives an unhealthy grid with the reason, every
  // cell unknown, and restarts the flow from the next frame.
  // `v_N` is the navigation solution's velocity [m/s] at the frame (of the camera, NED), when it
  // has one: its mean over the interval is used instead of the poses' difference, which carries
  // the position fixes' steps.
  DepthGrid Update(const cv::Mat& image, int64_t utime, const std::optional<Eigen::Isometry3d>& T_NC,
                   const std::optional<Eigen::Vector3d>& v_N = std::nullopt);

  const std::vector<DepthFeature>& features() const;
  const MonoDepthParams& params() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
