#pragma once
// The simulated vehicle behind the VehicleBackend interface: quadrotor model, battery, GPS
// position through GeographicLib. Thread-safe: the sim driver steps it while the IMU and SVO
// threads read and write it.
#include <array>
#include <mutex>

#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/quadrotor_model.hpp"

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
  void WriteRotors(const std::array<double, 4>& rotor_inputs) override;

  // The simulated RC transmitter: sticks (aileron, elevator, throttle, rudder in -1..1) and the
  // fail-safe switch (true: the pilot flies).
  void SetRc(const std::array<double, 4>& sticks, bool manual);

  // Ground truth, for tests and the simulator's own logging; never for the flight stack.
  QuadrotorState TruthState() const;
  int64_t utime() const;
  const QuadrotorModel& model() const { return model_; }

 private:
  mutable std::mutex mutex_;
  QuadrotorModel model_;
  BatteryParams battery_;
  LocalNedFrame frame_;
  QuadrotorState state_;
  std::array<double, 4> rotor_cmd_;
  double battery_used_ah_ = 0.0;
  int64_t utime_;
  Eigen::Vector3d wind_N_ = Eigen::Vector3d::Zero();
  std::array<double, 4> rc_sticks_ = {0, 0, -1, 0};
  bool rc_manual_ = false;
};

}  // namespace uav::sim
