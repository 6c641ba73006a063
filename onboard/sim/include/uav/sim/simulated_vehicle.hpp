#pragma once
// What the simulator's driver (app::SimFlight) needs of a simulated vehicle besides the backend
// the flight stack sees: stepping its physics, the truth the cameras render from and the tests
// score against, and the simulator's faults and RC transmitter. The X650 quadrotor (SimVehicle)
// and U-Lion (SimTailSitter) implement it; the vehicle file's vehicle_type picks one
// (MakeSimulatedVehicle).
#include <array>
#include <cstdint>
#include <memory>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "uav/hal/vehicle_backend.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/parameters.hpp"

namespace uav::sim {

// The rigid body's true state. Frames: N (NED, origin at home), B the vehicle's body frame.
struct BodyTruth {
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // [m]
  Eigen::Vector3d v_N = Eigen::Vector3d::Zero();  // [m/s]
  Eigen::Quaterniond q_NB = Eigen::Quaterniond::Identity();
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();  // [rad/s]
};

class SimulatedVehicle : public hal::VehicleBackend {
 public:
  // Advances the simulation by dt_us on the simulated clock.
  virtual void Step(int64_t dt_us) = 0;
  // Ground truth, for the cameras, the tests and the simulator's own logging; never for the
  // flight stack.
  virtual BodyTruth Truth() const = 0;
  virtual Eigen::Vector3d TruthWind_N() const = 0;
  virtual int64_t utime() const = 0;
  // Simulator fault: the GPS receiver loses (false) or regains (true) its fix.
  virtual void SetGpsEnabled(bool enabled) = 0;
  // The simulated RC transmitter: sticks (aileron, elevator, throttle, rudder in -1..1) and the
  // fail-safe switch (true: the pilot flies).
  virtual void SetRc(const std::array<double, 4>& sticks, bool manual) = 0;
};

// The vehicle the file describes (vehicle_type 0: the X650 quadrotor, 1: U-Lion), on the ground
// at home. Throws std::invalid_argument naming a bad entry.
std::unique_ptr<SimulatedVehicle> MakeSimulatedVehicle(const ParameterSet& params, const GeodeticPoint& home,
                                                       int64_t start_utime);

}  // namespace uav::sim
