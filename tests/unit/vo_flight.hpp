#pragma once
// Test helper: rendered stereo flights over the GPS-denied village for visual odometry, with the
// exact pose of the rectified left camera for every pair.
#include <algorithm>
#include <cmath>
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
  explicit StereoFlightRenderer(const world::Scene& scene)
      : setup_(*scene.stereo_camera()), renderer_(scene, setup_),
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
  world::StereoSetup setup_;
  world::StereoRenderer renderer_;
  StereoRectifier rectifier_;
};

}  // namespace uav::vision::testing
