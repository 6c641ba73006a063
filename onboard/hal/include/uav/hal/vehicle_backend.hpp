#pragma once
// What the onboard threads see of the vehicle (thesis 2.3.2): the IMU thread reads sensors, the
// SVO thread writes actuators. A simulator and, later, hardware drivers implement it.
#include <array>
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/shared/geodesy.hpp"

namespace uav::hal {

struct SensorSample {
  int64_t utime = 0;  // [us] time of the sample on the vehicle clock
  // Navigation solution of the INS box (thesis 2.3.2: the ArduIMU outputs fused attitude).
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();   // [m] NED from home
  Eigen::Vector3d v_N = Eigen::Vector3d::Zero();   // [m/s]
  Eigen::Quaterniond q_NB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();   // [rad/s] gyro
  Eigen::Vector3d f_B = Eigen::Vector3d::Zero();   // [m/s^2] accelerometer specific force
  GeodeticPoint gps;                               // GPS receiver fix
  int gps_fix = 0;                                 // 0 none, 3 3-D
  int gps_satellites = 0;
  double battery_voltage_v = 0.0;
  double battery_remaining = 0.0;                  // [0..1]
  // RC receiver (PPM read by the IMU board): aileron, elevator, throttle, rudder in -1..1,
  // and the fail-safe switch channel (true = pilot has control).
  std::array<double, 4> rc_sticks = {0, 0, 0, 0};
  bool rc_manual = false;
};

class VehicleBackend {
 public:
  virtual ~VehicleBackend() = default;
  virtual SensorSample ReadSensors() = 0;
  // Normalised rotor inputs M_1..M_4 in -1..1 (thesis Table 2.3); values outside are clamped.
  virtual void WriteRotors(const std::array<double, 4>& rotor_inputs) = 0;
};

}  // namespace uav::hal
