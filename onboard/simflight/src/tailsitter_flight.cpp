#include "uav/simflight/tailsitter_flight.hpp"

#include <algorithm>
#include <cmath>

namespace uav::simflight {

namespace {
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

control::TailSitterControlParams ControlParams(const ParameterSet& vehicle, control::TransitionSchedule schedule) {
  control::TailSitterControlParams p = control::TailSitterControlParams::FromParameters(vehicle);
  p.schedule = schedule;
  return p;
}
}  // namespace

airframe::TailSitterParams VariedPlant(const airframe::TailSitterParams& nominal, const TailSitterVariation& v) {
  airframe::TailSitterParams p = nominal;
  p.mass_kg *= v.mass_scale;
  p.thrust_max_n *= v.thrust_scale;
  p.wing_coefficients.section_lift_slope_per_rad *= v.aero_scale;
  p.wing_coefficients.normal_force_at_90 = std::min(2.1, p.wing_coefficients.normal_force_at_90 * v.aero_scale);
  p.wing_coefficients.profile_drag *= v.aero_scale;
  return p;
}

TailSitterFlight::TailSitterFlight(const ParameterSet& vehicle, const TailSitterVariation& variation,
                                   control::TransitionSchedule schedule)
    : model_(VariedPlant(airframe::TailSitterParams::FromParameters(vehicle), variation)),
      controller_(ControlParams(vehicle, schedule)),
      wind_(sim::WindParams::FromParameters(vehicle), static_cast<uint64_t>(vehicle.Get("sim_seed"))) {
  PlaceOnGround(0.0);
}

void TailSitterFlight::PlaceOnGround(double heading) {
  state_ = sim::TailSitterState::UprightOnGround(heading);
  state_.battery_m = model_.params().battery_travel_m;
}

void TailSitterFlight::PlaceInHover(const Eigen::Vector3d& p_N, double heading) {
  PlaceOnGround(heading);
  state_.p_N = p_N;
  state_.thrust_n = model_.params().mass_kg * model_.params().gravity;
}

double TailSitterFlight::airspeed() const { return model_.AirData(state_, wind_.wind_N()).airspeed_mps; }

hal::VehicleEstimate TailSitterFlight::Estimate() const {
  hal::VehicleEstimate est;
  est.utime = static_cast<int64_t>(t_ * 1e6);
  est.p_N = state_.p_N;
  est.p_O = state_.p_N;
  est.q_NB = state_.q_NB;
  est.v_N = state_.q_NB * state_.v_B;
  est.w_B = state_.w_B;
  return est;
}

std::string TailSitterFlight::StartTransition(bool to_wing) { return controller_.StartTransition(to_wing, Estimate()); }

void TailSitterFlight::Step(const control::TailSitterSetpoint& sp) {
  airframe::TailSitterInputs u = controller_.Update(Estimate(), airspeed(), sp, kControlPeriod);
  u.thrust *= rotor_health_;
  const double h = kControlPeriod / kSubsteps;
  for (int i = 0; i < kSubsteps; ++i) model_.Step(state_, u, wind_.Step(h), h);
  t_ += kControlPeriod;
  const sim::TailSitterAirData air = model_.AirData(state_, wind_.wind_N());
  const Eigen::Matrix3d R = state_.q_NB.toRotationMatrix();
  TailSitterSample s;
  s.t_s = t_;
  s.mode = controller_.mode();
  s.p_N = state_.p_N;
  s.altitude_m = altitude();
  s.airspeed_mps = air.airspeed_mps;
  s.ground_speed_mps = (state_.q_NB * state_.v_B).head<2>().norm();
  s.pitch_deg = std::asin(std::clamp(-R(2, 0), -1.0, 1.0)) * kRadToDeg;
  s.pitch_setpoint_deg = controller_.pitch_setpoint() * kRadToDeg;
  s.alpha_deg = air.alpha_rad * kRadToDeg;
  s.thrust_n = state_.thrust_n;
  s.wing_lift_n = model_.Forces(state_, wind_.wind_N()).wing_lift_n;
  samples_.push_back(s);
}

bool TailSitterFlight::Fly(const control::TailSitterSetpoint& sp, double seconds, const std::function<bool()>& done) {
  const double end = t_ + seconds;
  while (t_ < end - 1e-9) {
    Step(sp);
    if (done && done()) return true;
  }
  return false;
}

}  // namespace uav::simflight
