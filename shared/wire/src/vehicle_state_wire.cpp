#include "uav/wire/messages.hpp"

#include <cmath>
#include <stdexcept>

#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/status_text_t.hpp"
#include "uavmsg/vehicle_state_t.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav {
namespace {
// The enums' values are their wire values.
using S = uavmsg::vehicle_state_t;
using A = uavmsg::command_ack_t;
using T = uavmsg::status_text_t;
template <class E>
constexpr int8_t W(E v) {
  return static_cast<int8_t>(v);
}
static_assert(W(Task::kIdle) == S::TASK_IDLE && W(Task::kTakeoff) == S::TASK_TAKEOFF &&
              W(Task::kHover) == S::TASK_HOVER && W(Task::kGoto) == S::TASK_GOTO && W(Task::kLand) == S::TASK_LAND &&
              W(Task::kTrack) == S::TASK_TRACK && W(Task::kMission) == S::TASK_MISSION &&
              W(Task::kReturn) == S::TASK_RETURN && W(Task::kFollow) == S::TASK_FOLLOW &&
              W(Task::kSticks) == S::TASK_STICKS);
static_assert(W(CommandResult::kAccepted) == A::RESULT_ACCEPTED && W(CommandResult::kRejected) == A::RESULT_REJECTED &&
              W(CommandResult::kInProgress) == A::RESULT_IN_PROGRESS &&
              W(CommandResult::kCompleted) == A::RESULT_COMPLETED && W(CommandResult::kFailed) == A::RESULT_FAILED &&
              W(CommandResult::kReplaced) == A::RESULT_REPLACED);
static_assert(W(FailsafeAction::kNone) == S::FAILSAFE_NONE && W(FailsafeAction::kHold) == S::FAILSAFE_HOLD &&
              W(FailsafeAction::kReturn) == S::FAILSAFE_RETURN && W(FailsafeAction::kLand) == S::FAILSAFE_LAND &&
              W(FailsafeAction::kManual) == S::FAILSAFE_MANUAL);
static_assert(W(Severity::kError) == T::SEVERITY_ERROR && W(Severity::kWarning) == T::SEVERITY_WARNING &&
              W(Severity::kInfo) == T::SEVERITY_INFO);
static_assert(W(AttitudeMode::kDirect) == S::ATTITUDE_DIRECT && W(AttitudeMode::kGyroHover) == S::ATTITUDE_GYRO_HOVER &&
              W(AttitudeMode::kGyroCruise) == S::ATTITUDE_GYRO_CRUISE);
static_assert(W(FlightMode::kManual) == S::MODE_MANUAL && W(FlightMode::kAuto) == S::MODE_AUTO);
static_assert(W(AvoidState::kOff) == S::AVOID_OFF && W(AvoidState::kClear) == S::AVOID_CLEAR &&
              W(AvoidState::kAvoiding) == S::AVOID_AVOIDING && W(AvoidState::kBlocked) == S::AVOID_BLOCKED &&
              W(AvoidState::kNoPath) == S::AVOID_NO_PATH && W(AvoidState::kNoData) == S::AVOID_NO_DATA);

}  // namespace

VehicleState FromMessage(const uavmsg::vehicle_state_t& m) {
  auto finite = [](const char* field, std::initializer_list<double> values) {
    for (double v : values)
      if (!std::isfinite(v)) throw std::invalid_argument(std::string("vehicle_state_t.") + field + " is not finite");
  };
  finite("x/y/z", {m.x, m.y, m.z});
  finite("u/v/w", {m.u, m.v, m.w});
  finite("phi/theta/psi", {m.phi, m.theta, m.psi});
  auto need = [](auto value, const char* field, int wire) {
    if (!value) throw std::invalid_argument(std::string("vehicle_state_t.") + field + " = " + std::to_string(wire) + " names no known value");
    return *value;
  };
  VehicleState s;
  s.utime = m.utime;
  s.p_N = {m.x, m.y, m.z};
  s.v_B = {m.u, m.v, m.w};
  s.euler = {m.phi, m.theta, m.psi};
  s.w_B = {m.p, m.q, m.r};
  s.f_B = {m.acx, m.acy, m.acz};
  s.gps = {m.gps_latitude_deg, m.gps_longitude_deg, m.gps_altitude_m};
  s.gps_fix = m.gps_fix;
  s.gps_satellites = m.gps_satellites;
  for (int i = 0; i < 4; ++i) {
    s.rotor_input[i] = m.rotor_input[i];
    s.servo_input[i] = m.servo_input[i];
  }
  s.flight_mode = need(FlightModeFromWire(m.flight_mode), "flight_mode", m.flight_mode);
  s.attitude_mode = need(AttitudeModeFromWire(m.attitude_mode), "attitude_mode", m.attitude_mode);
  s.task = need(TaskFromWire(m.task), "task", m.task);
  s.failsafe = need(FailsafeFromWire(m.failsafe), "failsafe", m.failsafe);
  s.home = {m.home_latitude_deg, m.home_longitude_deg, m.home_altitude_m};
  s.mission_item = m.mission_item;
  s.capturing = m.capturing;
  s.armed = m.armed;
  s.landed = m.landed;
  s.battery_voltage_v = m.battery_voltage_v;
  s.battery_remaining = m.battery_remaining;
  s.obstacle_range_m = m.obstacle_range_m;
  s.nearest_wire_m = m.nearest_wire_m;
  s.obstacle_count = m.obstacle_count;
  s.nearest_obstacle_m = m.nearest_obstacle_m;
  s.fence_radius_m = m.fence_radius_m;
  s.fence_alt_m = m.fence_alt_m;
  s.chirp_channel = m.chirp_channel;
  s.avoid_state = need(AvoidStateFromWire(m.avoid_state), "avoid_state", m.avoid_state);
  s.avoid_speed_limit_m_s = m.avoid_speed_limit_m_s;
  s.replan_ms = m.replan_ms;
  s.vehicle_type = need(VehicleTypeFromWire(m.vehicle_type), "vehicle_type", m.vehicle_type);
  s.vtol_mode = need(VtolModeFromWire(m.vtol_mode), "vtol_mode", m.vtol_mode);
  s.transition_progress = m.transition_progress;
  s.airspeed_m_s = m.airspeed_m_s;
  s.alpha_rad = m.alpha_rad;
  return s;
}

