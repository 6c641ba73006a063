#pragma once
// Test helper: rendered stereo flights over the GPS-denied village for visual odometry, with the
// exact pose of the rectified left camera for every pair.
#include <algorithm>
#include <cmath>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/stereo_rectifier.hpp"
#include "uav/vision/stereo_vo.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision::testing {

inline world::Scene VoVillage() {
  return world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/gps_denied_village.scene.json");
}

inline Eigen::Isometry3d BodyPose(const Eigen::Vector3d& p_N, double yaw, double pitch, double roll) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles a;
  a.psi = yaw, a.theta = pitch, a.phi = roll;
  T.linear() = RotationNBFromEuler(a);
  T.translation() = p_N;
  return T;
}

// A racetrack at `alt_m`: 120 m north, a right turn of radius 25 m, 60 m east... back to the
// start (517 m), flown at `speed` with the nose 4 degrees down and banked into the turns, the
// height swinging by 1 m. `s` is the distance flown.
inline Eigen::Isometry3d RacetrackPose(double s, double alt_m, double speed) {
  const double a = 120, b = 60, r = 25, turn = M_PI / 2 * r;
  const double legs[8] = {a, turn, b, turn, a, turn, b, turn};
  const double perimeter = 2 * (a + b) + 4 * turn;
  s = std::fmod(s, perimeter);
  Eigen::Vector2d p(-a / 2, -b / 2 - r);  // start of the first (northward) leg, west side
  double heading = 0, bank = 0;
  for (int i = 0; i < 8; ++i) {
    const double l = std::min(s, legs[i]);
    if (i % 2 == 0) {
      p += l * Eigen::Vector2d(std::cos(heading), std::sin(heading));
    } else {
      const Eigen::Vector2d centre = p + r * Eigen::Vector2d(std::cos(heading + M_PI / 2), std::sin(heading + M_PI / 2));
      const double ang = l / r;
      p = centre + r * Eigen::Vector2d(std::cos(heading - M_PI / 2 + ang), std::sin(heading - M_PI / 2 + ang));
      heading += ang;
      // Banked into the turn, rolling in and out over 1 s (a real vehicle cannot roll at once).
      const double ramp = std::clamp(std::min(l, legs[i] - l) / speed, 0.0, 1.0);
      if (s < legs[i]) bank = ramp * std::atan(speed * speed / (r * 9.81));
    }
    s -= l;
    if (s <= 0) break;
  }
  const double alt = alt_m + std::sin(2 * M_PI * s / 97.0);
  return BodyPose({p.x(), p.y(), -alt}, heading, -4 * M_PI / 180, bank);
}

// A KITTI-like car rig (Geiger et al. 2012, sequences 04-12): grey cameras of 1226 x 370 px, focal
// length 707.09 px, baseline 0.54 m, facing forward 1.65 m above the road.
inline world::StereoSetup KittiRig() {
  world::CameraSetup c;
  c.name = "kitti";
  c.intrinsics.width = 1226, c.intrinsics.height = 370;
  c.intrinsics.fx = c.intrinsics.fy = 707.0912;
  c.intrinsics.cx = 601.8873, c.intrinsics.cy = 183.1104;
  c.rate_hz = 10;
  Eigen::Isometry3d T_B_rig = Eigen::Isometry3d::Identity();
  T_B_rig.linear() = RotationBCForward();
  return world::MakeStereoSetup(c, T_B_rig, 0.5372, {});
}

// A drive on the ground (the rig 1.65 m up): `straight` m north, a left turn of `turn_deg` on a
// radius of `radius` m, then straight on. `s` is the distance driven.
inline Eigen::Isometry3d DrivePose(double s, double straight, double radius, double turn_deg) {
  const double arc = radius * turn_deg * M_PI / 180;
  Eigen::Vector2d p(-straight, 0);
  double heading = 0;
  const double l1 = std::min(s, straight);
  p.x() += l1;
  s -= l1;
  if (s > 0) {
    const double l2 = std::min(s, arc), ang = l2 / radius;
    const Eigen::Vector2d centre = p + radius * Eigen::Vector2d(0, -1);  // turning left (towards west)
    p = centre + radius * Eigen::Vector2d(std::sin(ang), std::cos(ang));
    heading = -ang;
    s -= l2;
  }
  if (s > 0) p += s * Eigen::Vector2d(std::cos(heading), std::sin(heading));
  return BodyPose({p.x(), p.y(), -1.65}, heading, 0, 0);
}

// The INS's attitude of a camera as the odometry is fed it in flight: the truth with a slow
// drift (0.01 deg/s about the vertical, as a heading held by the magnetometer wanders) and
// 0.03 deg of noise per axis.
class ImuAttitude {
 public:
  Eigen::Matrix3d R_NC(const Eigen::Matrix3d& R_NC_true, double t_s) {
    const double deg = M_PI / 180;
    const Eigen::Vector3d error(noise_(rng_), noise_(rng_), 0.01 * deg * t_s + noise_(rng_));
    return Eigen::AngleAxisd(error.norm(), error.normalized()).toRotationMatrix() * R_NC_true;
  }

 private:
  std::mt19937 rng_{3};
  std::normal_distribution<double> noise_{0.0, 0.03 * M_PI / 180};
};

struct RenderedPair {
  RectifiedPair pair;
  Eigen::Isometry3d T_NC;  // exact pose of the rectified left camera
  Eigen::Isometry3d T_NB;
};

class StereoFlightRenderer {
 public:
  explicit StereoFlightRenderer(const world::Scene& scene) : StereoFlightRenderer(scene, *scene.stereo_camera()) {}
  // `setup` as calibrated (what rectification and the odometry believe); `actual`, where given, as
  // the cameras really are (a calibration's residual).
  StereoFlightRenderer(const world::Scene& scene, const world::StereoSetup& setup,
                       const std::optional<world::StereoSetup>& actual = std::nullopt)
      : setup_(setup), actual_(actual.value_or(setup)), renderer_(scene, actual_),
        rectifier_(StereoRig{setup_.left.intrinsics, setup_.right.intrinsics, setup_.T_LR()}) {}
  RenderedPair Render(const Eigen::Isometry3d& T_NB, int64_t utime) const {
    const world::StereoFrame f = renderer_.Render(T_NB, utime, false);  // dark, as the VO thread takes its pairs
    RenderedPair out;
    cv::Mat l, r;
    cv::cvtColor(f.left.image, l, cv::COLOR_BGR2GRAY);
    cv::cvtColor(f.right.image, r, cv::COLOR_BGR2GRAY);
    rectifier_.Rectify(l, r, &out.pair.left, &out.pair.right);
    out.pair.left_utime = out.pair.right_utime = utime;
    out.T_NB = T_NB;
    out.T_NC = T_NB * setup_.left.T_BC;
    out.T_NC.linear() = out.T_NC.linear() * rectifier_.geometry().R_L_rect;
    return out;
  }
  const RectifiedGeometry& geometry() const { return rectifier_.geometry(); }
  const world::StereoSetup& setup() const { return setup_; }

 private:
  world::StereoSetup setup_, actual_;
  world::StereoRenderer renderer_;
  StereoRectifier rectifier_;
};

}  // namespace uav::vision::testing
