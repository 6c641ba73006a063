#pragma once
// The vehicle's state as the flight stack reports it (vehicle_state_t decoded once into typed
// data), and the one table of its telemetry signals. The table (name, unit, frame, how to read
// it, display format) drives the GCS telemetry tree, its plots and CSV export, and the onboard
// flight-log columns: a signal is declared here and nowhere else.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/frames.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/signals.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace uav {

struct VehicleState {
  int64_t utime = 0;                                // [us] time of validity, vehicle clock
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();    // [m] position in N (NED from home)
  Eigen::Vector3d v_B = Eigen::Vector3d::Zero();    // [m/s] velocity in N, expressed in B
  EulerAngles euler;                                // [rad] of R_NB, z-y-x (Eq. 5.51)
  Eigen::Vector3d w_B = Eigen::Vector3d::Zero();    // [rad/s] body rates
  Eigen::Vector3d f_B = Eigen::Vector3d::Zero();    // [m/s^2] specific force
  GeodeticPoint gps;                                // WGS84 fix
  int gps_fix = 0;                                  // 0 none, 2 2-D, 3 3-D
  int gps_satellites = 0;
  std::array<double, 4> rotor_input{};              // M_1..M_4, -1..1 (Table 2.3)
  std::array<double, 4> servo_input{};              // U_a, U_e, U_th, U_r, -1..1
  FlightMode flight_mode = FlightMode::kAuto;
  AttitudeMode attitude_mode = AttitudeMode::kDirect;
  Task task = Task::kIdle;
  FailsafeAction failsafe = FailsafeAction::kNone;
  GeodeticPoint home;                               // origin of N
  int mission_item = -1;                            // item being flown, -1 none
  bool capturing = false;
  bool armed = false;
  bool landed = true;
  double battery_voltage_v = 0.0;                   // [V]
  double battery_remaining = 0.0;                   // [0..1]
  double obstacle_range_m = -1.0;                   // [m] nearest ahead; < 0 none
  double nearest_wire_m = -1.0;                     // [m] nearest ranged power line; < 0 none
  int obstacle_count = 0;                           // stereo obstacle cylinders in view
  double nearest_obstacle_m = -1.0;                 // [m] horizontal, to the nearest one's surface; < 0 none
  double fence_radius_m = 0.0;                      // [m] geofence around home
  double fence_alt_m = 0.0;                         // [m] geofence ceiling
  int chirp_channel = 0;                            // servo channel being chirped, 0 none
  AvoidState avoid_state = AvoidState::kOff;        // obstacle avoidance's safety layer
  double avoid_speed_limit_m_s = -1.0;              // [m/s] what the space seen free allows; < 0 off
  double replan_ms = -1.0;                          // [ms] the avoidance planner's last plan; < 0 none
  VehicleType vehicle_type = VehicleType::kQuadrotor;
  VtolMode vtol_mode = VtolMode::kHover;            // a tail-sitter's; a quadrotor always hovers
  double transition_progress = 1.0;                 // [0..1] 1 when not transitioning
  double airspeed_m_s = -1.0;                       // [m/s] the pitot's; < 0 no pitot
  double alpha_rad = 0.0;                           // [rad] angle of attack of the estimated velocity

  double altitude() const { return -p_N.z(); }      // [m] above home
  double ground_speed() const;                      // [m/s] horizontal, of v_N = R_NB v_B
  double heading() const;                           // [rad] psi in [0, 2 pi): 0 north, pi/2 east
  double home_distance() const { return p_N.head<2>().norm(); }  // [m] horizontal, from home
};

// Every signal of vehicle_state_t, in Table 2.3 order first.
const std::vector<Signal<VehicleState>>& VehicleStateSignals();

}  // namespace uav