void ToMessage(const VehicleState& s, uavmsg::vehicle_state_t* m) {
  m->utime = s.utime;
  m->x = s.p_N.x(), m->y = s.p_N.y(), m->z = s.p_N.z();
  m->u = s.v_B.x(), m->v = s.v_B.y(), m->w = s.v_B.z();
  m->phi = s.euler.phi, m->theta = s.euler.theta, m->psi = s.euler.psi;
  m->p = s.w_B.x(), m->q = s.w_B.y(), m->r = s.w_B.z();
  m->acx = s.f_B.x(), m->acy = s.f_B.y(), m->acz = s.f_B.z();
  m->gps_latitude_deg = s.gps.latitude_deg;
  m->gps_longitude_deg = s.gps.longitude_deg;
  m->gps_altitude_m = s.gps.altitude_m;
  m->gps_fix = static_cast<int8_t>(s.gps_fix);
  m->gps_satellites = static_cast<int8_t>(s.gps_satellites);
  for (int i = 0; i < 4; ++i) {
    m->rotor_input[i] = static_cast<float>(s.rotor_input[i]);
    m->servo_input[i] = static_cast<float>(s.servo_input[i]);
  }
  m->flight_mode = static_cast<int8_t>(s.flight_mode);
  m->attitude_mode = static_cast<int8_t>(s.attitude_mode);
  m->task = static_cast<int8_t>(s.task);
  m->failsafe = static_cast<int8_t>(s.failsafe);
  m->home_latitude_deg = s.home.latitude_deg;
  m->home_longitude_deg = s.home.longitude_deg;
  m->home_altitude_m = s.home.altitude_m;
  m->mission_item = s.mission_item;
  m->capturing = s.capturing;
  m->armed = s.armed;
  m->landed = s.landed;
  m->battery_voltage_v = static_cast<float>(s.battery_voltage_v);
  m->battery_remaining = static_cast<float>(s.battery_remaining);
  m->obstacle_range_m = static_cast<float>(s.obstacle_range_m);
  m->nearest_wire_m = static_cast<float>(s.nearest_wire_m);
  m->obstacle_count = static_cast<int16_t>(s.obstacle_count);
  m->nearest_obstacle_m = static_cast<float>(s.nearest_obstacle_m);
  m->fence_radius_m = static_cast<float>(s.fence_radius_m);
  m->fence_alt_m = static_cast<float>(s.fence_alt_m);
  m->chirp_channel = static_cast<int8_t>(s.chirp_channel);
  m->avoid_state = static_cast<int8_t>(s.avoid_state);
  m->avoid_speed_limit_m_s = static_cast<float>(s.avoid_speed_limit_m_s);
  m->replan_ms = static_cast<float>(s.replan_ms);
  m->vehicle_type = static_cast<int8_t>(s.vehicle_type);
  m->vtol_mode = static_cast<int8_t>(s.vtol_mode);
  m->transition_progress = static_cast<float>(s.transition_progress);
  m->airspeed_m_s = static_cast<float>(s.airspeed_m_s);
  m->alpha_rad = static_cast<float>(s.alpha_rad);
}

}  // namespace uav
