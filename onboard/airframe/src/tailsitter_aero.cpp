#include "uav/airframe/tailsitter_aero.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace uav::airframe {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kGravity = 9.80665;

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}

bool InRange(double x, double lo, double hi) { return std::isfinite(x) && x >= lo && x <= hi; }

// Beard and McLain, Eq. 4.10: about 0 below the stall angle, about 1 past it, either sign.
double Blend(double alpha, double alpha0, double m) {
  const double a = std::exp(-m * (alpha - alpha0)), b = std::exp(m * (alpha + alpha0));
  return (1 + a + b) / ((1 + a) * (1 + b));
}

}  // namespace

void WingGeometry::Validate() const {
  Require(InRange(area_m2, 1e-3, 100), "wing area_m2 must be in 0.001..100, got " + std::to_string(area_m2));
  Require(InRange(span_m, 0.05, 100), "wing span_m must be in 0.05..100, got " + std::to_string(span_m));
  Require(InRange(chord_m, 0.01, 20), "wing chord_m must be in 0.01..20, got " + std::to_string(chord_m));
  Require(std::abs(span_m * chord_m - area_m2) <= 0.1 * area_m2,
          "wing area_m2 " + std::to_string(area_m2) + " is not span x chord (" + std::to_string(span_m * chord_m) +
              ") within 10 %");
}

void WingCoefficients::Validate() const {
  Require(InRange(section_lift_slope_per_rad, 3.0, 7.0), "section_lift_slope_per_rad must be in 3..7 (thin airfoil: 2 pi)");
  Require(InRange(zero_lift_alpha_rad, -0.2, 0.05), "zero_lift_alpha_rad must be in -0.2..0.05");
  Require(InRange(stall_alpha_rad, 0.1, 0.4), "stall_alpha_rad must be in 0.1..0.4 (6-23 deg)");
  Require(InRange(blend_sharpness_per_rad, 5, 500), "blend_sharpness_per_rad must be in 5..500");
  Require(InRange(profile_drag, 0.005, 0.2), "profile_drag must be in 0.005..0.2");
  Require(InRange(oswald, 0.5, 1.0), "oswald must be in 0.5..1");
  Require(InRange(normal_force_at_90, 1.0, 2.1), "normal_force_at_90 must be in 1..2.1 (flat plates: 1.17-1.98)");
}

WingAerodynamics::WingAerodynamics(const WingGeometry& geometry, const WingCoefficients& coefficients)
    : g_(geometry), c_(coefficients) {
  g_.Validate();
  c_.Validate();
  // Lifting-line theory: the finite wing's slope (Anderson, Fundamentals of Aerodynamics, 5.3).
  const double a0 = c_.section_lift_slope_per_rad;
  lift_slope_ = a0 / (1 + a0 / (kPi * c_.oswald * g_.AspectRatio()));
  for (double alpha = 0; alpha <= kPi / 2 + 1e-9; alpha += kPi / 3600) {
    const double cl = At(alpha).lift;
    if (cl > cl_max_) cl_max_ = cl, cl_max_alpha_ = alpha;
  }
}

AeroCoefficients WingAerodynamics::At(double alpha) const {
  alpha = std::remainder(alpha, 2 * kPi);  // -pi..pi
  const double sigma = Blend(alpha, c_.stall_alpha_rad, c_.blend_sharpness_per_rad);
  const double cl_attached = lift_slope_ * (alpha - c_.zero_lift_alpha_rad);
  const double cd_attached = c_.profile_drag + cl_attached * cl_attached / (kPi * c_.oswald * g_.AspectRatio());
  const double cn = c_.normal_force_at_90 * std::sin(alpha);
  AeroCoefficients out;
  out.lift = (1 - sigma) * cl_attached + sigma * cn * std::cos(alpha);
  // The plate's drag never falls under the profile drag.
  out.drag = (1 - sigma) * cd_attached + sigma * std::max(c_.profile_drag, cn * std::sin(alpha));
  return out;
}

double WingAerodynamics::Lift(double alpha, double airspeed, double rho) const {
  return 0.5 * rho * airspeed * airspeed * g_.area_m2 * At(alpha).lift;  // Eq. 2.26
}

double WingAerodynamics::Drag(double alpha, double airspeed, double rho) const {
  return 0.5 * rho * airspeed * airspeed * g_.area_m2 * At(alpha).drag;  // Eq. 2.24
}

double WingAerodynamics::StallSpeed(double mass_kg, double rho) const {
  return std::sqrt(2 * mass_kg * kGravity / (rho * g_.area_m2 * cl_max_));
}

double InducedVelocity(double thrust_n, double disk_area_m2, double rho, double axial_speed_mps) {
  Require(std::isfinite(thrust_n) && thrust_n >= 0, "thrust must be finite and not negative");
  Require(std::isfinite(disk_area_m2) && disk_area_m2 > 0, "disk area must be positive");
  Require(std::isfinite(rho) && rho > 0, "air density must be positive");
  Require(std::isfinite(axial_speed_mps) && axial_speed_mps >= 0, "axial speed must be finite and not negative");
  const double v = axial_speed_mps;
  return -v / 2 + std::sqrt(v * v / 4 + thrust_n / (2 * rho * disk_area_m2));
}

