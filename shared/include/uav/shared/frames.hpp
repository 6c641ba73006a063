#pragma once
#include <optional>
// Frames and rotations. Conventions (DESIGN.md 4): N = local North-East-Down, B = body
// forward-right-down. Angles in radians.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace uav {

// Roll, pitch, yaw of R_NB in z-y-x order: R_NB = Rz(psi) Ry(theta) Rx(phi) (thesis Eq. 5.51).
struct EulerAngles {
  double phi = 0.0;    // roll  [rad]
  double theta = 0.0;  // pitch [rad]
  double psi = 0.0;    // yaw   [rad]
};

// Rotation taking body-frame vectors to N: v_N = R_NB * v_B (thesis Eq. 2.2, Eq. 5.51).
// Note: the (1,3) entry of Eq. 2.2 as printed in the thesis repeats s_phi where c_phi belongs
// (c_psi s_theta c_phi + s_psi s_phi); this is the correct product Rz*Ry*Rx.
Eigen::Matrix3d RotationNBFromEuler(const EulerAngles& e);

// Inverse of RotationNBFromEuler for theta in (-pi/2, pi/2); psi and phi in (-pi, pi].
EulerAngles EulerFromRotationNB(const Eigen::Matrix3d& R_NB);

// Earth's field in N, unit strength, dipping `inclination_rad` below the horizon toward
// magnetic north (taken as true north). What the simulated magnetometer reads and the INS expects.
Eigen::Vector3d MagneticField_N(double inclination_rad);

// The rotation R_NB that takes two directions measured in B onto their known values in N
// (TRIAD): the first pair exactly, the second as nearly as the first allows. Any attitude,
// nose-up included. Returns nullopt when either pair is (nearly) parallel or zero.
std::optional<Eigen::Matrix3d> TriadRotationNB(const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N,
                                               const Eigen::Vector3d& a_B, const Eigen::Vector3d& b_B);

// Gamma of thesis Eq. 2.3: d/dt(phi, theta, psi) = Gamma(phi, theta) * w_B. Singular at
// theta = +-pi/2, which is why the simulator integrates a quaternion instead.
Eigen::Matrix3d EulerRateFromBodyRate(double phi, double theta);

// A forward-looking camera in the body frame (thesis Eq. 5.48): x_C = right (y_B), y_C = down
// (z_B), z_C = forward (x_B). Mounts pitched down are Ry(pitch) times this.
Eigen::Matrix3d RotationBCForward();

// Wraps an angle to (-pi, pi].
double WrapAngle(double a);

}  // namespace uav
