#pragma once
// The state the vehicle reports about itself, in one typed form for every consumer: the
// telemetry stream (vehicle_state_t) and the flight log both write it through the signal table.
#include "uav/runtime/blackboard.hpp"
#include "uav/shared/vehicle_state.hpp"

namespace uav::runtime {

// From the navigation solution and the other threads' outputs on the blackboard; `home` is the
// origin of N, `attitude_mode` the airframe's wiring.
VehicleState ReportedState(const BlackboardData& d, const GeodeticPoint& home, AttitudeMode attitude_mode);

}  // namespace uav::runtime
