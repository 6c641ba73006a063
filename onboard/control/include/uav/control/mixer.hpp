#pragma once
// Servo-style channels to rotor inputs for the cross-style quadrotor (thesis Eq. 2.11).
#include <array>

namespace uav::control {

// The four autopilot channels, normalised like the RC sticks of thesis Table 2.3:
// throttle u_th is the common rotor input (hover trim 0.18, Table 2.4); aileron u_a, elevator
// u_e and rudder u_r are differential rotor inputs producing roll, pitch and yaw torque.
struct ServoCommand {
  double aileron = 0.0;   // u_a
  double elevator = 0.0;  // u_e
  double throttle = -1.0; // u_th
  double rudder = 0.0;    // u_r
};

// Rotor 1 front-right, 2 front-left, 3 rear-left, 4 rear-right. Each unit of u_a gives
// 4*K_f*l*sqrt(2)/2 of roll torque, u_e the same in pitch, u_r 4*d*K_v of yaw torque.
// When a rotor would exceed 1 all are lowered together so that attitude keeps priority over
// climb; the result is clamped to [-1, 1].
std::array<double, 4> MixToRotors(const ServoCommand& s);

}  // namespace uav::control
