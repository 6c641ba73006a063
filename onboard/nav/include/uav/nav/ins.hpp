#pragma once
// The IMU thread's inertial navigation (thesis 2.3.2: "the INS consists of an IMU, GPS,
// barometer and ultrasonic sonar"): a 16-state error-state Kalman filter. The IMU propagates
// position, velocity and attitude at 50 Hz; GPS position and velocity, barometric and sonar
// height and magnetic heading correct them and estimate the gyro, accelerometer and barometer
// biases. Plain class, fed plain samples; control reads its estimate, never the truth.
#include <cstdint>
#include <optional>
#include <utility>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/hal/navigation_estimate.hpp"
#include "uav/hal/vehicle_backend.hpp"
#include "uav/nav/position_history.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/visual_odometry.hpp"

namespace uav::nav {

// The sensors' noise figures (1 sigma, the vehicle file's imu_*, gps_*, baro_*, sonar_*, mag_*)
// and the filter's own bias random walks.
struct InsParams {
  double gravity;
  double gyro_noise, gyro_bias, accel_noise, accel_bias, mag_noise, mag_inclination;
  double gps_noise_h, gps_noise_v, gps_vel_noise;  // total: white and wander together
  double baro_noise, baro_drift, baro_drift_time, sonar_noise, sonar_mount_pitch;
  double gyro_bias_walk, accel_bias_walk;  // [rad/s/sqrt(s)], [m/s^2/sqrt(s)]
  static InsParams FromParameters(const ParameterSet& p);
};

struct InsHealth {
  bool aligned = false;
  int gps_rejected = 0;    // GPS fixes refused by the innovation gate, in a row
  int gps_resets = 0;      // times the position was reset to GPS after a run of refusals
  int sonar_rejected = 0;  // sonar readings refused (an object under the vehicle)
  int imu_rejected = 0;    // IMU samples refused: not finite or beyond the sensor's range
  int other_rejected = 0;  // GPS, barometer, sonar or magnetometer readings that were not finite
  int vision_height_used = 0, vision_height_rejected = 0;  // QueueHeight's, applied and refused
  int vision_position_used = 0, vision_position_rejected = 0;  // QueueVisualPosition's
  int vision_reanchors = 0;  // times the odometry was tied to the INS again after a run of refusals
};


class Ins {
 public:
  Ins(const InsParams& params, const GeodeticPoint& home);

  // One IMU sample (50 Hz): propagates, then applies the measurements that are new in it.
  // `at_rest` (disarmed on the ground) adds zero-velocity and zero-rate measurements.
  // A sample whose gyro or accelerometer is not finite or beyond the sensor's range (35 rad/s,
  // 16 g) is refused whole; a non-finite slow reading is skipped. The estimate stays finite.
  void Update(const hal::SensorSample& sample, bool at_rest);
  // A height of the body origin over the ground from vision (active stereo, thesis ch. 4) [m]
  // with its 1 sigma, measured at `utime` (the exposure; it arrives later), applied at the next
  // Update like the sonar's against the height estimated at `utime` (position_history.hpp; gated
  // at 5 sigma: a reading off a table is refused). A non-finite or negative one, or one older than
  // the last second, is counted and dropped.
  void QueueHeight(int64_t utime, double height_m, double sigma_m);
  // A body position from visual odometry (thesis ch. 5) in its own frame anchored in N [m], with
  // its 1 sigma and its segment (an unbroken chain of poses), measured at `utime` (the exposure)
  // and fused against the position estimated then, like QueueHeight. The odometry is relative: while GPS
  // fixes are fresh (one in the last 0.3 s) each position ties the two frames together; once a
  // fix is missed, each next one corrects the position against that tie (gated at 5 sigma), and
  // a new segment is tied where it starts. Refused for half a second in a row (a jump of the
  // odometry's chain, or an INS that has become too sure of itself), the odometry is tied again
  // where the INS is: the INS never flies on the IMU alone while the odometry still sees.
  void QueueVisualPosition(int64_t utime, const Eigen::Vector3d& p_N, double sigma_m, int segment);
  // Aligns anew on the next complete sample, as at power-up (level and heading from gravity and
  // the field, position from the GPS fix, height zero, the biases and covariance reset): after a
  // crash the filter ran on a tumbling IMU and its estimate may be anything. The vehicle must
  // stand still (the land detector says when).
  void Realign() {
    health_.aligned = false;
    visual_anchor_.reset();
  }
  // Where the position comes from (telemetry shows it): GPS fixes, visual odometry while GPS is
  // lost, or the IMU alone (dead reckoning, which drifts within seconds).
  PositionSource position_source() const { return position_source_; }

