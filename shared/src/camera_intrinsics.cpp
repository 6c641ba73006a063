#include "uav/shared/camera_intrinsics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/LU>

namespace uav {


namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("camera intrinsics: " + what);
}
}  // namespace

void ValidateIntrinsics(const CameraIntrinsics& k) {
  Require(k.width >= 16 && k.width <= 20000, "width must be 16..20000 px, got " + std::to_string(k.width));
  Require(k.height >= 16 && k.height <= 20000, "height must be 16..20000 px, got " + std::to_string(k.height));
  Require(std::isfinite(k.fx) && k.fx > 0, "fx must be positive and finite");
  Require(std::isfinite(k.fy) && k.fy > 0, "fy must be positive and finite");
  Require(std::isfinite(k.cx) && k.cx >= 0 && k.cx <= k.width - 1, "cx must lie inside the image");
  Require(std::isfinite(k.cy) && k.cy >= 0 && k.cy <= k.height - 1, "cy must lie inside the image");
  const char* names[5] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i)
    Require(std::isfinite(k.distortion[i]) && std::abs(k.distortion[i]) < 10.0,
            std::string(names[i]) + " must be finite with magnitude below 10");
}

CameraIntrinsics IntrinsicsFromParameters(const ParameterSet& p) {
  CameraIntrinsics k;
  k.width = static_cast<int>(p.Get("image_width_px"));
  k.height = static_cast<int>(p.Get("image_height_px"));
  const double f_mm = p.Get("focal_length_mm");
  k.fx = f_mm / p.Get("sensor_width_mm") * k.width;
  k.fy = f_mm / p.Get("sensor_height_mm") * k.height;
  k.cx = p.Has("cx_px") ? p.Get("cx_px") : (k.width - 1) / 2.0;
  k.cy = p.Has("cy_px") ? p.Get("cy_px") : (k.height - 1) / 2.0;
  const char* names[5] = {"k1", "k2", "p1", "p2", "k3"};
  for (int i = 0; i < 5; ++i) k.distortion[i] = p.Has(names[i]) ? p.Get(names[i]) : 0.0;
  try {
    ValidateIntrinsics(k);
  } catch (const std::exception& e) {
    throw std::invalid_argument(p.source() + ": " + e.what());
  }
  return k;
}

namespace {
Eigen::Vector2d Distort(const CameraIntrinsics& k, double x, double y) {
  const auto& d = k.distortion;
  const double r2 = x * x + y * y;
  const double radial = 1.0 + r2 * (d[0] + r2 * (d[1] + r2 * d[4]));
  const double xd = x * radial + 2.0 * d[2] * x * y + d[3] * (r2 + 2.0 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2.0 * y * y) + 2.0 * d[3] * x * y;
  return {xd, yd};
}
}  // namespace

Eigen::Vector2d Project(const CameraIntrinsics& k, const Eigen::Vector3d& p_C) {
  const Eigen::Vector2d xd = Distort(k, p_C.x() / p_C.z(), p_C.y() / p_C.z());
  return {k.fx * xd.x() + k.cx, k.fy * xd.y() + k.cy};
}

Eigen::Vector2d Unproject(const CameraIntrinsics& k, const Eigen::Vector2d& uv) {
  const Eigen::Vector2d target((uv.x() - k.cx) / k.fx, (uv.y() - k.cy) / k.fy);
  Eigen::Vector2d x = target;
  const auto& d = k.distortion;
  if (d[0] == 0 && d[1] == 0 && d[2] == 0 && d[3] == 0 && d[4] == 0) return x;
  // Newton's method on Distort(x) = target with a numeric Jacobian; converges in a few steps for
  // any lens a survey or stereo camera has.
  for (int it = 0; it < 50; ++it) {
    const Eigen::Vector2d r = Distort(k, x.x(), x.y()) - target;
    if (r.norm() < 1e-13) break;
    const double h = 1e-7;
    Eigen::Matrix2d J;
    J.col(0) = (Distort(k, x.x() + h, x.y()) - Distort(k, x.x() - h, x.y())) / (2 * h);
    J.col(1) = (Distort(k, x.x(), x.y() + h) - Distort(k, x.x(), x.y() - h)) / (2 * h);
    x -= J.inverse() * r;
  }
  return x;
}

}  // namespace uav
