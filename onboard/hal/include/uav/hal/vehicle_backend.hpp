#pragma once
// What the onboard threads see of the vehicle (thesis 2.3.2): the IMU thread reads the raw
// sensors of the INS box (IMU, GPS, barometer, sonar, and on a winged vehicle the pitot) and the
// RC receiver; the SVO thread writes the servo board's output channels. A simulator and, later,
// hardware drivers implement it.
#include <array>
#include <cmath>
#include <cstdint>

#include <Eigen/Core>

#include "uav/shared/geodesy.hpp"

namespace uav::hal {

// One 50 Hz sample of every sensor (thesis 2.3.2). Slow sensors repeat their latest reading and
// say when it was taken, so the INS uses each reading once.
struct SensorSample {
  int64_t utime = 0;  // [us] time of the sample on the vehicle clock
  // IMU (ArduIMU): body frame B (FRD).
  Eigen::Vector3d gyro_B = Eigen::Vector3d::Zero();   // [rad/s] angular rate
  Eigen::Vector3d accel_B = Eigen::Vector3d::Zero();  // [m/s^2] specific force (gravity excluded)
  Eigen::Vector3d mag_B = Eigen::Vector3d::UnitX();   // [1] Earth's field, unit strength
  // GPS receiver (u-blox): WGS84 fix and Doppler velocity in N (NED).
  int64_t gps_utime = 0;  // [us] time of the latest fix; 0: none yet
  GeodeticPoint gps;
  Eigen::Vector3d gps_v_N = Eigen::Vector3d::Zero();  // [m/s]
  int gps_fix = 0;                                    // 0 none, 3 3-D
  int gps_satellites = 0;
  // Barometric altitude above the pressure at power-on [m], every sample.
  double baro_alt_m = 0.0;
  // Downward sonar: slant range to the ground along SonarBeam_B [m]; sonar_valid false out of
  // range.
  int64_t sonar_utime = 0;
  double sonar_range_m = 0.0;
  bool sonar_valid = false;
  // Pitot tube along x_B (a winged vehicle's air-data probe): the airspeed it reads [m/s];
  // airspeed_valid false on a vehicle without one.
  double airspeed_mps = 0.0;
  bool airspeed_valid = false;
  double battery_voltage_v = 0.0;
  double battery_remaining = 0.0;                  // [0..1]
  // RC receiver (PPM read by the IMU board): aileron, elevator, throttle, rudder in -1..1,
  // and the fail-safe switch channel (true = pilot has control).
  std::array<double, 4> rc_sticks = {0, 0, 0, 0};
  bool rc_manual = false;
};

// The sonar's beam in B, unit: +z_B (down on a level multicopter) pitched by the vehicle file's
// `sonar_mount_pitch` [rad] toward +x_B; -pi/2 points it along the tail, down when a tail-sitter
// stands or hovers upright.
inline Eigen::Vector3d SonarBeam_B(double mount_pitch_rad) {
  return {std::sin(mount_pitch_rad), 0.0, std::cos(mount_pitch_rad)};
}

// The servo board's output channels, each in -1..1 (-1 also: a channel not wired). The quadrotor
// uses the first four: the rotors M_1..M_4 directly, or the gyro's aileron, elevator, throttle and
// rudder inputs (VehicleParams::attitude_mode; thesis 2.5, Fig. 2.21). U-Lion uses all eight
// (airframe::ToChannels in tailsitter_params.hpp).
constexpr int kOutputChannels = 8;
using OutputChannels = std::array<double, kOutputChannels>;
inline OutputChannels UnwiredChannels() {
  OutputChannels c;
  c.fill(-1.0);
  return c;
}

class VehicleBackend {
 public:
  virtual ~VehicleBackend() = default;
  virtual SensorSample ReadSensors() = 0;
  // Values outside -1..1 are clamped; a non-finite value is taken as -1 (off).
  virtual void WriteOutputs(const OutputChannels& channels) = 0;
};

}  // namespace uav::hal
