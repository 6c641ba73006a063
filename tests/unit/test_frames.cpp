#include <gtest/gtest.h>

#include <cmath>

#include "uav/shared/frames.hpp"

namespace uav {
namespace {

TEST(Frames, YawOnlyRotatesNorthToEast) {
  // psi = 90 deg: the body x axis (forward) points East in N.
  const Eigen::Matrix3d R = RotationNBFromEuler({0, 0, M_PI / 2});
  const Eigen::Vector3d fwd_N = R * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(fwd_N.x(), 0.0, 1e-12);
  EXPECT_NEAR(fwd_N.y(), 1.0, 1e-12);
  EXPECT_NEAR(fwd_N.z(), 0.0, 1e-12);
}

TEST(Frames, PitchUpRaisesTheNose) {
  // theta = +30 deg (nose up): forward axis gains an upward (negative down) component.
  const Eigen::Matrix3d R = RotationNBFromEuler({0, M_PI / 6, 0});
  const Eigen::Vector3d fwd_N = R * Eigen::Vector3d::UnitX();
  EXPECT_NEAR(fwd_N.x(), std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(fwd_N.z(), -0.5, 1e-12);
}

TEST(Frames, RollRightLowersTheRightSide) {
  // phi = +30 deg: the body y axis (right) points partly down.
  const Eigen::Matrix3d R = RotationNBFromEuler({M_PI / 6, 0, 0});
  const Eigen::Vector3d right_N = R * Eigen::Vector3d::UnitY();
  EXPECT_NEAR(right_N.y(), std::sqrt(3.0) / 2, 1e-12);
  EXPECT_NEAR(right_N.z(), 0.5, 1e-12);
}

TEST(Frames, MatchesHandComputedEq22WithCorrectedEntry) {
  // phi = 10, theta = 20, psi = 30 degrees, each entry computed by hand from Eq. 2.2.
  const double f = 10 * M_PI / 180, t = 20 * M_PI / 180, p = 30 * M_PI / 180;
  const Eigen::Matrix3d R = RotationNBFromEuler({f, t, p});
  using std::cos;
  using std::sin;
  EXPECT_NEAR(R(0, 0), cos(t) * cos(p), 1e-12);
  EXPECT_NEAR(R(0, 1), cos(p) * sin(t) * sin(f) - sin(p) * cos(f), 1e-12);
  EXPECT_NEAR(R(0, 2), cos(p) * sin(t) * cos(f) + sin(p) * sin(f), 1e-12);
  EXPECT_NEAR(R(1, 0), sin(p) * cos(t), 1e-12);
  EXPECT_NEAR(R(1, 1), sin(p) * sin(t) * sin(f) + cos(p) * cos(f), 1e-12);
  EXPECT_NEAR(R(1, 2), sin(p) * sin(t) * cos(f) - cos(p) * sin(f), 1e-12);
  EXPECT_NEAR(R(2, 0), -sin(t), 1e-12);
  EXPECT_NEAR(R(2, 1), cos(t) * sin(f), 1e-12);
  EXPECT_NEAR(R(2, 2), cos(t) * cos(f), 1e-12);
  // Numbers: R(0,0) = cos20 cos30 = 0.813797681.
  EXPECT_NEAR(R(0, 0), 0.813797681, 1e-9);
}

TEST(Frames, EqualsZYXProductOfEq551) {
  const double f = 0.3, t = -0.4, p = 2.5;
  const Eigen::Matrix3d expected = (Eigen::AngleAxisd(p, Eigen::Vector3d::UnitZ()) *
                                    Eigen::AngleAxisd(t, Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(f, Eigen::Vector3d::UnitX()))
                                       .toRotationMatrix();
  EXPECT_TRUE(RotationNBFromEuler({f, t, p}).isApprox(expected, 1e-12));
  EXPECT_TRUE(RotationNBFromEuler({f, t, p}).determinant() > 0.999999);
}

TEST(Frames, EulerRoundTrip) {
  for (double f : {-2.0, -0.5, 0.0, 0.7, 3.0})
    for (double t : {-1.4, -0.2, 0.0, 0.9})
      for (double p : {-3.0, -1.0, 0.0, 1.5, 3.1}) {
        const EulerAngles e = EulerFromRotationNB(RotationNBFromEuler({f, t, p}));
        EXPECT_NEAR(e.phi, f, 1e-9);
        EXPECT_NEAR(e.theta, t, 1e-9);
        EXPECT_NEAR(e.psi, p, 1e-9);
      }
}

TEST(Frames, EulerRateMatrixEq23AgainstFiniteDifference) {
  // Rotate by a small body rate and compare the Euler angle change with Gamma * w.
  const EulerAngles e{0.2, -0.3, 1.0};
  const Eigen::Vector3d w_B(0.1, -0.2, 0.3);
  const double dt = 1e-6;
  const Eigen::Matrix3d R0 = RotationNBFromEuler(e);
  const Eigen::Matrix3d R1 = R0 * Eigen::AngleAxisd(w_B.norm() * dt, w_B.normalized()).toRotationMatrix();
  const EulerAngles e1 = EulerFromRotationNB(R1);
  const Eigen::Vector3d rate((e1.phi - e.phi) / dt, (e1.theta - e.theta) / dt, (e1.psi - e.psi) / dt);
  const Eigen::Vector3d expected = EulerRateFromBodyRate(e.phi, e.theta) * w_B;
  EXPECT_NEAR(rate.x(), expected.x(), 1e-5);
  EXPECT_NEAR(rate.y(), expected.y(), 1e-5);
  EXPECT_NEAR(rate.z(), expected.z(), 1e-5);
  // Hand value at zero attitude: Gamma is the identity.
  EXPECT_TRUE(EulerRateFromBodyRate(0, 0).isApprox(Eigen::Matrix3d::Identity()));
}

TEST(Frames, WrapAngle) {
  EXPECT_NEAR(WrapAngle(3 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(-M_PI), M_PI, 1e-12);
  EXPECT_NEAR(WrapAngle(2 * M_PI + 0.1), 0.1, 1e-12);
  EXPECT_NEAR(WrapAngle(-0.1), -0.1, 1e-12);
}

}  // namespace
}  // namespace uav
