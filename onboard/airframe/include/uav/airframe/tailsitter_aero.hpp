#pragma once
// U-Lion, the thesis's tail-sitter (2.6): the wing's aerodynamics over the whole angle-of-attack
// range, the coaxial rotor's slipstream by momentum theory, the four-bar wing sweep
// (Eq. 2.27-2.28) and the sliding battery's centre-of-gravity shift (2.6.3). Plain functions and
// classes fed plain data; no state, no clock.
#include <string>

namespace uav::airframe {

// Table 2.7.
struct WingGeometry {
  double area_m2 = 0.36;
  double span_m = 1.8;
  double chord_m = 0.2;
  double AspectRatio() const { return span_m * span_m / area_m2; }
  // Throws std::invalid_argument naming the entry: non-positive sizes, or an area that is not
  // span x chord within 10 % (a rectangular wing).
  void Validate() const;
};

// Where the thesis is silent, each coefficient is a named assumption with its source.
struct WingCoefficients {
  // Clark Y: zero-lift angle about -3.5 degrees (Abbott and von Doenhoff, Theory of Wing
  // Sections), so the section lift slope a0 = 2 pi x 0.95 gives Cl0 = a0 x 0.061.
  double section_lift_slope_per_rad = 2 * 3.14159265358979 * 0.95;
  double zero_lift_alpha_rad = -0.061;
  double stall_alpha_rad = 0.227;       // 13 deg: Clark Y at Re 1e5 stalls at 12-14 deg
  double blend_sharpness_per_rad = 50;  // M of Beard and McLain's blending (Eq. 4.10)
  double profile_drag = 0.02;           // CD0: Clark Y at Re 1.1e5 (Selig's low-Re data, 0.015-0.025)
  double oswald = 0.85;                 // span efficiency of a straight rectangular wing
  double normal_force_at_90 = 1.28;     // flat plate broadside, aspect ratio 9 (Hoerner: 1.2-1.3; 2-D 1.98)
  // Throws std::invalid_argument naming the entry out of its physical range.
  void Validate() const;
};

struct AeroCoefficients {
  double lift = 0.0;  // C_L (Eq. 2.23), perpendicular to the airflow
  double drag = 0.0;  // C_D (Eq. 2.24), along it
};

// Wing lift and drag at any angle of attack (thesis 2.6.2, Eq. 2.23-2.26). Attached flow: the
// finite wing's lift slope by lifting-line theory, a = a0 / (1 + a0 / (pi e AR)), and induced
// drag C_L^2 / (pi e AR). Past the stall: a flat plate whose normal-force coefficient is
// CN90 sin(alpha), so C_L = CN cos(alpha) and C_D = CN sin(alpha). The two are blended by
// Beard and McLain's sigmoid (Small Unmanned Aircraft, 2012, Eq. 4.9-4.10), so a tail-sitter
// in hover (90 degrees) and in cruise (a few degrees) is the same model.
class WingAerodynamics {
 public:
  // Throws std::invalid_argument naming the bad entry.
  WingAerodynamics(const WingGeometry& geometry, const WingCoefficients& coefficients);
  AeroCoefficients At(double alpha_rad) const;  // any angle; symmetric past +-180 deg
  double LiftSlopePerRad() const { return lift_slope_; }
  // Largest C_L over 0-90 degrees and where it is.
  double MaxLift() const { return cl_max_; }
  double MaxLiftAlphaRad() const { return cl_max_alpha_; }
  // [N] at airspeed [m/s], air density [kg/m^3].
  double Lift(double alpha_rad, double airspeed_mps, double rho) const;
  double Drag(double alpha_rad, double airspeed_mps, double rho) const;
  // The slowest level flight on the wing alone: sqrt(2 m g / (rho S C_Lmax)) [m/s].
  double StallSpeed(double mass_kg, double rho) const;
  const WingGeometry& geometry() const { return g_; }

 private:
  WingGeometry g_;
  WingCoefficients c_;
  double lift_slope_ = 0.0, cl_max_ = 0.0, cl_max_alpha_ = 0.0;
};

// Momentum theory for the coaxial rotor (thesis 2.6.2, vector thrust): the induced velocity
// at the disk in hover, v_i = sqrt(T / (2 rho A)) [m/s], and in axial flight V,
// v_i = -V/2 + sqrt(V^2/4 + T / (2 rho A)); the fully developed slipstream is V + 2 v_i. What the
// wing and the canards in the propwash see.
double InducedVelocity(double thrust_n, double disk_area_m2, double rho, double axial_speed_mps = 0.0);
double SlipstreamSpeed(double thrust_n, double disk_area_m2, double rho, double axial_speed_mps = 0.0);

// The wing-sweep four-bar linkage (thesis 2.6.2, Fig. 2.39): from the frame's joint distance
// EF, the servo rocker OA and half the wing's sweep beta, the driven link EB (Eq. 2.27) and
// the coupler AB (Eq. 2.28). Throws std::invalid_argument unless 0 < OA < EF and
// 0 < beta < 90 deg.
struct FourBarLinkage {
  double ef_m = 0.0, oa_m = 0.0, eb_m = 0.0, ab_m = 0.0;
  static FourBarLinkage Design(double ef_m, double oa_m, double beta_rad);
};

// Power and level-flight trim (thesis 2.6: hover on the rotor, cruise on the wing). Where the
// thesis is silent, named assumptions: the fuselage's parasite drag area, the rotor's figure
// of merit in hover and propulsive efficiency in cruise, the motors' and ESCs' efficiency, and
// the battery: 4S 2200 mAh (Table 2.9), 2.2 Ah at 14.8 V nominal.
struct PowerModel {
  double mass_kg = 2.2;
  double disk_area_m2 = 0.0613;          // one 11-inch disk (the coaxial pair shares it)
  double parasite_drag_area_m2 = 0.01;   // fuselage, gimbal, canards: C_D A, about 1 m x 0.1 m
  double figure_of_merit = 0.6;          // small propellers in hover
  double propulsive_efficiency = 0.7;    // in cruise
  double electrical_efficiency = 0.8;    // motors and ESCs
  double battery_wh = 32.6;
  void Validate() const;  // throws std::invalid_argument naming the entry
};

struct CruiseTrim {
  bool found = false;       // false: the wing cannot carry the weight at this speed
  double alpha_rad = 0.0;   // angle of attack (the fuselage along the thrust)
  double thrust_n = 0.0;
  double electric_w = 0.0;
  double endurance_min = 0.0;
};

// Hover on the rotor alone: T = m g, P = T v_i / FM (momentum theory), electric power.
double HoverElectricPower(const PowerModel& m, double rho);
double HoverEnduranceMin(const PowerModel& m, double rho);
// Level flight on the wing at `airspeed`: T cos(alpha) = D, T sin(alpha) + L = m g, the
// smallest such alpha (the wing-borne branch), and the power T (V + v_i) / eta.
CruiseTrim TrimCruise(const WingAerodynamics& wing, const PowerModel& m, double airspeed_mps, double rho);

// The sliding battery (thesis 2.6.3): moving `battery_kg` by `travel_m` moves the whole
// vehicle's centre of gravity by battery x travel / total [m].
double CgShift(double battery_kg, double travel_m, double total_kg);

}  // namespace uav::airframe
