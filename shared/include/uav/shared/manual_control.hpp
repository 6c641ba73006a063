#pragma once
// The operator's sticks (manual_control_t): a gamepad, a joystick or the GCS's virtual sticks, sent
// at 20 Hz while the operator flies, as MAVLink's MANUAL_CONTROL. Position-assisted, as PX4's
// Position mode: full deflection is the vehicle's speed limit, released sticks hold position.
#include <cstdint>

namespace uav {

// Mode 2, in the vehicle's heading frame; each axis in [-1, 1].
struct ManualSticks {
  int64_t utime = 0;   // [us] vehicle clock when received (GCS clock when sent)
  double forward = 0;  // + ahead along the heading
  double right = 0;    // + to the right
  double up = 0;       // + climb
  double yaw = 0;      // + clockwise seen from above
  bool deadman = false;  // held: the sticks fly the vehicle; released: it holds where it is
};

// Throws std::invalid_argument naming the axis: not a finite number or outside [-1, 1].
void ValidateSticks(const ManualSticks& s);

}  // namespace uav
