#include "uav/gcs/stick_input.hpp"

#include <algorithm>
#include <cmath>

namespace uav::gcs {
namespace {

double Shape(double v, double dead_zone) {
  const double a = std::abs(v);
  if (!std::isfinite(v) || a <= dead_zone) return 0.0;
  return std::copysign(std::min(1.0, (a - dead_zone) / (1.0 - dead_zone)), v);
}

}  // namespace

ManualSticks SticksFromGamepad(const GamepadState& g, double dead_zone) {
  ManualSticks s;
  s.yaw = Shape(g.axes[0], dead_zone);
  s.up = -Shape(g.axes[1], dead_zone);  // GLFW: stick pushed away is -1
  s.right = Shape(g.axes[2], dead_zone);
  s.forward = -Shape(g.axes[3], dead_zone);
  s.deadman = g.buttons[4] || g.buttons[5];
  return s;
}

void StickInput::SetEnabled(bool on) {
  if (enabled_ && !on) send_release_ = true;
  enabled_ = on;
}

void StickInput::SetGamepad(const std::optional<GamepadState>& g) {
  if (g) gamepad_ = SticksFromGamepad(*g);
  else gamepad_.reset();
}

void StickInput::Tick(const std::string& vehicle_id, double now) {
  if (vehicle_id.empty()) return;
  if (send_release_) {
    ManualSticks release;
    release.utime = static_cast<int64_t>(now * 1e6);
    outgoing_.push_back({vehicle_id, release});
    ++sent_;
    send_release_ = false;
  }
  // On a schedule, not "a period since the last": at 60 frames a second that would send every
  // fourth frame (15 Hz); this way the sends average kPeriod_s apart whatever the frame rate.
  if (!enabled_ || now + 1e-6 < next_due_) return;
  // Late by more than a period (the first send, a stalled frame): the schedule restarts from now.
  next_due_ = now - next_due_ > kPeriod_s ? now + kPeriod_s : next_due_ + kPeriod_s;
  ManualSticks s = current();
  s.utime = static_cast<int64_t>(now * 1e6);
  outgoing_.push_back({vehicle_id, s});
  ++sent_;
}

}  // namespace uav::gcs
