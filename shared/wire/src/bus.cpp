#include "uav/wire/bus.hpp"

#include <stdexcept>

namespace uav {

Bus::Bus(const std::string& url) : url_(url), lcm_(url) {
  if (!lcm_.good()) throw std::runtime_error("cannot start LCM on '" + url + "'");
}

Bus::~Bus() = default;

int Bus::Handle(int timeout_ms) {
  int handled = 0;
  // First wait (up to timeout) for one message, then drain whatever else is already queued.
  int rc = lcm_.handleTimeout(timeout_ms);
  while (rc > 0) {
    ++handled;
    rc = lcm_.handleTimeout(0);
  }
  return handled;
}

}  // namespace uav