  hal::VehicleEstimate estimate() const { return estimate_; }
  const InsHealth& health() const { return health_; }
  Eigen::Vector3d gyro_bias() const { return bg_; }
  double gravity() const { return p_.gravity; }
  Eigen::Vector3d accel_bias() const { return ba_; }
  // 1 sigma of the position error the filter believes [m], N.
  Eigen::Vector3d position_sigma() const;

  static constexpr int kStates = 16;  // dp dv dtheta dbg dba dbaro
  using Vector = Eigen::Matrix<double, kStates, 1>;
  using Matrix = Eigen::Matrix<double, kStates, kStates>;

 private:
  void Align(const hal::SensorSample& s);
  void Propagate(const Eigen::Vector3d& gyro_B, const Eigen::Vector3d& accel_B, double dt);
  // Scalar measurement z = h(x) + noise with Jacobian H and variance r; `gate` in sigmas (0: none).
  // Returns false when the gate refused it.
  bool Correct(double innovation, const Vector& H, double r, double gate);
  void Publish(const hal::SensorSample& s);
  // The position estimated at `utime` (now: the state being corrected), for late measurements.
  std::optional<Eigen::Vector3d> PositionAt(int64_t utime, int64_t now) const;

  InsParams p_;
  LocalNedFrame frame_;
  Eigen::Vector3d p_N_ = Eigen::Vector3d::Zero(), v_N_ = Eigen::Vector3d::Zero();
  Eigen::Vector2d p_O_ne_ = Eigen::Vector2d::Zero();  // VehicleEstimate::p_O, north and east
  Eigen::Vector2d v_O_ne_ = Eigen::Vector2d::Zero();  // its rate of change
  Eigen::Quaterniond q_NB_ = Eigen::Quaterniond::Identity();
  Eigen::Vector3d bg_ = Eigen::Vector3d::Zero(), ba_ = Eigen::Vector3d::Zero();
  double baro_bias_ = 0.0;
  Matrix P_ = Matrix::Identity();

 public:
  const Matrix& covariance() const { return P_; }
  int64_t last_utime_ = -1, last_gps_utime_ = 0, last_sonar_utime_ = 0;
  struct VisionHeight {
    int64_t utime;
    double height_m, sigma_m;
  };
  std::optional<VisionHeight> queued_height_;
  struct VisualPosition {
    int64_t utime;
    Eigen::Vector3d p_N;
    double sigma_m;
    int segment;
  };
  std::optional<VisualPosition> queued_visual_;
  std::optional<std::pair<Eigen::Vector3d, int>> visual_anchor_;  // odometry-to-N offset, its segment
  int64_t last_gps_fix_utime_ = -1, last_visual_utime_ = -1;       // when each last corrected
  int64_t visual_refused_since_utime_ = -1;  // the first of the current run of refused positions
  PositionHistory past_p_N_;                 // the estimate's positions, for late measurements
  PositionSource position_source_ = PositionSource::kGps;
  bool has_flown_ = false;  // false until the first sample not at rest
  hal::VehicleEstimate estimate_;
  InsHealth health_;
};

}  // namespace uav::nav
