#include "uav/sim/sim_sensors.hpp"

#include "uav/shared/frames.hpp"

#include <cmath>

namespace uav::sim {
namespace {

// One step of a first-order Gauss-Markov process with stationary 1 sigma `sigma`.
double GaussMarkov(double x, double sigma, double tau, double dt, double unit_normal) {
  const double a = std::exp(-dt / tau);
  return a * x + sigma * std::sqrt(1.0 - a * a) * unit_normal;
}

}  // namespace

SensorParams SensorParams::FromParameters(const ParameterSet& p) {
  return {p.Get("imu_gyro_noise"), p.Get("imu_gyro_bias"),  p.Get("imu_accel_noise"), p.Get("imu_accel_bias"),
          p.Get("mag_noise"),      p.Get("mag_inclination"), p.Get("gps_rate"),       p.Get("gps_noise_h"),
          p.Get("gps_drift_h"),    p.Get("gps_noise_v"),    p.Get("gps_drift_v"),     p.Get("gps_drift_time"),
          p.Get("gps_vel_noise"),  p.Get("baro_noise"),     p.Get("baro_drift"),      p.Get("baro_drift_time"),
          p.Get("sonar_rate"),     p.Get("sonar_range_min"), p.Get("sonar_range_max"), p.Get("sonar_noise"),
          p.Get("sonar_mount_pitch")};
}

Eigen::Vector3d SensorParams::MagneticField_N() const { return uav::MagneticField_N(mag_inclination); }

SimSensors::SimSensors(const SensorParams& params, const GeodeticPoint& home, uint64_t seed)
    : p_(params), frame_(home), rng_(seed ^ 0x53454e53ull) {
  gyro_bias_ = p_.gyro_bias * Normal3();
  accel_bias_ = p_.accel_bias * Normal3();
  // Start the wander from its stationary distribution: a receiver that has run a while.
  gps_drift_N_ = Normal3().cwiseProduct(Eigen::Vector3d(p_.gps_drift_h, p_.gps_drift_h, p_.gps_drift_v));
  baro_drift_ = 0.0;  // the barometer is zeroed at power-on
}

Eigen::Vector3d SimSensors::Normal3() {
  const double x = normal_(rng_), y = normal_(rng_), z = normal_(rng_);
  return {x, y, z};
}

ImuDeltas::Reading ImuDeltas::Measure(int64_t utime, const Eigen::Vector3d& v_N, const Eigen::Quaterniond& q_NB,
                                      double gravity, const Reading& first) {
  Reading r = first;
  const double T = (utime - last_utime_) * 1e-6;
  if (last_utime_ >= 0 && T > 0.0) {
    r.f_B = q_NB.conjugate() * ((v_N - last_v_N_) / T - Eigen::Vector3d(0, 0, gravity));
    const Eigen::AngleAxisd dq(last_q_NB_.conjugate() * q_NB);
    r.w_B = dq.axis() * dq.angle() / T;
  }
  last_utime_ = utime;
  last_v_N_ = v_N;
  last_q_NB_ = q_NB;
  return r;
}

void SimSensors::Sample(int64_t utime, const QuadrotorState& truth, const Eigen::Vector3d& specific_force_B,
                        hal::SensorSample* out) {
  const double dt = last_utime_ < 0 ? 0.0 : (utime - last_utime_) * 1e-6;
  last_utime_ = utime;
  const Eigen::Matrix3d R_NB = truth.q_NB.toRotationMatrix();
  out->utime = utime;
  out->gyro_B = truth.w_B + gyro_bias_ + p_.gyro_noise * Normal3();
  out->accel_B = specific_force_B + accel_bias_ + p_.accel_noise * Normal3();
  out->mag_B = R_NB.transpose() * p_.MagneticField_N() + p_.mag_noise * Normal3();

  // Barometer: altitude above the power-on level, wandering slowly.
  baro_drift_ = GaussMarkov(baro_drift_, p_.baro_drift, p_.baro_drift_time, dt, normal_(rng_));
  out->baro_alt_m = -truth.p_N.z() + baro_drift_ + p_.baro_noise * normal_(rng_);

  if (utime >= next_gps_utime_ && gps_enabled_) {
    const double gps_dt = 1.0 / p_.gps_rate;
    for (int i = 0; i < 3; ++i)
      gps_drift_N_[i] = GaussMarkov(gps_drift_N_[i], i < 2 ? p_.gps_drift_h : p_.gps_drift_v, p_.gps_drift_time,
                                    gps_utime_ == 0 ? 0.0 : gps_dt, normal_(rng_));
    const Eigen::Vector3d white = Normal3().cwiseProduct(Eigen::Vector3d(p_.gps_noise_h, p_.gps_noise_h, p_.gps_noise_v));
    gps_error_N_ = gps_drift_N_ + white;
    gps_ = frame_.ToGeodetic(truth.p_N + gps_error_N_);
    gps_v_N_ = R_NB * truth.v_B + p_.gps_vel_noise * Normal3();
    gps_utime_ = utime;
    // The receiver's own clock: fixes stay at gps_rate on average whatever the sampling.
    next_gps_utime_ = std::max(next_gps_utime_ + static_cast<int64_t>(std::llround(1e6 * gps_dt)), utime);
  }
  if (utime >= next_sonar_utime_) {
    // Slant range along the beam to the flat ground at z = 0; the echo is lost out of range or
    // when the beam meets the ground too obliquely (beyond 30 deg of tilt).
    const double cos_tilt = (R_NB * hal::SonarBeam_B(p_.sonar_mount_pitch)).z();
    const double height = -truth.p_N.z();
    sonar_valid_ = false;
    if (cos_tilt > std::cos(M_PI / 6)) {
      const double range = height / cos_tilt + p_.sonar_noise * normal_(rng_);
      if (range >= p_.sonar_range_min && range <= p_.sonar_range_max) {
        sonar_range_ = range;
        sonar_valid_ = true;
      }
    }
    sonar_utime_ = utime;
    next_sonar_utime_ = std::max(next_sonar_utime_ + static_cast<int64_t>(std::llround(1e6 / p_.sonar_rate)), utime);
  }
  out->gps_utime = gps_utime_;
  out->gps = gps_;
  out->gps_v_N = gps_v_N_;
  out->gps_fix = gps_enabled_ ? 3 : 0;
  out->gps_satellites = gps_enabled_ ? 9 : 0;
  out->sonar_utime = sonar_utime_;
  out->sonar_range_m = sonar_range_;
  out->sonar_valid = sonar_valid_;
}

}  // namespace uav::sim
