#include "uav/sim/sim_vehicle.hpp"

#include <algorithm>
#include <cmath>

namespace uav::sim {

BatteryParams BatteryParams::FromParameters(const ParameterSet& p) {
  return {p.Get("battery_capacity"), p.Get("battery_voltage_full"), p.Get("battery_voltage_empty"),
          p.Get("battery_hover_current"), p.Get("battery_idle_current")};
}

SimVehicle::SimVehicle(const ParameterSet& params, const GeodeticPoint& home, int64_t start_utime)
    : model_(QuadrotorParams::FromParameters(params)),
      battery_(BatteryParams::FromParameters(params)),
      frame_(home),
      sensors_(SensorParams::FromParameters(params), home, static_cast<uint64_t>(params.Get("sim_seed"))),
      wind_(WindParams::FromParameters(params), static_cast<uint64_t>(params.Get("sim_seed"))),
      utime_(start_utime) {
  outputs_.fill(-1.0);
  state_.rotor.fill(-1.0);
}

void SimVehicle::Step(int64_t dt_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double dt = dt_us * 1e-6;
  // Dead time of the gyro in hover mode: the outputs of `delay` ago drive roll and pitch.
  const auto delay_steps = static_cast<std::size_t>(std::lround(model_.params().gyro.hover_delay / dt));
  output_history_.push_back(outputs_);
  while (output_history_.size() > delay_steps + 1) output_history_.pop_front();
  const Eigen::Vector3d wind_N = wind_.Step(dt);
  on_ground_ = model_.Step(state_, outputs_, output_history_.front(), wind_N, dt);
  // Battery: current grows with thrust^1.5 (momentum theory: power ~ T^(3/2)).
  const auto& q = model_.params();
  double thrust = 0.0;
  for (double r : state_.rotor) thrust += model_.RotorThrust(r);
  const double load = thrust / (q.mass * q.gravity);
  const double current = battery_.idle_current + battery_.hover_current * std::pow(load, 1.5);
  battery_used_ah_ += current * dt / 3600.0;
  utime_ += dt_us;
}

void SimVehicle::SetRc(const std::array<double, 4>& sticks, bool manual) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int i = 0; i < 4; ++i) rc_sticks_[i] = std::clamp(sticks[i], -1.0, 1.0);
  rc_manual_ = manual;
}

hal::SensorSample SimVehicle::ReadSensors() {
  std::lock_guard<std::mutex> lock(mutex_);
  hal::SensorSample s;
  s.utime = utime_;
  s.rc_sticks = rc_sticks_;
  s.rc_manual = rc_manual_;
  const double g = model_.params().gravity;
  ImuDeltas::Reading first;  // on the ground the legs carry the weight
  first.f_B = on_ground_ ? Eigen::Vector3d(state_.q_NB.conjugate() * Eigen::Vector3d(0, 0, -g))
                         : model_.SpecificForceB(state_, wind_.wind_N());
  first.w_B = state_.w_B;
  const ImuDeltas::Reading imu = imu_.Measure(utime_, state_.q_NB * state_.v_B, state_.q_NB, g, first);
  QuadrotorState measured = state_;
  measured.w_B = imu.w_B;
  sensors_.Sample(utime_, measured, imu.f_B, &s);
  const double remaining =
      std::clamp(1.0 - battery_used_ah_ / battery_.capacity_ah, 0.0, 1.0);
  s.battery_remaining = remaining;
  s.battery_voltage_v =
      battery_.voltage_empty + remaining * (battery_.voltage_full - battery_.voltage_empty);
  return s;
}

void SimVehicle::WriteOutputs(const hal::OutputChannels& channels) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int i = 0; i < 4; ++i)
    outputs_[i] = std::isfinite(channels[i]) ? std::clamp(channels[i], -1.0, 1.0) : -1.0;
}

Eigen::Vector3d SimVehicle::TruthWind_N() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return wind_.wind_N();
}

Eigen::Vector3d SimVehicle::GpsError_N() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sensors_.gps_error_N();
}

BodyTruth SimVehicle::Truth() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return {state_.p_N, state_.q_NB * state_.v_B, state_.q_NB, state_.w_B};
}

void SimVehicle::SetGpsEnabled(bool enabled) {
  std::lock_guard<std::mutex> lock(mutex_);
  sensors_.SetGpsEnabled(enabled);
}

QuadrotorState SimVehicle::TruthState() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return state_;
}

int64_t SimVehicle::utime() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return utime_;
}

}  // namespace uav::sim
