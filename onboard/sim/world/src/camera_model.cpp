#include "uav/world/camera_model.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace uav::world {

Eigen::Matrix3d RotationBCDownward() {
  Eigen::Matrix3d R;
  // Columns are the camera axes in B: x_C = right (y_B), y_C = towards the tail (-x_B), z_C = down.
  R.col(0) = Eigen::Vector3d(0, 1, 0);
  R.col(1) = Eigen::Vector3d(-1, 0, 0);
  R.col(2) = Eigen::Vector3d(0, 0, 1);
  return R;
}

Eigen::Vector3d LaserEmitter::BeamDirection(int i) const {
  const int r = i / cols, c = i % cols;
  const double ax = (c - (cols - 1) / 2.0) * pitch_rad;
  const double ay = (r - (rows - 1) / 2.0) * pitch_rad;
  // A diffraction grating spreads the orders evenly in the tangent of the angle.
  const double cr = std::cos(roll_rad), sr = std::sin(roll_rad);
  const double tx = std::tan(ax), ty = std::tan(ay);
  return Eigen::Vector3d(cr * tx - sr * ty, sr * tx + cr * ty, 1.0).normalized();
}

StereoSetup MakeStereoSetup(const CameraSetup& camera, const Eigen::Isometry3d& T_B_rig,
                            double baseline_m, const LaserEmitter& laser) {
  if (!(std::isfinite(baseline_m) && baseline_m > 0.0 && baseline_m <= 2.0))
    throw std::invalid_argument("stereo baseline must be in (0, 2] m");
  StereoSetup s;
  s.baseline_m = baseline_m;
  s.laser = laser;
  s.left = camera;
  s.right = camera;
  s.left.name = camera.name + "_left";
  s.right.name = camera.name + "_right";
  s.left.T_BC = T_B_rig * Eigen::Translation3d(-baseline_m / 2, 0, 0);
  s.right.T_BC = T_B_rig * Eigen::Translation3d(baseline_m / 2, 0, 0);
  s.T_BE = T_B_rig;
  return s;
}

}  // namespace uav::world
