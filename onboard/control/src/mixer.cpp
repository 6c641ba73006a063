#include "uav/control/mixer.hpp"

#include <algorithm>
#include <cmath>

namespace uav::control {

std::array<double, 4> MixToRotors(const ServoCommand& s) {
  const double th = s.throttle, a = s.aileron, e = s.elevator, r = s.rudder;
  // Inverse of Eq. 2.11 with thrust linear in the input (Eq. 2.13).
  std::array<double, 4> m = {th - a + e + r, th + a + e - r, th + a - e + r, th - a - e - r};
  for (double v : m)
    if (!std::isfinite(v)) return {-1.0, -1.0, -1.0, -1.0};  // never pass NaN to the motors
  const double top = *std::max_element(m.begin(), m.end());
  if (top > 1.0)
    for (double& v : m) v -= top - 1.0;
  for (double& v : m) v = std::clamp(v, -1.0, 1.0);
  return m;
}

}  // namespace uav::control
