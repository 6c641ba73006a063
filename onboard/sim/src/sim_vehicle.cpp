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
      utime_(start_utime) {
  rotor_cmd_.fill(-1.0);
  state_.rotor.fill(-1.0);
}

void SimVehicle::Step(int64_t dt_us) {
  std::lock_guard<std::mutex> lock(mutex_);
  const double dt = dt_us * 1e-6;
  model_.Step(state_, rotor_cmd_, wind_N_, dt);
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
  s.p_N = state_.p_N;
  s.v_N = state_.q_NB * state_.v_B;
  s.q_NB = state_.q_NB;
  s.w_B = state_.w_B;
  s.f_B = model_.SpecificForceB(state_, wind_N_);
  s.gps = frame_.ToGeodetic(state_.p_N);
  s.gps_fix = 3;
  s.gps_satellites = 12;
  const double remaining =
      std::clamp(1.0 - battery_used_ah_ / battery_.capacity_ah, 0.0, 1.0);
  s.battery_remaining = remaining;
  s.battery_voltage_v =
      battery_.voltage_empty + remaining * (battery_.voltage_full - battery_.voltage_empty);
  return s;
}

void SimVehicle::WriteRotors(const std::array<double, 4>& rotor_inputs) {
  std::lock_guard<std::mutex> lock(mutex_);
  for (int i = 0; i < 4; ++i)
    rotor_cmd_[i] = std::isfinite(rotor_inputs[i]) ? std::clamp(rotor_inputs[i], -1.0, 1.0) : -1.0;
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
