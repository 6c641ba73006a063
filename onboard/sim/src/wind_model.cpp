#include "uav/sim/wind_model.hpp"

#include <cmath>

namespace uav::sim {

WindParams WindParams::FromParameters(const ParameterSet& p) {
  return {p.Get("wind_speed"),           p.Get("wind_direction"), p.Get("wind_turbulence"),
          p.Get("wind_turbulence_time"), p.Get("wind_gust"),      p.Get("wind_gust_duration"),
          p.Get("wind_gust_interval")};
}

WindModel::WindModel(const WindParams& params, uint64_t seed) : p_(params), rng_(seed ^ 0x57494e44ull) {
  std::exponential_distribution<double> wait(1.0 / p_.gust_interval);
  next_gust_in_ = wait(rng_);
  wind_N_ = steady_N();
}

Eigen::Vector3d WindModel::steady_N() const {
  // Wind from the north (direction 0) blows towards the south.
  return -p_.speed * Eigen::Vector3d(std::cos(p_.direction), std::sin(p_.direction), 0.0);
}

Eigen::Vector3d WindModel::Step(double dt) {
  if (p_.speed <= 0.0) return wind_N_ = Eigen::Vector3d::Zero();  // calm air: nothing to draw
  // Turbulence: x' = -x / T + sigma sqrt(2 / T) w, exact discretisation.
  const double sigma = p_.turbulence * p_.speed;
  const double a = std::exp(-dt / p_.turbulence_time);
  const double b = sigma * std::sqrt(1.0 - a * a);
  const Eigen::Vector3d scale(1.0, 1.0, 0.5);
  for (int i = 0; i < 3; ++i) turbulence_N_[i] = a * turbulence_N_[i] + scale[i] * b * normal_(rng_);
  // Urban drafts.
  Eigen::Vector3d gust = Eigen::Vector3d::Zero();
  if (gust_age_ < 0.0) {
    next_gust_in_ -= dt;
    if (next_gust_in_ <= 0.0) {
      gust_age_ = 0.0;
      std::uniform_real_distribution<double> spread(-M_PI / 4, M_PI / 4);  // channelled near the mean wind
      const double heading = p_.direction + M_PI + spread(rng_);
      gust_dir_N_ = Eigen::Vector3d(std::cos(heading), std::sin(heading), 0.0);
    }
  }
  if (gust_age_ >= 0.0) {
    const double peak = p_.gust * p_.speed;
    gust = gust_dir_N_ * peak * 0.5 * (1.0 - std::cos(2.0 * M_PI * gust_age_ / p_.gust_duration));
    gust_age_ += dt;
    if (gust_age_ > p_.gust_duration) {
      gust_age_ = -1.0;
      std::exponential_distribution<double> wait(1.0 / p_.gust_interval);
      next_gust_in_ = wait(rng_);
    }
  }
  return wind_N_ = steady_N() + turbulence_N_ + gust;
}

}  // namespace uav::sim
