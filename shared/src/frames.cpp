#include "uav/shared/frames.hpp"

#include <algorithm>
#include <cmath>

namespace uav {

Eigen::Matrix3d RotationNBFromEuler(const EulerAngles& e) {
  const double cf = std::cos(e.phi), sf = std::sin(e.phi);
  const double ct = std::cos(e.theta), st = std::sin(e.theta);
  const double cp = std::cos(e.psi), sp = std::sin(e.psi);
  Eigen::Matrix3d R;
  // Thesis Eq. 2.2 (with the (1,3) entry corrected), equal to Rz(psi) Ry(theta) Rx(phi), Eq. 5.51.
  R << ct * cp, cp * st * sf - sp * cf, cp * st * cf + sp * sf,
       sp * ct, sp * st * sf + cp * cf, sp * st * cf - cp * sf,
       -st,     ct * sf,                ct * cf;
  return R;
}

EulerAngles EulerFromRotationNB(const Eigen::Matrix3d& R) {
  EulerAngles e;
  e.theta = -std::asin(std::clamp(R(2, 0), -1.0, 1.0));
  e.phi = std::atan2(R(2, 1), R(2, 2));
  e.psi = std::atan2(R(1, 0), R(0, 0));
  return e;
}

Eigen::Matrix3d EulerRateFromBodyRate(double phi, double theta) {
  const double cf = std::cos(phi), sf = std::sin(phi);
  const double ct = std::cos(theta), tt = std::tan(theta);
  Eigen::Matrix3d G;
  // Thesis Eq. 2.3.
  G << 1.0, sf * tt, cf * tt,
       0.0, cf, -sf,
       0.0, sf / ct, cf / ct;
  return G;
}

Eigen::Matrix3d RotationBCForward() {
  Eigen::Matrix3d R;
  R.col(0) = Eigen::Vector3d(0, 1, 0);
  R.col(1) = Eigen::Vector3d(0, 0, 1);
  R.col(2) = Eigen::Vector3d(1, 0, 0);
  return R;
}

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * M_PI);  // in [-pi, pi]
  return a <= -M_PI ? a + 2.0 * M_PI : a;
}

Eigen::Vector3d MagneticField_N(double inclination_rad) {
  return {std::cos(inclination_rad), 0.0, std::sin(inclination_rad)};
}

std::optional<Eigen::Matrix3d> TriadRotationNB(const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N,
                                               const Eigen::Vector3d& a_B, const Eigen::Vector3d& b_B) {
  auto triad = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) -> std::optional<Eigen::Matrix3d> {
    const Eigen::Vector3d c = a.cross(b);
    if (!(a.norm() > 1e-9) || !(c.norm() > 1e-6 * a.norm() * b.norm())) return std::nullopt;
    Eigen::Matrix3d m;
    m.col(0) = a.normalized();
    m.col(1) = c.normalized();
    m.col(2) = m.col(0).cross(m.col(1));
    return m;
  };
  const auto n = triad(a_N, b_N), b = triad(a_B, b_B);
  if (!n || !b) return std::nullopt;
  return Eigen::Matrix3d(*n * b->transpose());
}

}  // namespace uav
