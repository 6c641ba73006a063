#include "uav/shared/visual_odometry.hpp"

namespace uav {

const char* Name(PositionSource s) {
  switch (s) {
    case PositionSource::kGps: return "gps";
    case PositionSource::kVision: return "vision";
    case PositionSource::kInertial: return "inertial";
  }
  return "?";
}

// Visual odometry: health, counts, where the INS's position comes from, and the VO+IMU track's
// horizontal distance from the truth (simulation; 0 without one).
const std::vector<Signal<VisualOdometryReport>>& ReportSignals<VisualOdometryReport>::Table() {
  using F = SignalFormat;
  using R = VisualOdometryReport;
  static const std::vector<Signal<R>> k = {
      {{"healthy", "healthy", "1", "1 a motion, 0 none", F::kBool}, [](const R& r) { return double(r.healthy); }},
      {{"source", "source", "1", "0 GPS, 1 vision, 2 inertial", F::kInteger}, [](const R& r) { return double(r.source); }},
      {{"inliers", "inliers", "1", "", F::kInteger}, [](const R& r) { return double(r.inliers); }},
      {{"tracked", "tracked", "1", "", F::kInteger}, [](const R& r) { return double(r.tracked); }},
      {{"segment", "segment", "1", "", F::kInteger}, [](const R& r) { return double(r.segment); }},
      {{"rms", "rms_px", "px", "", F::kMetres}, [](const R& r) { return r.rms_px; }},
      {{"disparity_offset", "disparity_offset_px", "px", "stereo calibration residual learnt from the motion", F::kMetres},
       [](const R& r) { return r.disparity_offset_px; }},
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

}  // namespace uav
