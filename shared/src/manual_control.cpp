#include "uav/shared/manual_control.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace uav {

void ValidateSticks(const ManualSticks& s) {
  const struct {
    const char* name;
    double value;
  } axes[] = {{"forward", s.forward}, {"right", s.right}, {"up", s.up}, {"yaw", s.yaw}};
  for (const auto& a : axes)
    if (!std::isfinite(a.value) || std::abs(a.value) > 1.0)
      throw std::invalid_argument(std::string("stick ") + a.name + " = " + std::to_string(a.value) +
                                  " is not a number in [-1, 1]");
}

}  // namespace uav
