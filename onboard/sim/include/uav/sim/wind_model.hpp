#pragma once
// Wind over the simulated vehicle (thesis 2.2: "urban canyons frequently have large drafts"):
// a steady wind, turbulence (first-order Gauss-Markov per axis, a Dryden-like spectrum), and
// urban drafts (1-cos gusts at Poisson-distributed times along a random horizontal direction).
#include <cstdint>
#include <random>

#include <Eigen/Core>

#include "uav/shared/parameters.hpp"

namespace uav::sim {

struct WindParams {
  double speed;               // [m/s] steady wind
  double direction;           // [rad] where it comes from, clockwise from north
  double turbulence;          // turbulence 1 sigma per horizontal axis / speed (vertical: half)
  double turbulence_time;     // [s] correlation time
  double gust;                // draft peak / speed
  double gust_duration;       // [s]
  double gust_interval;       // [s] mean time between drafts
  static WindParams FromParameters(const ParameterSet& p);
};

class WindModel {
 public:
  WindModel(const WindParams& params, uint64_t seed);
  // Advances by dt [s]; returns the air's velocity in N [m/s].
  Eigen::Vector3d Step(double dt);
  const Eigen::Vector3d& wind_N() const { return wind_N_; }
  // The steady part alone [m/s].
  Eigen::Vector3d steady_N() const;

 private:
  WindParams p_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> normal_{0.0, 1.0};
  Eigen::Vector3d turbulence_N_ = Eigen::Vector3d::Zero();
  double next_gust_in_ = 0.0;  // [s] until the next draft starts
  double gust_age_ = -1.0;     // [s] into the current draft; < 0: none
  Eigen::Vector3d gust_dir_N_ = Eigen::Vector3d::UnitX();
  Eigen::Vector3d wind_N_ = Eigen::Vector3d::Zero();
};

}  // namespace uav::sim
