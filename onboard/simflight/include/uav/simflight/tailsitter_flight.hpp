#pragma once
// U-Lion flown closed loop on the simulated clock: the 6-DOF model (sim/tailsitter_model.hpp),
// wind as for the quadrotor, and the tail-sitter controller at the flight stack's 50 Hz. The
// controller is fed the true state and an air-data probe's airspeed; the plant may differ from
// the controller's model (mass, thrust, aerodynamic coefficients) as a Monte-Carlo run draws it.
// What the transition tests and uav-ulion-bench fly.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/control/tailsitter_controller.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/sim/tailsitter_model.hpp"
#include "uav/sim/wind_model.hpp"

namespace uav::simflight {

// How the flown airframe differs from the vehicle file the controller knows.
struct TailSitterVariation {
  double mass_scale = 1.0;    // total mass
  double thrust_scale = 1.0;  // the rotor's thrust at full command
  double aero_scale = 1.0;    // the wing's lift slope, flat-plate normal force and profile drag
};

struct TailSitterSample {
  double t_s = 0;
  control::TailSitterMode mode = control::TailSitterMode::kHover;
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();
  double altitude_m = 0, airspeed_mps = 0, ground_speed_mps = 0;
  double pitch_deg = 0, pitch_setpoint_deg = 0;  // nose elevation above the horizon
  double alpha_deg = 0, thrust_n = 0, wing_lift_n = 0;
};

class TailSitterFlight {
 public:
  static constexpr double kControlPeriod = 0.02;  // 50 Hz (thesis 2.3.2)
  static constexpr int kSubsteps = 5;              // physics at 250 Hz

  // Throws std::invalid_argument naming a bad entry of the vehicle file.
  TailSitterFlight(const ParameterSet& vehicle, const TailSitterVariation& variation = {},
                   control::TransitionSchedule schedule = control::TransitionSchedule::kLiftLimited);

  // Standing on its tail at the origin, the belly toward `heading`.
  void PlaceOnGround(double heading_rad);
  // Hovering at `p_N`, trimmed (thrust = weight), the belly toward `heading`.
  void PlaceInHover(const Eigen::Vector3d& p_N, double heading_rad);
  // One control period toward `sp`.
  void Step(const control::TailSitterSetpoint& sp);
  // Steps until `done` is true or `seconds` pass; returns whether `done` came true.
  bool Fly(const control::TailSitterSetpoint& sp, double seconds, const std::function<bool()>& done = {});
  // Simulator fault: the rotor gives this fraction of the thrust commanded (a failing ESC or
  // motor); 1 is healthy.
  void SetRotorHealth(double fraction) { rotor_health_ = fraction; }
  // "" or the controller's reason for refusing.
  std::string StartTransition(bool to_wing);

  const sim::TailSitterState& truth() const { return state_; }
  const control::TailSitterController& controller() const { return controller_; }
  const sim::TailSitterModel& model() const { return model_; }
  Eigen::Vector3d wind_N() const { return wind_.wind_N(); }
  double time() const { return t_; }
  double altitude() const { return -state_.p_N.z(); }
  double airspeed() const;
  const std::vector<TailSitterSample>& samples() const { return samples_; }
  hal::VehicleEstimate Estimate() const;

 private:
  sim::TailSitterModel model_;
  control::TailSitterController controller_;
  sim::WindModel wind_;
  sim::TailSitterState state_;
  double t_ = 0;
  double rotor_health_ = 1.0;
  std::vector<TailSitterSample> samples_;
};

// The plant a variation describes, from the vehicle file's.
airframe::TailSitterParams VariedPlant(const airframe::TailSitterParams& nominal, const TailSitterVariation& v);

}  // namespace uav::simflight