double SlipstreamSpeed(double thrust_n, double disk_area_m2, double rho, double axial_speed_mps) {
  return axial_speed_mps + 2 * InducedVelocity(thrust_n, disk_area_m2, rho, axial_speed_mps);
}

FourBarLinkage FourBarLinkage::Design(double ef_m, double oa_m, double beta_rad) {
  Require(std::isfinite(ef_m) && ef_m > 0, "four-bar: EF must be positive");
  Require(std::isfinite(oa_m) && oa_m > 0 && oa_m < ef_m, "four-bar: the rocker OA must be positive and shorter than EF");
  Require(std::isfinite(beta_rad) && beta_rad > 0 && beta_rad < kPi / 2, "four-bar: beta must be in 0..90 deg");
  FourBarLinkage l;
  l.ef_m = ef_m;
  l.oa_m = oa_m;
  l.eb_m = 0.5 * ef_m * oa_m / ((ef_m - oa_m) * std::sin(beta_rad));  // Eq. 2.27
  l.ab_m = 0.5 * ef_m - oa_m + l.eb_m * std::sin(beta_rad);          // Eq. 2.28
  return l;
}

void PowerModel::Validate() const {
  Require(InRange(mass_kg, 0.1, 100), "mass_kg must be in 0.1..100");
  Require(InRange(disk_area_m2, 1e-3, 10), "disk_area_m2 must be in 0.001..10");
  Require(InRange(parasite_drag_area_m2, 0, 1), "parasite_drag_area_m2 must be in 0..1");
  Require(InRange(figure_of_merit, 0.3, 0.85), "figure_of_merit must be in 0.3..0.85");
  Require(InRange(propulsive_efficiency, 0.3, 0.9), "propulsive_efficiency must be in 0.3..0.9");
  Require(InRange(electrical_efficiency, 0.5, 1.0), "electrical_efficiency must be in 0.5..1");
  Require(InRange(battery_wh, 1, 10000), "battery_wh must be in 1..10000");
}

double HoverElectricPower(const PowerModel& m, double rho) {
  m.Validate();
  const double thrust = m.mass_kg * kGravity;
  return thrust * InducedVelocity(thrust, m.disk_area_m2, rho) / m.figure_of_merit / m.electrical_efficiency;
}

double HoverEnduranceMin(const PowerModel& m, double rho) { return 60.0 * m.battery_wh / HoverElectricPower(m, rho); }

CruiseTrim TrimCruise(const WingAerodynamics& wing, const PowerModel& m, double airspeed, double rho) {
  m.Validate();
  Require(std::isfinite(airspeed) && airspeed > 0, "airspeed must be positive");
  const double weight = m.mass_kg * kGravity, q = 0.5 * rho * airspeed * airspeed;
  // Lift plus the thrust's vertical share, less the weight, with the thrust set to balance the
  // drag: its first zero from a slight negative angle up is the wing-borne trim.
  const auto excess = [&](double alpha) {
    const AeroCoefficients c = wing.At(alpha);
    const double drag = q * (wing.geometry().area_m2 * c.drag + m.parasite_drag_area_m2);
    return q * wing.geometry().area_m2 * c.lift + drag * std::tan(alpha) - weight;
  };
  CruiseTrim t;
  double lo = -5 * kPi / 180;
  if (excess(lo) > 0) return t;  // more than enough lift even nose-down: not a trim we model
  for (double hi = lo + kPi / 360; hi < 80 * kPi / 180; lo = hi, hi += kPi / 360) {
    if (excess(hi) < 0) continue;
    for (int i = 0; i < 60; ++i) {
      const double mid = 0.5 * (lo + hi);
      (excess(mid) < 0 ? lo : hi) = mid;
    }
    t.found = true;
    t.alpha_rad = 0.5 * (lo + hi);
    break;
  }
  if (!t.found) return t;
  const AeroCoefficients c = wing.At(t.alpha_rad);
  t.thrust_n = q * (wing.geometry().area_m2 * c.drag + m.parasite_drag_area_m2) / std::cos(t.alpha_rad);
  const double axial = airspeed * std::cos(t.alpha_rad);
  t.electric_w = t.thrust_n * (axial + InducedVelocity(t.thrust_n, m.disk_area_m2, rho, axial)) /
                 m.propulsive_efficiency / m.electrical_efficiency;
  t.endurance_min = 60.0 * m.battery_wh / t.electric_w;
  return t;
}

double CgShift(double battery_kg, double travel_m, double total_kg) {
  Require(std::isfinite(battery_kg) && battery_kg > 0, "battery mass must be positive");
  Require(std::isfinite(total_kg) && total_kg >= battery_kg, "total mass must be at least the battery's");
  Require(std::isfinite(travel_m), "battery travel must be finite");
  return battery_kg * travel_m / total_kg;
}

}  // namespace uav::airframe
