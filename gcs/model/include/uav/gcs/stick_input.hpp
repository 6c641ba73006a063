#pragma once
// The operator's sticks (QGroundControl's joystick and virtual joystick): a gamepad read through
// the display's platform (GLFW's gamepad API) or the Sticks panel's on-screen sticks, sent to the
// selected vehicle at 20 Hz while they are on (manual_control_t, signed by the link). The vehicle
// flies them in its `sticks` task and holds when the deadman is released or they fall silent.
#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uav/shared/manual_control.hpp"

namespace uav::gcs {

// A gamepad in GLFW's standard layout (GLFW_GAMEPAD_AXIS_*, GLFW_GAMEPAD_BUTTON_*).
struct GamepadState {
  std::array<float, 6> axes{};     // left x, left y, right x, right y (down +), left and right trigger
  std::array<bool, 15> buttons{};  // ... 4: left bumper, 5: right bumper ...
};

// Mode 2 (the left stick yaws and climbs, the right one moves): with a dead zone around the
// centre, rescaled so that the sticks still reach 1. The deadman is either bumper, held.
ManualSticks SticksFromGamepad(const GamepadState& g, double dead_zone = 0.08);

class StickInput {
 public:
  static constexpr double kPeriod_s = 0.05;  // 20 Hz, MAVLink's MANUAL_CONTROL rate for a GCS

  // On: the sticks go out. Switching off sends one last message with the deadman released.
  void SetEnabled(bool on);
  bool enabled() const { return enabled_; }
  // The Sticks panel's sticks (self-centring where they are dragged) and deadman.
  ManualSticks& virtual_sticks() { return virtual_; }
  // A connected gamepad's state this frame (nullopt: none); it overrides the virtual sticks.
  void SetGamepad(const std::optional<GamepadState>& g);
  bool has_gamepad() const { return gamepad_.has_value(); }
  const ManualSticks& current() const { return gamepad_ ? *gamepad_ : virtual_; }

  // Queues the current sticks for `vehicle_id` every kPeriod_s while on.
  void Tick(const std::string& vehicle_id, double now);
  std::vector<std::pair<std::string, ManualSticks>> TakeOutgoing() { return std::exchange(outgoing_, {}); }
  long sent() const { return sent_; }

 private:
  bool enabled_ = false;
  bool send_release_ = false;
  ManualSticks virtual_;
  std::optional<ManualSticks> gamepad_;
  double next_due_ = -1e9;  // [s] when the next send is due
  long sent_ = 0;
  std::vector<std::pair<std::string, ManualSticks>> outgoing_;
};

}  // namespace uav::gcs
