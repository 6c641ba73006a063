#pragma once
// Figures of a vehicle's flight envelope that both the flight stack and the GCS's planners use.
#include <cmath>

namespace uav {

// The radius of a level coordinated turn [m] at `speed_m_s` and bank `bank_rad`: r = v^2 / (g tan phi).
inline double CoordinatedTurnRadius(double speed_m_s, double bank_rad, double gravity_m_s2) {
  return speed_m_s * speed_m_s / (gravity_m_s2 * std::tan(bank_rad));
}

}  // namespace uav
