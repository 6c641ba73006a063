#include "uav/runtime/reported_state.hpp"

#include <cmath>

namespace uav::runtime {

VehicleState ReportedState(const BlackboardData& d, const GeodeticPoint& home, AttitudeMode attitude_mode) {
  const auto& e = d.estimate;
  VehicleState s;
  s.utime = e.utime;
  s.p_N = e.p_N;
  s.v_B = e.q_NB.conjugate() * e.v_N;
  s.euler = e.euler;
  s.w_B = e.w_B;
  s.f_B = e.f_B;
  s.gps = d.sample.gps;
  s.gps_fix = d.sample.gps_fix;
  s.gps_satellites = d.sample.gps_satellites;
  s.rotor_input = d.rotor_inputs;
  s.servo_input = {d.servo.aileron, d.servo.elevator, d.servo.throttle, d.servo.rudder};
  s.flight_mode = d.sample.rc_manual ? FlightMode::kManual : FlightMode::kAuto;
  s.attitude_mode = attitude_mode;
  s.task = d.task;
  s.failsafe = d.failsafe;
  s.home = home;
  s.mission_item = d.mission_item;
  s.capturing = d.capture_interval_s.has_value() || d.capture_distance_m.has_value();
  s.armed = d.armed;
  // On the ground at rest: not flying, not falling, not lying crashed (land_detector.hpp).
  s.landed = !d.airborne && (d.ground_state == control::GroundState::kOnGround ||
                             (d.ground_state == control::GroundState::kFlying && d.touched_down));
  s.battery_voltage_v = d.sample.battery_voltage_v;
  s.battery_remaining = d.sample.battery_remaining;
  s.obstacle_range_m = d.obstacle_range_m;
  s.nearest_wire_m = d.nearest_wire_m;
  s.obstacle_count = d.obstacle_count;
  s.nearest_obstacle_m = d.nearest_obstacle_m;
  s.fence_radius_m = d.fence_radius_m;
  s.fence_alt_m = d.fence_alt_m;
  s.chirp_channel = d.chirp_channel;
  s.avoid_state = d.avoid_state;
  s.avoid_speed_limit_m_s = d.avoid_speed_limit;
  s.replan_ms = d.avoid_plan ? d.avoid_plan->planning_ms : -1.0;
  const Eigen::Vector3d v_B = e.q_NB.conjugate() * e.v_N;
  s.alpha_rad = v_B.norm() > 1.0 ? std::atan2(v_B.z(), v_B.x()) : 0.0;
  if (d.tailsitter) {
    s.vehicle_type = VehicleType::kTailSitter;
    s.vtol_mode = d.tailsitter->mode;
    s.transition_progress = d.tailsitter->transition_progress;
    s.airspeed_m_s = d.sample.airspeed_valid ? d.sample.airspeed_mps : -1.0;
  }
  return s;
}

}  // namespace uav::runtime
