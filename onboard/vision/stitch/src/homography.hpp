#pragma once
// The one point-through-homography helper of the stitch library (internal).
#include <Eigen/Geometry>  // homogeneous()

namespace uav::vision {

// H applied to pixel p (homogeneous, then divided back).
inline Eigen::Vector2d Apply(const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = H * p.homogeneous();
  return q.head<2>() / q.z();
}

}  // namespace uav::vision
