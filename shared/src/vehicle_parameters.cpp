// The parameters of the vehicle and of a camera file, declared once: name, unit, default, limits
// and description. Files set values only (parameters.hpp). The vehicle's defaults are the X650
// of thesis 2.3-2.5 (resources/vehicles/x650.params sets the same values, explicitly).
#include "uav/shared/parameters.hpp"

namespace uav {

namespace {

// When a change over the link may take effect (ParamApply), one column of each row. The control
// thread applies a change and every other thread with live settings re-reads them in one place
// (VisionWorker::ApplyParameters, ImuWorker): gains, limits, failsafe thresholds, follow and the
// avoidance planner and safety layer change in flight; the geofence only on the ground; the
// rest build the vehicle at start.
constexpr ParamApply kStart = ParamApply::kAtStart;
constexpr ParamApply kGround = ParamApply::kOnGround;
constexpr ParamApply kFlight = ParamApply::kInFlight;

}  // namespace

const ParameterSchema& VehicleParameterSchema() {
  // {name, unit, default, min, max, description, when it may change}
  static const ParameterSchema kSchema = [] {
  ParameterSchema schema{"vehicle", {
    // --- Rigid body (thesis Eq. 2.1, Table 2.2) ---
    {"mass", "kg", 1.37, 0.1, 50, "total platform mass m (Table 2.2)", kStart},
    {"inertia_xx", "kg.m2", 0.03356, 1e-4, 10, "rolling moment of inertia J_xx (Table 2.2)", kStart},
    {"inertia_yy", "kg.m2", 0.03122, 1e-4, 10, "pitching moment of inertia J_yy (Table 2.2)", kStart},
    {"inertia_zz", "kg.m2", 0.05423, 1e-4, 10, "yawing moment of inertia J_zz (Table 2.2)", kStart},
    {"arm_length", "m", 0.325, 0.05, 5, "rotor to CG distance l (Table 2.2)", kStart},
    {"gravity", "m/s2", 9.80665, 9.7, 9.9, "standard gravity g (Eq. 2.7)", kStart},

    // --- Rotors (thesis Eq. 2.5, 2.10, 2.13; flight-identified values of Table 2.5) ---
    {"thrust_gain", "N", 3.8738, 0.1, 100, "K_f, thrust per unit of normalised rotor input (Table 2.5)", kStart},
    {"thrust_time_constant", "s", 0.095583, 0.001, 1, "tau_f, first-order rotor thrust lag (Table 2.5)", kStart},
    {"induced_torque_coeff", "N.m.s", 0.013, 0, 1, "d, reactive torque Q_i = d * Omega_i (Eq. 2.10, Table 2.5)", kStart},
    {"rotor_speed_gain", "rad/s", 9.2994, 0, 1000, "K_v, Omega_i = K_v * v_i (Eq. 2.5, Table 2.2)", kStart},
    // Eq. 2.13 is identified around the hover trim (thesis 2.4.5): thrust is linear in the
    // normalised input and vanishes at this input. Chosen so that the throttle trim u_th0 = 0.18
    // of Table 2.4 gives m*g/4 per rotor: 0.18 - 1.37*9.80665/(4*3.8738) = -0.687.
    {"rotor_input_zero_thrust", "1", -0.687, -1, 1, "normalised input M_i at which thrust is zero", kStart},
    {"rotor_input_idle", "1", -0.80, -1, 1, "armed on the ground: rotors spin, no lift", kStart},

    // --- Body drag (thesis Eq. 2.6; the thesis neglects it at low speed, kept small) ---
    {"air_density", "kg/m3", 1.225, 0.5, 1.5, "rho", kStart},
    {"drag_area", "m2", 0.04, 0, 2, "C_d times reference area", kStart},

    // --- Hover trim and gyro in the loop (thesis 2.4.5 Table 2.4, 2.5 Table 2.6) ---
    // The airframe's imbalance: the servo inputs at which it hovers without turning (Table 2.4).
    // The throttle trim u_th0 = 0.18 is built into rotor_input_zero_thrust above.
    {"trim_aileron", "1", 0.066, -0.3, 0.3, "u_a0 (Table 2.4)", kStart},
    {"trim_elevator", "1", 0.066, -0.3, 0.3, "u_e0 (Table 2.4)", kStart},
    {"trim_rudder", "1", -0.013, -0.3, 0.3, "u_r0 (Table 2.4)", kStart},
    // 0: the servo board drives the rotors and the autopilot mixes (Eq. 2.11);
    // 1: the gyro is in the loop in hover mode, it holds roll and pitch angles (Eq. 2.17-2.19);
    // 2: the gyro is in the loop in cruise mode, it holds the body rates (Eq. 2.20-2.22).
    {"attitude_mode", "-", 0, 0, 2, "wiring of the servo board outputs (thesis Fig. 2.21)", kStart},
    {"gyro_hover_roll_gain", "rad", -0.8628, -20, 20, "K_phi (Eq. 2.17, Table 2.6)", kStart},
    {"gyro_hover_roll_tau", "s", 0.076615, 0.005, 1, "tau_phi1 = tau_phi2 (Table 2.6)", kStart},
    {"gyro_hover_pitch_gain", "rad", -0.59151, -20, 20, "K_theta (Eq. 2.18, Table 2.6)", kStart},
    {"gyro_hover_pitch_tau", "s", 0.079119, 0.005, 1, "tau_theta1 = tau_theta2 (Table 2.6)", kStart},
    {"gyro_hover_delay", "s", 0.1, 0, 0.5, "T_phi = T_theta (Table 2.6)", kStart},
    {"gyro_yaw_rate_gain", "rad/s", -4.8121, -20, 20, "K_r, the same in both modes (Eq. 2.19, 2.22, Table 2.6)", kStart},
    {"gyro_yaw_rate_tau", "s", 0.37029, 0.005, 2, "tau_r (Table 2.6)", kStart},
    {"gyro_cruise_roll_rate_gain", "rad/s", -2.3167, -20, 20, "K_p (Eq. 2.20, Table 2.6)", kStart},
    {"gyro_cruise_roll_rate_tau", "s", 0.033855, 0.005, 1, "tau_p (Table 2.6)", kStart},
    {"gyro_cruise_pitch_rate_gain", "rad/s", -2.4967, -20, 20, "K_q (Eq. 2.21, Table 2.6)", kStart},
    {"gyro_cruise_pitch_rate_tau", "s", 0.046672, 0.005, 1, "tau_q (Table 2.6)", kStart},

    // --- Airframe type, and the tail-sitter U-Lion (thesis 2.6; resources/vehicles/ulion.params) ---
    // The ts_* entries' defaults are U-Lion Mk III's (Tables 2.7-2.11) and, where the thesis is
    // silent, the assumptions ulion.params names. A quadrotor ignores them.
    {"vehicle_type", "-", 0, 0, 1, "0: the X650 quadrotor (thesis 2.3-2.5), 1: the U-Lion tail-sitter (thesis 2.6)", kStart},
    {"ts_wing_area", "m2", 0.36, 0.001, 100, "reference wing area S (Table 2.7)", kStart},
    {"ts_wing_span", "m", 1.8, 0.05, 100, "wing span, extended (Table 2.7)", kStart},
    {"ts_wing_chord", "m", 0.2, 0.01, 20, "wing chord (Table 2.7)", kStart},
    {"ts_wing_lift_slope", "1/rad", 5.969, 3, 7, "section lift slope a0 (Clark Y: 0.95 x 2 pi)", kStart},
    {"ts_wing_zero_lift_alpha", "rad", -0.061, -0.2, 0.05, "section zero-lift angle (Clark Y: -3.5 deg)", kStart},
    {"ts_wing_stall_alpha", "rad", 0.227, 0.1, 0.4, "stall angle (Clark Y at Re 1.1e5: 12-14 deg)", kStart},
    {"ts_wing_profile_drag", "-", 0.02, 0.005, 0.2, "profile drag C_D0 (Clark Y at Re 1.1e5)", kStart},
    {"ts_wing_oswald", "-", 0.85, 0.5, 1, "span efficiency e", kStart},
    {"ts_wing_normal_force_90", "-", 1.28, 1, 2.1, "flat-plate normal force broadside (Hoerner, aspect ratio 9)", kStart},
    {"ts_wing_x", "m", 0.01, -0.5, 0.5, "wing aerodynamic centre along x_B from the CG (battery forward)", kStart},
    {"ts_tail_area", "m2", 0.05, 0.001, 1, "horizontal tail area, elevator over its span", kStart},
    {"ts_tail_span", "m", 0.4, 0.05, 2, "horizontal tail span", kStart},
    {"ts_tail_x", "m", -0.55, -3, -0.05, "tail's aerodynamic centre along x_B from the CG", kStart},
    {"ts_fin_area", "m2", 0.03, 0, 1, "vertical fin area", kStart},
    {"ts_fin_height", "m", 0.2, 0.02, 1, "vertical fin height", kStart},
    {"ts_canard_area", "m2", 0.008, 0.0005, 0.1, "area of one canard (thesis 2.6.2: yaw in hover, in the propwash)", kStart},
    {"ts_canard_y", "m", 0.09, 0.01, 0.5, "canard centre's distance from the fuselage axis", kStart},
    {"ts_canard_x", "m", 0.2, -1, 2, "canards along x_B from the CG", kStart},
    {"ts_flap_effectiveness", "-", 0.5, 0.1, 1, "tau: effective angle of attack per radian of surface deflection", kStart},
    {"ts_surface_max", "rad", 0.44, 0.05, 0.8, "elevator, aileron and canard deflection limit (25 deg)", kStart},
    {"ts_surface_rate", "rad/s", 9.5, 0.5, 50, "surface servo rate (HS-65MG: 0.11 s per 60 deg, Table 2.10)", kStart},
    {"ts_rotor_x", "m", 0.45, 0.05, 3, "gimbal pivot along x_B from the CG", kStart},
    {"ts_rotor_diameter", "m", 0.28, 0.05, 3, "coaxial rotor diameter (11-inch propeller, thesis 2.6.2)", kStart},
    {"ts_thrust_max", "N", 40, 1, 1000, "coaxial pair's thrust at full throttle, static (Table 2.11)", kStart},
    {"ts_thrust_tau", "s", 0.05, 0.005, 1, "thrust lag", kStart},
    {"ts_prop_pitch_speed", "m/s", 30, 5, 200, "axial speed at which the propellers' thrust vanishes (11x7: 7 in x 9000 rpm)", kStart},
    {"ts_rotor_torque_max", "N.m", 0.06, 0, 10, "differential torque of the pair at full command (about x_B)", kStart},
    {"ts_gimbal_max", "rad", 0.5236, 0.05, 0.8, "gimbal tilt limit per axis (+-30 deg, thesis 2.6.5)", kStart},
    {"ts_gimbal_rate", "rad/s", 6.5, 0.5, 50, "gimbal servo rate (0.16 s per 60 deg, Table 2.10)", kStart},
    {"ts_servo_tau", "s", 0.02, 0.001, 0.5, "servo lag below the rate limit", kStart},
    {"ts_fuselage_axial", "m2", 0.01, 0, 1, "fuselage, gimbal and canards' drag area C_D A along x_B", kStart},
    {"ts_fuselage_side", "m2", 0.1, 0, 2, "fuselage's drag area broadside", kStart},
    {"ts_battery_mass", "kg", 0.3, 0.01, 10, "sliding battery (thesis 2.6.3: 300 g)", kStart},
    {"ts_battery_travel", "m", 0.4, 0, 2, "battery travel toward the tail (thesis 2.6.3: 40 cm, CG 5-6 cm)", kStart},
    {"ts_battery_speed", "m/s", 0.1, 0.01, 2, "battery belt speed", kStart},
    // Tail-sitter control: the hover loops are the ctl_* position gains above.
    {"ts_att_gain", "1/s2", 50, 1, 400, "attitude angle gain, every axis (natural frequency squared)", kStart},
    {"ts_rate_gain", "1/s", 9, 0.5, 60, "attitude rate damping", kStart},
    {"ts_att_int", "1/s3", 15, 0, 50, "attitude integrator (trims the wing's moment and the CG)", kStart},
    {"ts_tilt_max", "rad", 0.7, 0.1, 1.2, "hover: thrust axis tilt limit from vertical", kStart},
    {"ts_cruise_speed", "m/s", 12, 3, 60, "wing-borne airspeed (Table 2.11: 10 m/s, hand-flown; turns need a margin over the 9.5 m/s stall)", kStart},
    {"ts_trans_airspeed", "m/s", 10, 3, 60, "front transition complete at this airspeed", kStart},
    {"ts_trans_pitch_rate", "deg/s", 60, 5, 360, "front transition: nose-down rate of the pitch schedule", kStart},
    {"ts_back_pitch_rate", "deg/s", 180, 5, 360, "back transition: nose-up rate (a quick flare: the broadside wing brakes, the lift passes its peak fast)", kStart},
    {"ts_trans_timeout", "s", 6, 1, 60, "a transition not complete in this time aborts to hover", kStart},
    {"ts_trans_alt_loss", "m", 3, 0.5, 50, "a transition losing more height aborts to hover", kStart},
    {"ts_weathervane", "-", 1, 0, 1, "hover: 1 turns the wing edge-on to the wind (the heading follows the wind), 0 holds the commanded heading", kStart},
    {"ts_trans_min_alt", "m", 5, 1, 100, "no transition below this altitude", kStart},
    {"ts_land_approach_alt", "m", 20, 1, 100, "a landing from the wing circles its point down to this altitude, then transitions to hover (at least ts_trans_min_alt)", kStart},
    {"ts_bank_max", "rad", 0.5, 0.05, 1.2, "cruise: bank limit in coordinated turns", kStart},

    // --- Simulated sensors (thesis 2.3.2: ArduIMU with magnetometer, u-blox GPS, barometer, sonar) ---
    // Noise figures are 1 sigma per sample. The INS uses the same figures as its noise model.
    {"imu_gyro_noise", "rad/s", 0.001, 0, 1, "gyro white noise per 50 Hz sample (MPU-6000: 0.005 deg/s/sqrt(Hz), with vibration)", kStart},
    {"imu_gyro_bias", "rad/s", 0.01, 0, 0.5, "gyro turn-on bias per axis (each flight draws one)", kStart},
    {"imu_accel_noise", "m/s2", 0.03, 0, 5, "accelerometer white noise per sample (MPU-6000: 400 ug/sqrt(Hz), with vibration)", kStart},
    {"imu_accel_bias", "m/s2", 0.1, 0, 2, "accelerometer turn-on bias per axis", kStart},
    {"mag_noise", "1", 0.01, 0, 0.5, "magnetometer noise, in units of the field strength", kStart},
    {"mag_inclination", "rad", -0.30, -1.5, 1.5, "dip of Earth's field below the horizon (Singapore about -17 deg)", kStart},
    {"gps_rate", "Hz", 5, 1, 20, "u-blox navigation rate", kStart},
    {"gps_noise_h", "m", 0.5, 0, 20, "horizontal white noise per axis", kStart},
    {"gps_drift_h", "m", 1.0, 0, 20, "horizontal wander per axis (first-order Gauss-Markov)", kStart},
    {"gps_noise_v", "m", 1.5, 0, 50, "altitude white noise: GPS altitude is poor (thesis 2.3.2)", kStart},
    {"gps_drift_v", "m", 3.0, 0, 50, "altitude wander", kStart},
    {"gps_drift_time", "s", 60, 1, 3600, "correlation time of the wander", kStart},
    {"gps_vel_noise", "m/s", 0.05, 0, 5, "Doppler velocity noise per axis (u-blox 6: 0.1 m/s CEP50 in motion)", kStart},
    {"baro_noise", "m", 0.3, 0, 10, "barometric altitude white noise per sample", kStart},
    {"baro_drift", "m", 0.5, 0, 20, "barometric wander (weather, temperature)", kStart},
    {"baro_drift_time", "s", 300, 1, 36000, "correlation time of the barometric wander", kStart},
    {"sonar_rate", "Hz", 20, 1, 50, "sonar ping rate", kStart},
    {"sonar_range_min", "m", 0.05, 0, 1, "closer than this the echo is lost", kStart},
    {"sonar_range_max", "m", 5.0, 0.5, 20, "farther than this the echo is lost", kStart},
    {"sonar_noise", "m", 0.01, 0, 1, "sonar range noise", kStart},
    {"sonar_mount_pitch", "rad", 0, -1.5708, 1.5708,
     "the sonar's beam pitched from +z_B toward +x_B: 0 down on a multicopter, -pi/2 along a tail-sitter's tail", kStart},
    {"ins_gyro_bias_walk", "rad/s/sqrt(s)", 0.00001, 0, 0.1, "INS: how fast it lets the gyro bias wander", kStart},
    {"ins_accel_bias_walk", "m/s2/sqrt(s)", 0.0002, 0, 1, "INS: how fast it lets the accelerometer bias wander", kStart},
    {"sim_seed", "-", 1, 0, 1e9, "seed of the simulated sensor noise and wind (runs are repeatable)", kStart},

    // --- Simulated wind (thesis 2.2: urban canyons have large drafts) ---
    {"wind_speed", "m/s", 0, 0, 20, "steady wind; 0 is calm air", kStart},
    {"wind_direction", "rad", 0, -3.1416, 3.1416, "where the wind comes from, clockwise from north", kStart},
    {"wind_turbulence", "-", 0.15, 0, 1, "turbulence 1 sigma per axis, as a fraction of wind_speed", kStart},
    {"wind_turbulence_time", "s", 2.0, 0.1, 60, "correlation time of the turbulence", kStart},
    {"wind_gust", "-", 0.6, 0, 2, "peak of an urban draft (1-cos gust), as a fraction of wind_speed", kStart},
    {"wind_gust_duration", "s", 3.0, 0.5, 30, "length of one draft", kStart},
    {"wind_gust_interval", "s", 15, 1, 600, "mean time between drafts (Poisson)", kStart},

    // --- Battery (3S LiPo; simple drain model for telemetry and later failsafes) ---
    {"battery_capacity", "Ah", 5.0, 0.1, 100, "usable capacity", kStart},
    {"battery_voltage_full", "V", 12.6, 1, 60, "open-circuit voltage at 100 %", kStart},
    {"battery_voltage_empty", "V", 10.5, 1, 60, "open-circuit voltage at 0 %", kStart},
    {"battery_hover_current", "A", 18.0, 0, 300, "current drawn in hover", kStart},
    {"battery_idle_current", "A", 0.8, 0, 50, "avionics current, rotors off", kStart},

    // --- Position and attitude controller (onboard/control) ---
    // The horizontal loops sit below the attitude loop. With the attitude loop at 4 rad/s,
    // 0.9/1.8/0.4 limit-cycled at +-1 m around a goto target; with it at about 6 rad/s (below),
    // 1.0/2.2/0.5 hold within 0.35 m in 5 m/s wind with drafts (0.74 m with 0.7/1.2/0.2).
    {"ctl_pos_gain_xy", "1/s", 0.7, 0, 10, "horizontal position P gain (outer loop); 1.0 overshot a 3 m goto by 0.5 m", kFlight},
    {"ctl_pos_gain_z", "1/s", 1.2, 0, 10, "vertical position P gain", kFlight},
    {"ctl_vel_gain_xy", "1/s", 2.2, 0, 20, "horizontal velocity P gain", kFlight},
    {"ctl_vel_int_xy", "1/s2", 0.5, 0, 20, "horizontal velocity I gain", kFlight},
    {"ctl_vel_gain_z", "1/s", 3.0, 0, 20, "vertical velocity P gain", kFlight},
    {"ctl_vel_int_z", "1/s2", 1.0, 0, 20, "vertical velocity I gain", kFlight},
    {"ctl_vel_int_limit", "m/s2", 2.0, 0, 10, "anti-windup: integrator output limit", kFlight},
    // The attitude loop (slow pair near 5.5 rad/s, below) takes 0.3-0.4 s to bring a saturated
    // tilt back, while the velocity loop asks for it at once: reversed at 2 m/s under a 0.6 m/s
    // limit, the vehicle came back at 1.35 m/s, and a 10 m goto passed its 3 m/s limit at 3.65.
    // Taken against the velocity the measured acceleration reaches this far ahead, 0.68 m/s and
    // 3.04 m/s (PositionAttitudeController tests).
    {"ctl_vel_lead", "s", 0.25, 0, 1, "horizontal velocity loop: lead on the attitude loop's lag (0: none)", kFlight},
    {"ctl_speed_max_xy", "m/s", 3.0, 0.1, 15, "horizontal speed limit", kFlight},
    {"ctl_speed_max_up", "m/s", 2.0, 0.1, 10, "climb rate limit", kFlight},
    {"ctl_speed_max_down", "m/s", 1.0, 0.1, 10, "descent rate limit", kFlight},
    {"ctl_accel_max_xy", "m/s2", 4.0, 0.1, 20, "horizontal acceleration limit", kFlight},
    {"ctl_tilt_max", "rad", 0.45, 0.05, 0.9, "roll/pitch limit (about 26 deg)", kFlight},
    // Inner loop: tau = J*(K_att*e - K_rate*w). With the rotor lag tau_f the closed loop is
    // tau_f s^3 + s^2 + K_rate s + K_att; stable while K_rate > tau_f K_att (6 > 1.5 here), with
    // its slow pair near 5.5 rad/s.
    {"ctl_att_gain", "1/s2", 16, 0, 100, "roll/pitch angle gain", kFlight},
    {"ctl_rate_gain", "1/s", 6.0, 0, 100, "roll/pitch rate damping", kFlight},
    {"ctl_yaw_gain", "1/s2", 3.0, 0, 100, "yaw angle gain", kFlight},
    {"ctl_yaw_rate_gain", "1/s", 3.0, 0, 100, "yaw rate damping", kFlight},
    // Attitude integrator in servo units: with J/k_rp = 0.023 it adds 1.3 rad/s^3 to the loop above
    // (tau_f s^4 + s^3 + 6 s^2 + 16 s + 1.3). At 0.1 (4.3 rad/s^3) it fought the velocity
    // integrator and the hover wandered 0.3 m RMS; 0.03 takes up an untrimmed airframe in seconds.
    {"ctl_att_int", "1/(rad.s)", 0.03, 0, 2, "roll, pitch and yaw angle error integrator", kFlight},
    {"ctl_att_int_limit", "1", 0.15, 0, 0.5, "anti-windup: integrator output limit", kFlight},

    // Zero controller output flies the trim (thesis 2.4.5: "trim values correspond to the zero
    // controller output"). uav-sysid's "trim" re-identifies them from a hover.
    {"ctl_trim_aileron", "1", 0.066, -0.3, 0.3, "added to the aileron output", kFlight},
    {"ctl_trim_elevator", "1", 0.066, -0.3, 0.3, "added to the elevator output", kFlight},
    {"ctl_trim_rudder", "1", -0.013, -0.3, 0.3, "added to the rudder output", kFlight},
    // Gyro in the loop: the gyro is the inner loop, the autopilot commands it through the
    // identified models. Cruise mode: angle error to rate command, the tau_p = 0.034 s rate loop
    // allows 6 rad/s with 10 deg phase loss. Hover mode: the angle command passes through K_phi.
    {"ctl_gyro_att_gain", "1/s", 6.0, 0, 30, "cruise mode: roll/pitch angle error to rate command", kFlight},
    {"ctl_gyro_yaw_gain", "1/s", 1.5, 0, 10, "gyro modes: yaw angle error to yaw-rate command", kFlight},

    // --- Task manager ---
    {"task_reached_radius", "m", 0.3, 0.05, 5, "target counts as reached within this distance", kFlight},
    {"task_reached_speed", "m/s", 0.3, 0.05, 5, "... and below this speed", kFlight},
    {"task_land_speed", "m/s", 0.7, 0.1, 3, "descent rate while landing", kFlight},
    {"task_land_slow_alt", "m", 2.0, 0.5, 20, "below this altitude land at a third of the rate", kFlight},
    {"task_path_accel", "m/s^2", 1.0, 0.1, 5, "acceleration of the path reference (track, mission)", kFlight},
    {"task_path_leash", "m", 3.0, 0.5, 20, "the path reference never leads the vehicle by more", kFlight},
    {"task_return_alt", "m", 15.0, 2, 120, "lowest altitude for the flight home (clears trees, thesis 6.5)", kFlight},
    {"fs_link_hold_time", "s", 5.0, 1, 120, "no GCS heartbeat this long (once one was heard): hold position", kFlight},
    {"fs_link_return_time", "s", 20.0, 2, 600, "... this long: return home (must exceed fs_link_hold_time)", kFlight},
    {"prearm_min_sats", "-", 6, 4, 20, "pre-arm: a 3-D GPS fix needs at least this many satellites", kFlight},
    {"prearm_max_att_sigma", "deg", 5.0, 0.5, 30, "pre-arm: the INS's attitude 1-sigma must be below this", kFlight},
    {"prearm_max_sensor_age", "s", 0.1, 0.02, 2, "pre-arm: the newest IMU sample must be younger", kFlight},
    {"prearm_max_tilt", "deg", 20.0, 2, 60, "pre-arm: standing still, tilted from upright at most this (a vehicle on its side is refused)", kFlight},
    {"fs_crash_tilt", "deg", 60.0, 20, 180, "crash: tipped beyond this from upright in flight for 0.5 s (a flip, a lost rotor; quadrotor only)", kFlight},
    {"fs_crash_accel", "m/s2", 100.0, 20, 300, "crash: a specific force beyond this (an impact); a fall with the motors stopped is a crash too", kFlight},
    {"task_disarm_preflight", "s", 10.0, 0, 600, "armed on the ground this long without a takeoff: disarm (PX4's COM_DISARM_PRFLT); 0: never", kFlight},
    {"task_disarm_land", "s", 0.0, 0, 20, "after a touchdown the rotors idle this long, then disarm (PX4's COM_DISARM_LAND)", kFlight},
    {"fs_battery_return", "-", 0.25, 0.05, 0.9, "battery remaining below this: return home", kFlight},
    {"fs_battery_land", "-", 0.10, 0.01, 0.5, "battery remaining below this: land where it is", kFlight},
    {"fs_fence_radius", "m", 500, 10, 5000, "geofence: horizontal distance from home", kGround},
    {"fs_fence_alt", "m", 120, 5, 500, "geofence: altitude above home (legal ceiling)", kGround},
    {"fs_fence_action", "-", 2, 1, 3, "on a fence breach (the circle, the ceiling, the uploaded zones): 1 hold, 2 return (to the nearest rally point, else home), 3 land", kGround},
    {"task_stall_time", "s", 60.0, 5, 600, "a path task that makes no progress this long fails and holds", kFlight},
    {"task_stick_yaw_rate", "deg/s", 45.0, 5, 180, "sticks: the yaw rate at full deflection (full forward, right or up is the speed limit)", kFlight},
    {"task_stick_timeout", "s", 0.5, 0.1, 2, "sticks: silent this long (no manual_control_t), the vehicle holds where it is", kFlight},
    {"task_landed_alt", "m", 0.15, 0.01, 1, "landed when below this altitude ...", kFlight},
    {"task_landed_time", "s", 0.5, 0.1, 10, "... and still for this long", kFlight},

    // --- GCS link (CMM thread) ---
    {"link_heartbeat_period", "s", 1.0, 0.1, 10, "vehicle heartbeat_t period", kStart},
    {"link_tile_period", "s", 0.2, 0.05, 5, "at most one live-map tile per period (~100 kB/s at 0.2 s)", kStart},

    // --- Power lines (STEREO thread, thesis 3.6) ---
    {"pwl_enable", "-", 1, 0, 1, "detect power lines in the stereo pair and range them", kStart},
    {"pwl_min_range", "m", 1.5, 0.5, 20, "nearest wire searched for (largest disparity)", kStart},
    {"pwl_max_range", "m", 60, 5, 500, "farthest wire ranged (smallest disparity)", kStart},
    {"pwl_segments", "-", 0, 0, 1, "straight pieces of the wires' edge map by 0: LSD, 1: EDLines (a fifth of LSD's time over foliage; the avoidance tables were measured with LSD)", kStart},
    {"pwl_verify", "-", 0, 0, 1, "drop the curves the learned verifier, trained on real photos, gives under 0.7 of being a wire (the avoidance tables were measured without it)", kStart},
    {"pwl_rig", "-", -1, -1, 7, "stereo rig (the scene's, from 0) for wires alone, beside obs_rig: a pair rolled about its axis ranges the level wires a level pair cannot; -1: wires on obs_rig", kStart},

    // --- Stereo obstacles (STEREO thread, thesis 3.2, 3.5) ---
    {"obs_enable", "-", 1, 0, 1, "detect obstacles (and, with pwl_enable, wires unless pwl_rig has them) on obs_rig; 0: the rig is not used for them (obstacle avoidance needs 1)", kStart},
    {"obs_matcher", "-", 1, 0, 2, "disparity by 0: block matching, 1: OpenCV's semi-global matching, 2: our census semi-global matcher", kStart},
    {"obs_max_sigma", "m", 0.3, 0.05, 2, "range gate: points deeper than where the depth error (Eq. 3.7) reaches this are dropped", kStart},
    {"obs_margin", "m", 0.5, 0, 5, "safety margin added to each obstacle cylinder's radius", kFlight},
    {"obs_min_voxels", "-", 20, 3, 1000, "smallest cluster (5 cm voxels) reported as an obstacle", kStart},
    {"obs_cloud_rate", "Hz", 1, 0, 5, "decimated point cloud to the GCS (0: none)", kStart},
    {"obs_rig", "-", -1, -1, 7, "stereo rig (the scene's, from 0) for obstacles and wires; -1: the first rig neither odometry, active stereo nor pwl_rig uses", kStart},

    // --- Target tracking and follow (TRK thread, thesis 3.7) ---
    {"trk_tracker", "-", 3, 0, 4, "0: CamShift (thesis 3.7), 1: KCF, 2: CSRT (opencv-contrib), 3: auto (CamShift where the target's colour stands out, else the correlation filter), 4: the correlation filter (HOG, DSST scale, re-detection)", kStart},
    {"trk_window", "-", 0, 0, 1, "CamShift search window 0: adaptive (moments), 1: static (selection's size)", kStart},
    {"trk_gimbal_gain", "-", 0.5, 0, 1, "fraction of the target's vertical offset the gimbal corrects per frame (0: gimbal fixed)", kStart},
    {"trk_buffer_s", "s", 10, 1, 30, "frames kept for a target picked on an older (frozen) frame; the tracker catches up through them (about 0.9 MB per 640x480 frame)", kStart},
    {"gimbal_pitch", "deg", -20, -90, 20, "gimbal pitch before a target is locked (0 ahead, -90 straight down)", kStart},
    {"flw_distance", "m", 8, 2, 50, "follow: horizontal distance kept from the target", kFlight},
    {"flw_height", "m", 5, 2, 50, "follow: height kept above the target's ground", kFlight},
    {"flw_lost_timeout", "s", 10, 1, 120, "follow: hold this long after the target is lost, then give up", kFlight},
    {"mdp_camera", "-", 1, 0, 2, "depth from motion (thesis 3.4) on 0: none, 1: the downward camera, 2: the gimbal camera", kStart},
    {"mdp_obstacle_depth", "m", 10, 0.5, 500, "depth from motion: a grid cell nearer than this is an obstacle, beyond it free", kStart},
    {"mdp_max_features", "-", 240, 12, 2000, "depth from motion: features tracked, spread over the 4x3 grid", kStart},
    {"asv_enable", "-", 0, 0, 1, "1: active stereo (thesis ch. 4) on asv_rig, a downward pair with the laser dot projector: the height from the dots", kStart},
    {"asv_rig", "-", 0, 0, 7, "stereo rig (the scene's, from 0) the active stereo runs on", kStart},
    {"asv_to_ins", "-", 1, 0, 1, "active stereo's height feeds the INS as a height sensor", kStart},
    {"asv_height_noise", "m", 0.02, 0.001, 1, "1 sigma the INS gives an active stereo height, at least", kStart},
    {"asv_threshold", "DN", 60, 5, 250, "a laser dot is this much brighter than the image's median", kStart},
    {"asv_min_points", "-", 20, 3, 1000, "fewer matched dots: no height", kStart},
    {"vo_enable", "-", 0, 0, 1, "1: visual odometry (thesis ch. 5) on vo_rig: position while GPS is lost", kStart},
    {"vo_rig", "-", 0, 0, 7, "stereo rig (the scene's, from 0) the visual odometry runs on", kStart},
    {"vo_method", "-", 0, 0, 2, "motion from 0 PnP, 1 EPnP, 2 the rigid 3D-3D method (thesis 5.3)", kStart},
    {"vo_position_noise", "m", 0.05, 0.001, 10, "1 sigma the INS and the VO+IMU filter give a VO position", kStart},
    {"vo_max_features", "-", 400, 20, 5000, "corners detected per keyframe", kStart},
    {"vo_offset_prior", "px", 0.2, 0, 5, "1 sigma of the stereo pair's disparity offset before the odometry learns it from the motion; 0: taken as 0, not learnt", kStart},
    // --- Vision timing (thesis Table 2.1's vision threads, off the control path) ---
    // Each result reaches the rest of the vehicle this long after its frame was exposed. On a
    // simulated clock these fixed figures keep a run repeatable; at --speed 1 (or with
    // vis_measured 1) the measured compute time is used instead. 0: when the work is done.
    {"vis_measured", "-", 0, 0, 1, "1: every vision result visible when its work is done (measured), even on a simulated clock", kStart},
    {"cam_latency", "ms", 20, 0, 1000, "downward camera frame to its preview, shared frame and survey capture", kStart},
    {"obs_latency", "ms", 60, 0, 1000, "stereo pair to its obstacles, nearest range and wires", kStart},
    {"vo_latency", "ms", 50, 0, 1000, "stereo pair to its visual odometry position", kStart},
    {"asv_latency", "ms", 30, 0, 1000, "active stereo pair to its height", kStart},
    {"trk_latency", "ms", 40, 0, 1000, "gimbal frame to its tracked target", kStart},
    {"mdp_latency", "ms", 60, 0, 1000, "frame to its depth-from-motion grid", kStart},
    {"map_latency", "ms", 0, 0, 10000, "survey captures to their live map tiles (0: when stitched)", kStart},
    // --- Obstacle avoidance (AVD thread and the safety layer in CTL, thesis 7.2) ---
    {"avd_enable", "-", 0, 0, 1, "1: every task that moves the vehicle goes through the 3-D map, the planner and the safety layer (needs a stereo rig for obstacles)", kStart},
    {"avd_body_radius", "m", 0.5, 0.05, 5, "the airframe's radius, propellers included; the planner keeps this plus obs_margin from what it senses", kFlight},
    {"avd_body_height", "m", 0.5, 0.05, 5, "the airframe's height, landing gear and propellers included: the map clears the unknown space the body fills, a disc this high, not a ball", kFlight},
    {"avd_brake_accel", "m/s^2", 2.5, 0.5, 10, "deceleration the speed limit counts on: the vehicle can always stop within the space it has seen", kFlight},
    {"avd_reaction", "s", 0.4, 0, 2, "control and attitude lag before braking bites, added to the perception's age", kFlight},
    {"avd_stale", "s", 0.5, 0.1, 5, "perception or plan older than this: brake and hold", kFlight},
    {"avd_blind_return", "s", 3, 0.5, 60, "no obstacle perception for this long in flight (a camera failed): return home at the altitude flown, on the map alone, through space seen free; hold where there is none", kFlight},
    {"avd_rate", "Hz", 10, 1, 50, "replanning rate", kStart},
    {"avd_latency", "ms", 30, 0, 1000, "a plan reaches control this long after it was started (simulated clock; measured at --speed 1)", kStart},
    {"avd_window", "m", 16, 4, 50, "half width of the planning window around the vehicle", kFlight},
    {"avd_window_up", "m", 4, 1, 20, "half height of the planning window", kFlight},
    {"avd_grid", "m", 0.4, 0.1, 2, "planning cell", kStart},
    {"avd_map_res", "m", 0.2, 0.05, 2, "3-D map cell (OctoMap resolution)", kStart},
    {"avd_map_cells", "-", 2000000, 10000, 50000000, "3-D map memory bound in leaves: past it the cells farthest from the vehicle are dropped", kStart},
    {"avd_min_alt", "m", 1.5, 0.5, 100, "lowest altitude a detour may take", kFlight},
    {"avd_lookahead", "m", 2, 0.5, 20, "the position reference leads the vehicle along the detour by this", kFlight},
    {"avd_hysteresis", "-", 0.15, 0, 2, "a detour being flown is kept unless a new one is this fraction shorter (no left/right flips)", kFlight},
    {"avd_yaw_rate", "deg/s", 60, 5, 360, "turn rate toward the way the vehicle flies (the forward cameras look ahead)", kFlight},
    {"fs_nav_land_s", "s", 5, 0, 60, "no position source (GPS lost, VO unhealthy): hold this long, then land", kFlight},
  }};
  return schema;
  }();
  return kSchema;
}

const ParameterSchema& CameraParameterSchema() {
  static const ParameterSchema kSchema{"camera", {
    {"sensor_width_mm", "mm", std::nullopt, 0.1, 100, "sensor extent along the image width"},
    {"sensor_height_mm", "mm", std::nullopt, 0.1, 100, "sensor extent along the image height"},
    {"focal_length_mm", "mm", std::nullopt, 0.1, 1000, "lens focal length"},
    {"image_width_px", "px", std::nullopt, 16, 20000, "image width"},
    {"image_height_px", "px", std::nullopt, 16, 20000, "image height"},
    {"landscape", "-", 1, 0, 1, "1: image width across the flight direction"},
    {"cx_px", "px", std::nullopt, 0, 20000, "principal point x (default: the image centre)", kStart, true},
    {"cy_px", "px", std::nullopt, 0, 20000, "principal point y (default: the image centre)", kStart, true},
    {"k1", "-", 0, -1, 1, "radial distortion (OpenCV k1)"},
    {"k2", "-", 0, -1, 1, "radial distortion (OpenCV k2)"},
    {"p1", "-", 0, -1, 1, "tangential distortion (OpenCV p1)"},
    {"p2", "-", 0, -1, 1, "tangential distortion (OpenCV p2)"},
    {"k3", "-", 0, -1, 1, "radial distortion (OpenCV k3)"},
  }};
  return kSchema;
}

}  // namespace uav
