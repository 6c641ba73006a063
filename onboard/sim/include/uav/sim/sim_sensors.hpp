#pragma once
// The INS box's sensors (thesis 2.3.2) measuring the simulated truth: IMU (gyro, accelerometer,
// magnetometer) with white noise and turn-on biases, GPS at its own rate with white noise plus a
// slow wander and a poor altitude, a barometer with wander, and a downward sonar with limited
// range over flat ground. Plain class: the caller supplies the truth and the time.
#include <cstdint>
#include <random>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/quadrotor_model.hpp"

namespace uav::sim {

// Noise figures, 1 sigma (units in the vehicle file).
struct SensorParams {
  double gyro_noise, gyro_bias, accel_noise, accel_bias, mag_noise, mag_inclination;
  double gps_rate, gps_noise_h, gps_drift_h, gps_noise_v, gps_drift_v, gps_drift_time, gps_vel_noise;
  double baro_noise, baro_drift, baro_drift_time;
  double sonar_rate, sonar_range_min, sonar_range_max, sonar_noise, sonar_mount_pitch;
  static SensorParams FromParameters(const ParameterSet& p);
  // Earth's field in N, unit strength (declination taken as zero: magnetic north is north).
  Eigen::Vector3d MagneticField_N() const;
};

// The IMU integrates between samples (as a MEMS IMU's filter and the ArduIMU's oversampling do):
// what it reads are the mean specific force and body rate since the previous sample, from the
// velocity and attitude then and now (delta-velocity, delta-angle), so that touchdowns and fast
// manoeuvres between samples reach the INS.
class ImuDeltas {
 public:
  struct Reading {
    Eigen::Vector3d f_B = Eigen::Vector3d::Zero();  // [m/s^2] specific force
    Eigen::Vector3d w_B = Eigen::Vector3d::Zero();  // [rad/s]
  };
  // The truth at `utime`; the first call (no previous sample) reads `first`, the instantaneous values.
  Reading Measure(int64_t utime, const Eigen::Vector3d& v_N, const Eigen::Quaterniond& q_NB, double gravity,
                  const Reading& first);

 private:
  int64_t last_utime_ = -1;
  Eigen::Vector3d last_v_N_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond last_q_NB_ = Eigen::Quaterniond::Identity();
};

class SimSensors {
 public:
  SimSensors(const SensorParams& params, const GeodeticPoint& home, uint64_t seed);

  // Measures `truth` at `utime`. `specific_force_B` is what an ideal accelerometer feels
  // [m/s^2]. Slow sensors take a new reading only when their period has passed.
  void Sample(int64_t utime, const QuadrotorState& truth, const Eigen::Vector3d& specific_force_B,
              hal::SensorSample* out);

  // Simulator fault: without GPS the receiver reports no fix and no new readings (as under a
  // jammer or indoors); with it back, fixes resume at the next period.
  void SetGpsEnabled(bool enabled) { gps_enabled_ = enabled; }
  bool gps_enabled() const { return gps_enabled_; }

  // The turn-on biases this run drew (for tests of the INS).
  const Eigen::Vector3d& gyro_bias() const { return gyro_bias_; }
  const Eigen::Vector3d& accel_bias() const { return accel_bias_; }
  // The GPS error of the latest fix (truth to fix) in N [m].
  const Eigen::Vector3d& gps_error_N() const { return gps_error_N_; }

 private:
  Eigen::Vector3d Normal3();
  SensorParams p_;
  LocalNedFrame frame_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::Vector3d gyro_bias_, accel_bias_;
  Eigen::Vector3d gps_drift_N_ = Eigen::Vector3d::Zero();
  Eigen::Vector3d gps_error_N_ = Eigen::Vector3d::Zero();
  double baro_drift_ = 0.0;
  int64_t last_utime_ = -1;
  int64_t next_gps_utime_ = 0, next_sonar_utime_ = 0;
  // Latest slow readings, repeated between updates.
  int64_t gps_utime_ = 0, sonar_utime_ = 0;
  GeodeticPoint gps_;
  Eigen::Vector3d gps_v_N_ = Eigen::Vector3d::Zero();
  double sonar_range_ = 0.0;
  bool sonar_valid_ = false;
  bool gps_enabled_ = true;
};

}  // namespace uav::sim
