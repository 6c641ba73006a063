#pragma once
// The simulated vehicle behind the VehicleBackend interface: quadrotor model (with the gyro in
// the loop when the vehicle file says so), wind, battery and the INS box's sensors. Thread-safe:
// the sim driver steps it while the IMU and SVO threads read and write it.
#include <array>
#include <deque>
#include <mutex>

#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/quadrotor_model.hpp"
#include "uav/sim/sim_sensors.hpp"
#include "uav/sim/wind_model.hpp"

namespace uav::sim {

struct BatteryParams {
  double capacity_ah, voltage_full, voltage_empty, hover_current, idle_current;
  static BatteryParams FromParameters(const ParameterSet& p);
};

class SimVehicle : public hal::VehicleBackend {
 public:
  SimVehicle(const ParameterSet& params, const GeodeticPoint& home, int64_t start_utime);

  // Advances the simulation by dt_us on the simulated clock.
  void Step(int64_t dt_us);

  hal::SensorSample ReadSensors() override;
  void WriteOutputs(const std::array<double, 4>& channels) override;

  // The simulated RC transmitter: sticks (aileron, elevator, throttle, rudder in -1..1) and the
  // fail-safe switch (true: the pilot flies).
  void SetRc(const std::array<double, 4>& sticks, bool manual);

  // Ground truth, for tests and the simulator's own logging; never for the flight stack.
  QuadrotorState TruthState() const;
  Eigen::Vector3d TruthWind_N() const;
  // The error of the latest GPS fix [m], truth to fix, in N.
  Eigen::Vector3d GpsError_N() const;
  int64_t utime() const;
  const QuadrotorModel& model() const { return model_; }
  const SimSensors& sensors() const { return sensors_; }
  // Simulator fault: the GPS receiver loses (false) or regains (true) its fix.
  void SetGpsEnabled(bool enabled) { sensors_.SetGpsEnabled(enabled); }

 private:
  mutable std::mutex mutex_;
  QuadrotorModel model_;
  BatteryParams battery_;
  LocalNedFrame frame_;
  SimSensors sensors_;
  WindModel wind_;
  QuadrotorState state_;
  bool on_ground_ = true;
  // The IMU integrates between samples (as a MEMS IMU's filter and the ArduIMU's oversampling
  // do): the velocity and attitude at the previous sample give the mean specific force and rate.
  int64_t last_read_utime_ = -1;
  Eigen::Vector3d last_read_v_N_ = Eigen::Vector3d::Zero();
  Eigen::Quaterniond last_read_q_NB_ = Eigen::Quaterniond::Identity();
  std::array<double, 4> outputs_;
  // Outputs of the last gyro_hover_delay, oldest first (Eq. 2.17-2.18 dead time).
  std::deque<std::array<double, 4>> output_history_;
  double battery_used_ah_ = 0.0;
  int64_t utime_;
  std::array<double, 4> rc_sticks_ = {0, 0, -1, 0};
  bool rc_manual_ = false;
};

}  // namespace uav::sim
