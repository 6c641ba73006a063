#pragma once
// U-Lion simulated behind the VehicleBackend interface: the tail-sitter model
// (tailsitter_model.hpp) driven by the servo board's eight channels (airframe::FromChannels), wind
// and gusts, a battery drained by the rotor's power (momentum theory), the INS box's sensors and
// a pitot tube along x_B. Stands upright on its tail at home, the belly toward north.
// Thread-safe: the sim driver steps it while the IMU and SVO threads read and write it.
#include <mutex>

#include "uav/airframe/tailsitter_aero.hpp"
#include "uav/sim/sim_sensors.hpp"
#include "uav/sim/simulated_vehicle.hpp"
#include "uav/sim/tailsitter_model.hpp"
#include "uav/sim/wind_model.hpp"

namespace uav::sim {

class SimTailSitter : public SimulatedVehicle {
 public:
  SimTailSitter(const ParameterSet& params, const GeodeticPoint& home, int64_t start_utime);

  void Step(int64_t dt_us) override;
  hal::SensorSample ReadSensors() override;
  void WriteOutputs(const hal::OutputChannels& channels) override;
  BodyTruth Truth() const override;
  Eigen::Vector3d TruthWind_N() const override;
  int64_t utime() const override;
  void SetGpsEnabled(bool enabled) override;
  void SetRc(const std::array<double, 4>& sticks, bool manual) override;

  TailSitterState TruthState() const;
  TailSitterAirData TruthAirData() const;
  const TailSitterModel& model() const { return model_; }

 private:
  mutable std::mutex mutex_;
  TailSitterModel model_;
  airframe::PowerModel power_;
  double battery_capacity_ah_, voltage_full_, voltage_empty_;
  SimSensors sensors_;
  WindModel wind_;
  TailSitterState state_;
  TailSitterInputs inputs_;
  bool on_ground_ = true;
  ImuDeltas imu_;
  double battery_used_ah_ = 0.0;
  int64_t utime_;
  std::array<double, 4> rc_sticks_ = {0, 0, -1, 0};
  bool rc_manual_ = false;
};

}  // namespace uav::sim
