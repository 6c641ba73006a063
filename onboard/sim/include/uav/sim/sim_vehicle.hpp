#pragma once
// The simulated X650 behind the VehicleBackend interface: quadrotor model (with the gyro in
// the loop when the vehicle file says so), wind, battery and the INS box's sensors. Thread-safe:
// the sim driver steps it while the IMU and SVO threads read and write it.
#include <array>
#include <deque>
#include <mutex>

#include "uav/hal/vehicle_backend.hpp"
#include "uav/sim/simulated_vehicle.hpp"
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

class SimVehicle : public SimulatedVehicle {
 public:
  SimVehicle(const ParameterSet& params, const GeodeticPoint& home, int64_t start_utime);

  void Step(int64_t dt_us) override;
  hal::SensorSample ReadSensors() override;
  // The first four channels (rotors or the gyro's inputs); the others are not wired.
  void WriteOutputs(const hal::OutputChannels& channels) override;
  void SetRc(const std::array<double, 4>& sticks, bool manual) override;
  BodyTruth Truth() const override;
  Eigen::Vector3d TruthWind_N() const override;
  int64_t utime() const override;
  void SetGpsEnabled(bool enabled) override;

  // Ground truth with the rotors' state, for tests; never for the flight stack.
  QuadrotorState TruthState() const;
  // The error of the latest GPS fix [m], truth to fix, in N.
  Eigen::Vector3d GpsError_N() const;
  const QuadrotorModel& model() const { return model_; }
  const SimSensors& sensors() const { return sensors_; }

 private:
  mutable std::mutex mutex_;
  QuadrotorModel model_;
  BatteryParams battery_;
  LocalNedFrame frame_;
  SimSensors sensors_;
  WindModel wind_;
  QuadrotorState state_;
  bool on_ground_ = true;
  ImuDeltas imu_;
  std::array<double, 4> outputs_;
  // Outputs of the last gyro_hover_delay, oldest first (Eq. 2.17-2.18 dead time).
  std::deque<std::array<double, 4>> output_history_;
  double battery_used_ah_ = 0.0;
  int64_t utime_;
  std::array<double, 4> rc_sticks_ = {0, 0, -1, 0};
  bool rc_manual_ = false;
};

}  // namespace uav::sim
