#include "uav/sim/sim_tailsitter.hpp"

#include <algorithm>
#include <cmath>

#include "uav/sim/sim_vehicle.hpp"

namespace uav::sim {

SimTailSitter::SimTailSitter(const ParameterSet& params, const GeodeticPoint& home, int64_t start_utime)
    : model_(airframe::TailSitterParams::FromParameters(params)),
      battery_capacity_ah_(params.Get("battery_capacity")),
      voltage_full_(params.Get("battery_voltage_full")),
      voltage_empty_(params.Get("battery_voltage_empty")),
      sensors_(SensorParams::FromParameters(params), home, static_cast<uint64_t>(params.Get("sim_seed"))),
      wind_(WindParams::FromParameters(params), static_cast<uint64_t>(params.Get("sim_seed"))),
      state_(TailSitterState::UprightOnGround(0.0)),
      utime_(start_utime) {
  power_.mass_kg = model_.params().mass_kg;
  // Parked with the battery at the tail (the hover CG) and the rotors stopped.
  state_.battery_m = model_.params().battery_travel_m;
  inputs_.battery = 1.0;
}

void SimTailSitter::Step(int64_t dt_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double dt = dt_us * 1e-6;
  const Eigen::Vector3d wind_N = wind_.Step(dt);
  on_ground_ = model_.Step(state_, inputs_, wind_N, dt);
  // Battery: the rotor's induced power at this thrust and inflow (momentum theory over the
  // figure of merit) plus the useful power T u over the propulsive efficiency, through the
  // motors' and ESCs' efficiency, at the pack's mean voltage.
  const double u = std::max(0.0, model_.AirData(state_, wind_N).air_B.x());
  const double T = state_.thrust_n;
  double electric_w = 0.0;
  if (T > 0.0) {
    const double v_i = airframe::InducedVelocity(T, power_.disk_area_m2, model_.params().air_density, u);
    electric_w = (T * v_i / power_.figure_of_merit + T * u / power_.propulsive_efficiency) / power_.electrical_efficiency;
  }
  battery_used_ah_ += electric_w / (0.5 * (voltage_full_ + voltage_empty_)) * dt / 3600.0;
  utime_ += dt_us;
}

hal::SensorSample SimTailSitter::ReadSensors() {
  std::lock_guard<std::mutex> lock(mutex_);
  hal::SensorSample s;
  s.utime = utime_;
  s.rc_sticks = rc_sticks_;
  s.rc_manual = rc_manual_;
  const double g = model_.params().gravity;
  ImuDeltas::Reading first;  // standing, the tail carries the weight
  first.f_B = state_.q_NB.conjugate() * Eigen::Vector3d(0, 0, -g);
  first.w_B = state_.w_B;
  const ImuDeltas::Reading imu = imu_.Measure(utime_, state_.q_NB * state_.v_B, state_.q_NB, g, first);
  QuadrotorState measured;
  measured.p_N = state_.p_N;
  measured.v_B = state_.v_B;
  measured.q_NB = state_.q_NB;
  measured.w_B = imu.w_B;
  sensors_.Sample(utime_, measured, imu.f_B, &s);
  // The pitot reads the flow along the fuselage; the rotor's slipstream does not reach it (it
  // sits ahead of the propeller disk on the nose boom).
  const TailSitterAirData air = model_.AirData(state_, wind_.wind_N());
  s.airspeed_mps = std::max(0.0, air.air_B.x());
  s.airspeed_valid = true;
  const double remaining = std::clamp(1.0 - battery_used_ah_ / battery_capacity_ah_, 0.0, 1.0);
  s.battery_remaining = remaining;
  s.battery_voltage_v = voltage_empty_ + remaining * (voltage_full_ - voltage_empty_);
  return s;
}

void SimTailSitter::WriteOutputs(const hal::OutputChannels& channels) {
  std::lock_guard<std::mutex> lock(mutex_);
  inputs_ = airframe::FromChannels(channels);
}

BodyTruth SimTailSitter::Truth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {state_.p_N, state_.q_NB * state_.v_B, state_.q_NB, state_.w_B};
}

TailSitterState SimTailSitter::TruthState() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

TailSitterAirData SimTailSitter::TruthAirData() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return model_.AirData(state_, wind_.wind_N());
}

Eigen::Vector3d SimTailSitter::TruthWind_N() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return wind_.wind_N();
}

int64_t SimTailSitter::utime() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return utime_;
}

void SimTailSitter::SetGpsEnabled(bool enabled) {
  std::lock_guard<std::mutex> lock(mutex_);
  sensors_.SetGpsEnabled(enabled);
}

void SimTailSitter::SetRc(const std::array<double, 4>& sticks, bool manual) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int i = 0; i < 4; ++i) rc_sticks_[i] = std::clamp(sticks[i], -1.0, 1.0);
  rc_manual_ = manual;
}

std::unique_ptr<SimulatedVehicle> MakeSimulatedVehicle(const ParameterSet& params, const GeodeticPoint& home,
                                                       int64_t start_utime) {
  if (params.Get("vehicle_type") == 1) return std::make_unique<SimTailSitter>(params, home, start_utime);
  return std::make_unique<SimVehicle>(params, home, start_utime);
}

}  // namespace uav::sim
