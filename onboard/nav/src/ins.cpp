#include "uav/nav/ins.hpp"

#include <cmath>
#include <optional>

#include "uav/shared/frames.hpp"

namespace uav::nav {
namespace {

// Error-state layout.
constexpr int kP = 0, kV = 3, kTh = 6, kBg = 9, kBa = 12, kBb = 15;
// A run of refused visual positions this long ties the odometry to the INS again [us].
constexpr int64_t kVisualReanchorUs = 500'000;
// A GPS fix this recent is fresh: the next one of a 5 Hz receiver is not yet overdue [us].
constexpr int64_t kGpsFreshUs = 300'000;
constexpr double kOdometryTimeConstantS = 1.0;  // the odometry velocity's pull toward Doppler

// Forgets what the filter knew of one 3-state block (position, velocity, ...): its correlations
// with every other state dropped, its variances set anew (a reset of that block's states).
void ResetBlock(Ins::Matrix* P, int block, const Eigen::Vector3d& variance) {
  P->block<3, Ins::kStates>(block, 0).setZero();
  P->block<Ins::kStates, 3>(0, block).setZero();
  P->block<3, 3>(block, block) = variance.asDiagonal();
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Quaterniond ExpQ(const Eigen::Vector3d& th) {
  const double a = th.norm();
  if (a < 1e-12) return Eigen::Quaterniond(1, 0.5 * th.x(), 0.5 * th.y(), 0.5 * th.z()).normalized();
  return Eigen::Quaterniond(Eigen::AngleAxisd(a, th / a));
}

// The heading error [rad] a magnetometer reading shows against the attitude R_NB: the angle
// about N's z from the reading, rotated into N, to Earth's field, in the horizontal plane. Any
// attitude (a tail-sitter's nose-up hover included); nullopt when the reading rotated into N
// has almost no horizontal part.
std::optional<double> MagneticHeadingError(const Eigen::Matrix3d& R_NB, const Eigen::Vector3d& mag_B, double inclination) {
  const Eigen::Vector3d m_N = R_NB * mag_B, e_N = MagneticField_N(inclination);
  const double cross = m_N.x() * e_N.y() - m_N.y() * e_N.x(), dot = m_N.x() * e_N.x() + m_N.y() * e_N.y();
  if (std::hypot(cross, dot) < 0.05 * std::cos(inclination)) return std::nullopt;
  return std::atan2(cross, dot);
}

}  // namespace

InsParams InsParams::FromParameters(const ParameterSet& p) {
  InsParams i;
  i.gravity = p.Get("gravity");
  i.gyro_noise = p.Get("imu_gyro_noise");
  i.gyro_bias = p.Get("imu_gyro_bias");
  i.accel_noise = p.Get("imu_accel_noise");
  i.accel_bias = p.Get("imu_accel_bias");
  i.mag_noise = p.Get("mag_noise");
  i.mag_inclination = p.Get("mag_inclination");
  i.gps_noise_h = std::hypot(p.Get("gps_noise_h"), p.Get("gps_drift_h"));
  i.gps_noise_v = std::hypot(p.Get("gps_noise_v"), p.Get("gps_drift_v"));
  i.gps_vel_noise = p.Get("gps_vel_noise");
  i.baro_noise = p.Get("baro_noise");
  i.baro_drift = p.Get("baro_drift");
  i.baro_drift_time = p.Get("baro_drift_time");
  i.sonar_noise = p.Get("sonar_noise");
  i.sonar_mount_pitch = p.Get("sonar_mount_pitch");
  i.gyro_bias_walk = p.Get("ins_gyro_bias_walk");
  i.accel_bias_walk = p.Get("ins_accel_bias_walk");
  return i;
}

Ins::Ins(const InsParams& params, const GeodeticPoint& home) : p_(params), frame_(home) {}

Eigen::Vector3d Ins::position_sigma() const {
  return P_.diagonal().segment<3>(kP).cwiseMax(0.0).cwiseSqrt();
}

void Ins::Align(const hal::SensorSample& s) {
  // Level from the accelerometer (the vehicle stands still when powered), heading from the
  // magnetometer, position from the first GPS fix, height zero: it is powered at home.
  // TRIAD on gravity (exact) and the field (its heading), so that a vehicle standing in any
  // attitude aligns: a quadrotor level, a tail-sitter nose-up on its tail.
  const auto R_NB = TriadRotationNB(Eigen::Vector3d::UnitZ(), MagneticField_N(p_.mag_inclination), -s.accel_B, s.mag_B);
  q_NB_ = R_NB ? Eigen::Quaterniond(*R_NB) : Eigen::Quaterniond::Identity();
  p_N_.setZero();
  if (s.gps_utime > 0 && std::isfinite(s.gps.latitude_deg) && std::isfinite(s.gps.longitude_deg))
    p_N_.head<2>() = frame_.ToNed(s.gps).head<2>();
  p_O_ne_ = p_N_.head<2>();
  v_O_ne_.setZero();
  v_N_.setZero();
  bg_.setZero();
  ba_.setZero();
  baro_bias_ = s.baro_alt_m;
  P_.setZero();
  P_.diagonal().segment<2>(kP).setConstant(p_.gps_noise_h * p_.gps_noise_h);
  P_(kP + 2, kP + 2) = 0.3 * 0.3;
  P_.diagonal().segment<3>(kV).setConstant(0.1 * 0.1);
  P_.diagonal().segment<2>(kTh).setConstant(0.05 * 0.05);
  P_(kTh + 2, kTh + 2) = 0.2 * 0.2;
  P_.diagonal().segment<3>(kBg).setConstant(std::max(1e-8, p_.gyro_bias * p_.gyro_bias));
  // In hover a horizontal accelerometer bias looks exactly like a tilt; turns in yaw separate
  // the two (the bias turns with the body, a tilt error does not).
  P_.diagonal().segment<3>(kBa).setConstant(std::max(1e-8, p_.accel_bias * p_.accel_bias));
  P_(kBb, kBb) = 0.5 * 0.5;
  last_gps_utime_ = s.gps_utime;
  // Aligned at a known place (the fix, or home): that counts as a fix, so the position is not
  // "lost" while the receiver's first fix is on its way.
  last_gps_fix_utime_ = s.utime;
  last_sonar_utime_ = s.sonar_utime;
  health_.aligned = true;
}

void Ins::Propagate(const Eigen::Vector3d& gyro_B, const Eigen::Vector3d& accel_B, double dt) {
  const Eigen::Vector3d w = gyro_B - bg_;
  const Eigen::Vector3d f = accel_B - ba_;
  const Eigen::Matrix3d R = q_NB_.toRotationMatrix();
  const Eigen::Vector3d a_N = R * f + Eigen::Vector3d(0, 0, p_.gravity);
  p_N_ += v_N_ * dt + 0.5 * a_N * dt * dt;
  // The odometry frame moves with its own velocity (see Update); position corrections never
  // reach it.
  p_O_ne_ += v_O_ne_ * dt + 0.5 * a_N.head<2>() * dt * dt;
  v_O_ne_ += a_N.head<2>() * dt;
  v_N_ += a_N * dt;
  q_NB_ = (q_NB_ * ExpQ(w * dt)).normalized();

  // Error dynamics: dp' = dv, dv' = -R [f]x dth - R dba, dth' = -[w]x dth - dbg.
  Matrix F = Matrix::Identity();
  F.block<3, 3>(kP, kV) = Eigen::Matrix3d::Identity() * dt;
  F.block<3, 3>(kV, kTh) = -R * Skew(f) * dt;
  F.block<3, 3>(kV, kBa) = -R * dt;
  F.block<3, 3>(kTh, kTh) = Eigen::Matrix3d::Identity() - Skew(w) * dt;
  F.block<3, 3>(kTh, kBg) = -Eigen::Matrix3d::Identity() * dt;
  P_ = F * P_ * F.transpose();
  // Sensor noise per sample, plus a floor for what 50 Hz point samples miss between them.
  const double qv = (p_.accel_noise * p_.accel_noise) * dt * dt + 0.003 * 0.003 * dt;
  const double qth = (p_.gyro_noise * p_.gyro_noise) * dt * dt + 0.00005 * 0.00005 * dt;
  const double baro_walk = p_.baro_drift * std::sqrt(2.0 / p_.baro_drift_time);
  for (int i = 0; i < 3; ++i) {
    P_(kV + i, kV + i) += qv;
    P_(kTh + i, kTh + i) += qth;
    P_(kBg + i, kBg + i) += p_.gyro_bias_walk * p_.gyro_bias_walk * dt;
    P_(kBa + i, kBa + i) += p_.accel_bias_walk * p_.accel_bias_walk * dt;
  }
  P_(kBb, kBb) += baro_walk * baro_walk * dt;
}

bool Ins::Correct(double innovation, const Vector& H, double r, double gate) {
  const Vector PHt = P_ * H;
  const double s = H.dot(PHt) + r;
  if (!(s > 0.0) || !std::isfinite(innovation)) return false;
  if (gate > 0.0 && innovation * innovation > gate * gate * s) return false;
  const Vector K = PHt / s;
  const Vector dx = K * innovation;
  P_ -= K * PHt.transpose();
  P_ = 0.5 * (P_ + P_.transpose());
  // Inject the error into the nominal state (and reset it to zero).
  p_N_ += dx.segment<3>(kP);
  v_N_ += dx.segment<3>(kV);
  q_NB_ = (q_NB_ * ExpQ(dx.segment<3>(kTh))).normalized();
  bg_ += dx.segment<3>(kBg);
  ba_ += dx.segment<3>(kBa);
  baro_bias_ += dx(kBb);
  return true;
}

void Ins::Update(const hal::SensorSample& s, bool at_rest) {
  if (!s.gyro_B.allFinite() || !s.accel_B.allFinite() || s.gyro_B.cwiseAbs().maxCoeff() > 35.0 ||
      s.accel_B.cwiseAbs().maxCoeff() > 16.0 * p_.gravity) {
    ++health_.imu_rejected;  // propagation resumes with the next good sample, over the gap
    return;
  }
  const bool gps_ok = std::isfinite(s.gps.latitude_deg) && std::isfinite(s.gps.longitude_deg) &&
                      std::isfinite(s.gps.altitude_m) && s.gps_v_N.allFinite();
  const bool baro_ok = std::isfinite(s.baro_alt_m);
  const bool mag_ok = s.mag_B.allFinite() && s.mag_B.norm() > 0.1;
  const bool sonar_ok = std::isfinite(s.sonar_range_m);
  health_.other_rejected += !gps_ok + !baro_ok + !mag_ok + !sonar_ok;
  if (!health_.aligned) {
    if (!mag_ok || !baro_ok) return;  // align on a complete sample
    Align(s);
    last_utime_ = s.utime;
    Publish(s);
    return;
  }
  const double dt = (s.utime - last_utime_) * 1e-6;
  last_utime_ = s.utime;
  if (dt > 0.0 && dt < 1.0) Propagate(s.gyro_B, s.accel_B, dt);

  auto unit = [](int i) {
    Vector h = Vector::Zero();
    h(i) = 1.0;
    return h;
  };
  if (s.gps_utime != last_gps_utime_ && s.gps_fix >= 3 && gps_ok) {
    // The odometry frame's velocity: the IMU's acceleration between fixes, pulled toward the
    // Doppler velocity with a 1 s time constant. The filter's own velocity also answers to the
    // position fixes, so it takes up the fix's wander as motion (about 0.3 m in 10 s standing
    // still); Doppler does not wander.
    const double fix_dt = std::clamp((s.gps_utime - last_gps_utime_) * 1e-6, 0.0, kOdometryTimeConstantS);
    v_O_ne_ += fix_dt / kOdometryTimeConstantS * (s.gps_v_N.head<2>() - v_O_ne_);
    last_gps_utime_ = s.gps_utime;
    last_gps_fix_utime_ = s.utime;
    const Eigen::Vector3d z = frame_.ToNed(s.gps);
    // Most of GPS's error wanders slowly: successive fixes are far from independent, so each
    // counts as a tenth of an independent one (else the estimate chases the fix-to-fix noise).
    const double r_pos[3] = {10 * p_.gps_noise_h * p_.gps_noise_h, 10 * p_.gps_noise_h * p_.gps_noise_h,
                             10 * p_.gps_noise_v * p_.gps_noise_v};
    bool accepted = true;
    for (int i = 0; i < 3; ++i) accepted &= Correct(z[i] - p_N_[i], unit(kP + i), r_pos[i], 5.0);
    for (int i = 0; i < 3; ++i)
      accepted &= Correct(s.gps_v_N[i] - v_N_[i], unit(kV + i), p_.gps_vel_noise * p_.gps_vel_noise,
                          health_.gps_rejected >= 5 ? 0.0 : 5.0);  // after 1 s of refusals: take it
    health_.gps_rejected = accepted ? 0 : health_.gps_rejected + 1;
    // A filter that refuses GPS for 5 s has diverged (or GPS jumped): start again from GPS.
    if (health_.gps_rejected >= 25) {
      p_N_.head<2>() = z.head<2>();
      ResetBlock(&P_, kP, Eigen::Vector3d(r_pos[0], r_pos[1], r_pos[2]));
      health_.gps_rejected = 0;
      ++health_.gps_resets;
    }
  }
  // Barometer: baro = -z + bias.
  if (baro_ok) {
    Vector H = Vector::Zero();
    H(kP + 2) = -1.0;
    H(kBb) = 1.0;
    Correct(s.baro_alt_m - (-p_N_.z() + baro_bias_), H, p_.baro_noise * p_.baro_noise, 5.0);
  }
  if (s.sonar_utime != last_sonar_utime_ && s.sonar_valid && sonar_ok) {
    last_sonar_utime_ = s.sonar_utime;
    const double cos_tilt = (q_NB_ * hal::SonarBeam_B(p_.sonar_mount_pitch)).z();
    const double height = s.sonar_range_m * cos_tilt;
    if (!Correct(height - (-p_N_.z()), -unit(kP + 2), p_.sonar_noise * p_.sonar_noise + 0.01 * 0.01, 5.0))
      ++health_.sonar_rejected;
  }
  if (queued_height_) {
    const VisionHeight h = *queued_height_;
    queued_height_.reset();
    // Against the height estimated at its exposure (position_history.hpp).
    const std::optional<Eigen::Vector3d> p_then = PositionAt(h.utime, s.utime);
    if (p_then && Correct(h.height_m - (-p_then->z()), -unit(kP + 2), h.sigma_m * h.sigma_m + 0.01 * 0.01, 5.0))
      ++health_.vision_height_used;
    else
      ++health_.vision_height_rejected;
  }
  // Visual odometry (thesis 5.7). While GPS fixes are fresh, each VO position ties the
  // odometry's frame to the INS (a new segment is tied wherever it starts); from the first missed
  // fix on, VO positions correct the INS against that tie, so the motion since the last fix is
  // measured, not integrated from the IMU, and the hand-over never passes through "inertial
  // only". GPS stays the position source until no fix has come for 2.5 s.
  const int64_t since_fix_us = s.utime - last_gps_fix_utime_;
  const bool gps_fresh = last_gps_fix_utime_ >= 0 && since_fix_us <= kGpsFreshUs;
  const bool gps_lost = last_gps_fix_utime_ < 0 || since_fix_us > 2'500'000;
  // Each against the position estimated at its exposure (position_history.hpp).
  const std::optional<Eigen::Vector3d> visual_p_then =
      queued_visual_ ? PositionAt(queued_visual_->utime, s.utime) : std::optional<Eigen::Vector3d>();
  if (queued_visual_ && !visual_p_then) ++health_.vision_position_rejected;  // older than the last second
  if (queued_visual_ && visual_p_then) {
    const VisualPosition v = *queued_visual_;
    const Eigen::Vector3d& p_then = *visual_p_then;
    if (gps_fresh || !visual_anchor_ || visual_anchor_->second != v.segment) {
      visual_anchor_ = std::make_pair(Eigen::Vector3d(p_then - v.p_N), v.segment);
      visual_refused_since_utime_ = -1;
      last_visual_utime_ = s.utime;
    } else {
      const Eigen::Vector3d z = v.p_N + visual_anchor_->first;
      const double r = v.sigma_m * v.sigma_m + 0.01 * 0.01;
      bool accepted = true;
      for (int i = 0; i < 3; ++i) accepted &= Correct(z[i] - p_then[i], unit(kP + i), r, 5.0);
      if (accepted) {
        ++health_.vision_position_used;
        last_visual_utime_ = s.utime;
        visual_refused_since_utime_ = -1;
      } else {
        ++health_.vision_position_rejected;
        if (visual_refused_since_utime_ < 0) visual_refused_since_utime_ = s.utime;
        if (s.utime - visual_refused_since_utime_ >= kVisualReanchorUs) {
          // Tied again, the INS also lets go of what it was sure of: a wrong velocity would
          // carry it off the odometry again and again. Position to the odometry's sigma,
          // velocity to 0.5 m/s, their correlations dropped (as the GPS reset above).
          visual_anchor_->first = p_then - v.p_N;
          ResetBlock(&P_, kP, Eigen::Vector3d::Constant(r));
          ResetBlock(&P_, kV, Eigen::Vector3d::Constant(0.5 * 0.5));
          last_visual_utime_ = s.utime;
          visual_refused_since_utime_ = -1;
          ++health_.vision_reanchors;
        }
      }
    }
  }
  queued_visual_.reset();
  position_source_ = !gps_lost ? PositionSource::kGps
                     : (last_visual_utime_ >= 0 && s.utime - last_visual_utime_ <= 1'000'000) ? PositionSource::kVision
                                                                                              : PositionSource::kInertial;
  // Magnetic heading.
  if (mag_ok) {
    if (const auto heading_error = MagneticHeadingError(q_NB_.toRotationMatrix(), s.mag_B, p_.mag_inclination)) {
      Vector H = Vector::Zero();
      H.segment<3>(kTh) = q_NB_.toRotationMatrix().row(2).transpose();
      const double sigma = p_.mag_noise / std::max(0.1, std::cos(p_.mag_inclination)) + 0.002;
      Correct(*heading_error, H, sigma * sigma, 0.0);
    }
  }
  if (!at_rest) has_flown_ = true;
  if (at_rest && !has_flown_) {
    // Powered at home, before the first take-off: the height is zero by definition of home, which
    // zeroes the barometer as PX4 does before arming.
    Correct(-(-p_N_.z()), -unit(kP + 2), 0.02 * 0.02, 0.0);
  }
  // Without GPS (visual odometry, or inertial alone) the odometry frame follows the filter's
  // velocity, which is then all there is.
  if (gps_lost && dt > 0.0) v_O_ne_ += std::min(1.0, dt / kOdometryTimeConstantS) * (v_N_.head<2>() - v_O_ne_);
  if (at_rest) {
    // Standing on the ground: no velocity, no rotation (this is what calibrates the gyro bias).
    v_O_ne_.setZero();
    for (int i = 0; i < 3; ++i) Correct(-v_N_[i], unit(kV + i), 0.02 * 0.02, 0.0);
    for (int i = 0; i < 3; ++i)
      Correct(s.gyro_B[i] - bg_[i], unit(kBg + i), p_.gyro_noise * p_.gyro_noise + 1e-8, 0.0);
  }
  Publish(s);
}

std::optional<Eigen::Vector3d> Ins::PositionAt(int64_t utime, int64_t now) const {
  if (std::llabs(utime - now) <= PositionHistory::kMatchUs) return p_N_;  // this sample's: as corrected so far
  return past_p_N_.At(utime);
}

void Ins::Publish(const hal::SensorSample& s) {
  past_p_N_.Record(s.utime, p_N_);
  estimate_.utime = s.utime;
  estimate_.p_N = p_N_;
  estimate_.p_O << p_O_ne_, p_N_.z();
  estimate_.v_N = v_N_;
  estimate_.q_NB = q_NB_;
  estimate_.euler = EulerFromRotationNB(q_NB_.toRotationMatrix());
  estimate_.w_B = s.gyro_B - bg_;
  estimate_.f_B = s.accel_B - ba_;
  estimate_.attitude_covariance_B = P_.block<3, 3>(kTh, kTh);
}

void Ins::QueueHeight(int64_t utime, double height_m, double sigma_m) {
  if (!std::isfinite(height_m) || !std::isfinite(sigma_m) || height_m < 0 || sigma_m < 0) {
    ++health_.vision_height_rejected;
    return;
  }
  queued_height_ = VisionHeight{utime, height_m, sigma_m};
}

void Ins::QueueVisualPosition(int64_t utime, const Eigen::Vector3d& p_N, double sigma_m, int segment) {
  if (!p_N.allFinite() || !std::isfinite(sigma_m) || sigma_m <= 0) {
    ++health_.vision_position_rejected;
    return;
  }
  queued_visual_ = VisualPosition{utime, p_N, sigma_m, segment};
}

}  // namespace uav::nav
