#include "uav/waypoints/survey.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace uav::waypoints {
namespace {

constexpr double kDeg = M_PI / 180.0;

void Require(bool ok, const std::string& field, double v, const std::string& limits) {
  if (!ok) {
    std::ostringstream s;
    s << field << " = " << v << " is invalid: must be " << limits;
    throw std::invalid_argument(s.str());
  }
}

double WrapTwoPi(double a) {
  a = std::fmod(a, 2.0 * M_PI);
  return a < 0 ? a + 2.0 * M_PI : a;
}

// One survey line in the grid frame G of its pass (x along the lines, y to their right).
struct Leg {
  double x0, x1;  // first and last capture centre, x0 <= x1
  int captures;
};
struct Line {
  double y;
  std::vector<Leg> legs;  // sorted by x
};

// Grid frame G of a pass: rotating N by the line bearing.
struct GridFrame {
  double c, s;
  explicit GridFrame(double bearing_rad) : c(std::cos(bearing_rad)), s(std::sin(bearing_rad)) {}
  Eigen::Vector2d ToN(double x, double y) const { return {c * x - s * y, s * x + c * y}; }
};

// Lines in the order a vehicle that turns with `radius` flies them: from the first, each next
// line is the nearest unflown one at least two radii across; when none is, the farthest
// (counted in `tight`).
std::vector<Line> OrderForTurnRadius(const std::vector<Line>& lines, double radius, int* tight) {
  std::vector<Line> ordered;
  if (lines.empty()) return ordered;
  std::vector<bool> flown(lines.size(), false);
  std::size_t at = 0;
  flown[0] = true;
  ordered.push_back(lines[0]);
  for (std::size_t k = 1; k < lines.size(); ++k) {
    std::size_t next = lines.size(), farthest = lines.size();
    double nearest_d = 1e300, farthest_d = -1.0;
    for (std::size_t j = 0; j < lines.size(); ++j) {
      if (flown[j]) continue;
      const double d = std::abs(lines[j].y - lines[at].y);
      if (d >= 2 * radius - 1e-6 && d < nearest_d) nearest_d = d, next = j;
      if (d > farthest_d) farthest_d = d, farthest = j;
    }
    if (next == lines.size()) next = farthest, ++*tight;
    flown[next] = true;
    ordered.push_back(lines[next]);
    at = next;
  }
  return ordered;
}

// Straight-line time over `d` metres from rest to rest at cruise speed v, acceleration a.
double RestToRestTime(double d, double v, double a) {
  if (d <= 0) return 0.0;
  if (d >= v * v / a) return d / v + v / a;
  return 2.0 * std::sqrt(d / a);
}

// Cells of a grid covered by a union of convex quadrilaterals: the covered-area estimate.
class CoverageGrid {
 public:
  CoverageGrid(Eigen::Vector2d lo, Eigen::Vector2d hi, double cell) : lo_(lo), cell_(cell) {
    nx_ = std::max(1, static_cast<int>(std::ceil((hi.x() - lo.x()) / cell)));
    ny_ = std::max(1, static_cast<int>(std::ceil((hi.y() - lo.y()) / cell)));
    cells_.assign(static_cast<std::size_t>(nx_) * ny_, 0);
  }
  void Fill(const std::array<Eigen::Vector2d, 4>& quad) {
    double ylo = 1e300, yhi = -1e300;
    for (const auto& p : quad) ylo = std::min(ylo, p.y()), yhi = std::max(yhi, p.y());
    const int r0 = std::max(0, static_cast<int>(std::floor((ylo - lo_.y()) / cell_)));
    const int r1 = std::min(ny_ - 1, static_cast<int>(std::floor((yhi - lo_.y()) / cell_)));
    for (int r = r0; r <= r1; ++r) {
      const double y = lo_.y() + (r + 0.5) * cell_;
      double xa = 1e300, xb = -1e300;
      for (int i = 0; i < 4; ++i) {
        const auto& a = quad[i];
        const auto& b = quad[(i + 1) % 4];
        if ((a.y() > y) == (b.y() > y)) continue;
        const double x = a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
        xa = std::min(xa, x), xb = std::max(xb, x);
      }
      if (xa > xb) continue;
      const int c0 = std::max(0, static_cast<int>(std::ceil((xa - lo_.x()) / cell_ - 0.5)));
      const int c1 = std::min(nx_ - 1, static_cast<int>(std::floor((xb - lo_.x()) / cell_ - 0.5)));
      if (c0 <= c1)
        std::fill(cells_.begin() + static_cast<long>(r) * nx_ + c0,
                  cells_.begin() + static_cast<long>(r) * nx_ + c1 + 1, 1);
    }
  }
  double Area() const {
    return static_cast<double>(std::count(cells_.begin(), cells_.end(), 1)) * cell_ * cell_;
  }

 private:
  Eigen::Vector2d lo_;
  double cell_;
  int nx_, ny_;
  std::vector<uint8_t> cells_;
};

}  // namespace

void ValidateSurveyParams(const SurveyParams& p) {
  ValidateCamera(p.camera);
  Require(std::isfinite(p.camera_mount_yaw_deg), "camera_mount_yaw_deg", p.camera_mount_yaw_deg, "finite");
  Require(std::isfinite(p.altitude_m) && p.altitude_m >= 0 && p.altitude_m <= kMaxSurveyAltitude_m,
          "altitude_m", p.altitude_m, "in [0, 120] m (0: from the GSD)");
  if (p.altitude_m == 0) {
    Require(std::isfinite(p.gsd_cm_per_px) && p.gsd_cm_per_px > 0, "gsd_cm_per_px", p.gsd_cm_per_px,
            "positive when altitude_m is 0");
    const double alt = AltitudeForGsd(p.camera, p.gsd_cm_per_px);
    Require(alt >= 1.0 && alt <= kMaxSurveyAltitude_m, "gsd_cm_per_px", p.gsd_cm_per_px,
            "a GSD this camera reaches between 1 and 120 m (it needs " + std::to_string(alt) + " m)");
  } else {
    Require(p.altitude_m >= 1.0, "altitude_m", p.altitude_m, "at least 1 m");
  }
  Require(std::isfinite(p.front_overlap) && p.front_overlap >= 0 && p.front_overlap <= 0.95,
          "front_overlap", p.front_overlap, "in [0, 0.95]");
  Require(std::isfinite(p.side_overlap) && p.side_overlap >= 0 && p.side_overlap <= 0.95,
          "side_overlap", p.side_overlap, "in [0, 0.95]");
  Require(std::isfinite(p.grid_angle_deg), "grid_angle_deg", p.grid_angle_deg, "finite");
  Require(p.entry_corner >= 0 && p.entry_corner <= 3, "entry_corner", p.entry_corner, "0, 1, 2 or 3");
  Require(std::isfinite(p.turnaround_m) && p.turnaround_m >= 0 && p.turnaround_m <= 200,
          "turnaround_m", p.turnaround_m, "in [0, 200] m");
  Require(std::isfinite(p.turn_radius_m) && p.turn_radius_m >= 0 && p.turn_radius_m <= 500, "turn_radius_m",
          p.turn_radius_m, "in [0, 500] m (0: turns in place)");
  Require(std::isfinite(p.speed_m_s) && p.speed_m_s > 0 && p.speed_m_s <= 15, "speed_m_s", p.speed_m_s,
          "in (0, 15] m/s");
  Require(std::isfinite(p.capture_rate_hz) && p.capture_rate_hz > 0 && p.capture_rate_hz <= 30,
          "capture_rate_hz", p.capture_rate_hz, "in (0, 30] Hz");
  Require(std::isfinite(p.trigger_distance_m) && p.trigger_distance_m >= 0 && p.trigger_distance_m <= 1000,
          "trigger_distance_m", p.trigger_distance_m, "in [0, 1000] m (0: capture by rate)");
  Require(std::isfinite(p.accel_m_s2) && p.accel_m_s2 > 0 && p.accel_m_s2 <= 20, "accel_m_s2",
          p.accel_m_s2, "in (0, 20] m/s^2");
}

double SurveyAltitude(const SurveyParams& p) {
  return p.altitude_m > 0 ? p.altitude_m : AltitudeForGsd(p.camera, p.gsd_cm_per_px);
}

std::vector<Eigen::Vector2d> FootprintCorners(const SurveyParams& p, double altitude_m,
                                              const SurveyCapture& c) {
  // Image x (width) points to body right rotated by the mount yaw; image y to body back.
  const double w = altitude_m * p.camera.sensor_width_mm / p.camera.focal_length_mm;
  const double h = altitude_m * p.camera.sensor_height_mm / p.camera.focal_length_mm;
  const double a = c.yaw_rad + p.camera_mount_yaw_deg * kDeg;
  const Eigen::Vector2d right(-std::sin(a), std::cos(a)), forward(std::cos(a), std::sin(a));
  const Eigen::Vector2d centre = c.p_N.head<2>();
  return {centre + 0.5 * w * right + 0.5 * h * forward, centre - 0.5 * w * right + 0.5 * h * forward,
          centre - 0.5 * w * right - 0.5 * h * forward, centre + 0.5 * w * right - 0.5 * h * forward};
}

SurveyPlan PlanSurvey(const Polygon2& area_N, const SurveyParams& p) {
  ValidatePolygon(area_N);
  ValidateSurveyParams(p);
  for (const auto& v : area_N)
    if (v.norm() > 20000.0)
      throw std::invalid_argument("polygon vertex is " + std::to_string(v.norm() / 1000.0) +
                                  " km from home: surveys are planned within 20 km");

  SurveyPlan plan;
  plan.altitude_m = SurveyAltitude(p);
  plan.footprint = FootprintAt(p.camera, plan.altitude_m);
  plan.line_spacing_m = LineSpacing(plan.footprint, p.side_overlap);
  plan.required_trigger_distance_m = TriggerDistance(plan.footprint, p.front_overlap);
  plan.polygon_area_m2 = std::abs(SignedArea(area_N));
  const double W = plan.footprint.across_m, L = plan.footprint.along_m, S = plan.line_spacing_m;

  // Capture spacing: by distance if asked, else what the capture rate gives at the planned speed.
  const double by_rate = p.speed_m_s / p.capture_rate_hz;
  const double D = p.trigger_distance_m > 0 ? p.trigger_distance_m : by_rate;
  plan.capture_spacing_m = D;
  if (D > plan.required_trigger_distance_m * (1.0 + 1e-9)) {
    std::ostringstream s;
    s.precision(3);
    if (p.trigger_distance_m > 0) {
      s << "trigger distance " << D << " m is more than the " << plan.required_trigger_distance_m
        << " m that " << p.front_overlap * 100 << " % front overlap allows; use at most "
        << plan.required_trigger_distance_m << " m";
    } else {
      plan.suggested_speed_m_s = plan.required_trigger_distance_m * p.capture_rate_hz;
      s << "at " << p.speed_m_s << " m/s and " << p.capture_rate_hz << " Hz images are " << D
        << " m apart, more than the " << plan.required_trigger_distance_m << " m that "
        << p.front_overlap * 100 << " % front overlap allows; fly at " << plan.suggested_speed_m_s
        << " m/s or slower";
    }
    plan.overlap_problem = s.str();
  }

  const double alt = plan.altitude_m;
  const int passes = p.crosshatch ? 2 : 1;
  Eigen::Vector2d bb_lo(1e300, 1e300), bb_hi(-1e300, -1e300);
  std::vector<std::array<Eigen::Vector2d, 4>> strips;  // union of each leg's footprints, in N
  for (int pass = 0; pass < passes; ++pass) {
    const double bearing = (p.grid_angle_deg + 90.0 * pass) * kDeg;
    const GridFrame G(bearing);
    const Polygon2 poly = RotateInto(area_N, bearing);
    double ymin = 1e300, ymax = -1e300;
    for (const auto& v : poly) ymin = std::min(ymin, v.y()), ymax = std::max(ymax, v.y());

    // Lines centred on the polygon's extent, as few as cover it with the side overlap.
    const double extent = ymax - ymin;
    const int n = extent <= W ? 1 : static_cast<int>(std::ceil((extent - W) / S - 1e-9)) + 1;
    const double y0 = 0.5 * (ymin + ymax) - 0.5 * (n - 1) * S;
    std::vector<Line> lines;
    for (int k = 0; k < n; ++k) {
      Line line{y0 + k * S, {}};
      // Gaps shorter than a footprint are flown through with the camera on.
      std::vector<Interval> spans;
      for (const auto& iv : BandProjection(poly, line.y - 0.5 * W, line.y + 0.5 * W)) {
        if (!spans.empty() && iv.lo - spans.back().hi < L) spans.back().hi = iv.hi;
        else spans.push_back(iv);
      }
      for (const auto& iv : spans) {
        // Centred captures whose footprints reach both ends of the span.
        const int m = iv.hi - iv.lo <= L ? 1 : static_cast<int>(std::ceil((iv.hi - iv.lo - L) / D - 1e-9)) + 1;
        const double x0 = 0.5 * (iv.lo + iv.hi) - 0.5 * (m - 1) * D;
        line.legs.push_back({x0, x0 + (m - 1) * D, m});
      }
      if (!line.legs.empty()) lines.push_back(std::move(line));
    }

    // Entry: which line first and which way. The crosshatch pass starts at the corner nearest
    // to where the first pass ended.
    bool last_first = p.entry_corner & 2, against = p.entry_corner & 1;
    if (pass == 1 && !plan.waypoints.empty() && !lines.empty()) {
      const Eigen::Vector2d end = plan.waypoints.back().p_N.head<2>();
      double best = 1e300;
      for (int corner = 0; corner < 4; ++corner) {
        const Line& l = (corner & 2) ? lines.back() : lines.front();
        const double x = (corner & 1) ? l.legs.back().x1 + p.turnaround_m : l.legs.front().x0 - p.turnaround_m;
        const double d = (G.ToN(x, l.y) - end).norm();
        if (d < best) best = d, last_first = corner & 2, against = corner & 1;
      }
    }
    if (last_first) std::reverse(lines.begin(), lines.end());
    if (p.turn_radius_m > 0) lines = OrderForTurnRadius(lines, p.turn_radius_m, &plan.tight_turns);

    for (std::size_t li = 0; li < lines.size(); ++li) {
      const Line& line = lines[li];
      const int line_no = static_cast<int>(li);
      const bool backwards = against != (li % 2 == 1);
      const double dir = backwards ? -1.0 : 1.0;
      const double travel = WrapTwoPi(bearing + (backwards ? M_PI : 0.0));
      // Heading that puts the image the asked way round over the ground (see FootprintCorners).
      const double yaw = WrapTwoPi(travel - p.camera_mount_yaw_deg * kDeg + (p.camera.landscape ? 0.0 : -M_PI / 2));
      auto add_wp = [&](double x, SurveyWaypoint::Kind kind) {
        const Eigen::Vector2d q = G.ToN(x, line.y);
        plan.waypoints.push_back({Eigen::Vector3d(q.x(), q.y(), -alt), yaw, kind, pass, line_no});
      };
      std::vector<Leg> legs = line.legs;
      if (backwards) std::reverse(legs.begin(), legs.end());
      const double first = backwards ? legs.front().x1 : legs.front().x0;
      const double last = backwards ? legs.back().x0 : legs.back().x1;
      if (p.turnaround_m > 0) add_wp(first - dir * p.turnaround_m, SurveyWaypoint::Kind::kRunIn);
      for (const Leg& leg : legs) {
        const double a = backwards ? leg.x1 : leg.x0, b = backwards ? leg.x0 : leg.x1;
        add_wp(a, SurveyWaypoint::Kind::kCaptureStart);
        for (int i = 0; i < leg.captures; ++i) {
          const Eigen::Vector2d q = G.ToN(a + dir * i * D, line.y);
          plan.captures.push_back({Eigen::Vector3d(q.x(), q.y(), -alt), yaw, pass, line_no});
        }
        add_wp(b, SurveyWaypoint::Kind::kCaptureEnd);
        // The union of one leg's footprints is a rectangle when the captures overlap.
        const double xa = leg.x0 - 0.5 * L, xb = leg.x1 + 0.5 * L;
        if (D <= L) {
          strips.push_back({G.ToN(xa, line.y - 0.5 * W), G.ToN(xb, line.y - 0.5 * W),
                            G.ToN(xb, line.y + 0.5 * W), G.ToN(xa, line.y + 0.5 * W)});
        } else {
          for (int i = 0; i < leg.captures; ++i) {
            const double xc = leg.x0 + i * D;
            strips.push_back({G.ToN(xc - 0.5 * L, line.y - 0.5 * W), G.ToN(xc + 0.5 * L, line.y - 0.5 * W),
                              G.ToN(xc + 0.5 * L, line.y + 0.5 * W), G.ToN(xc - 0.5 * L, line.y + 0.5 * W)});
          }
        }
      }
      if (p.turnaround_m > 0) add_wp(last + dir * p.turnaround_m, SurveyWaypoint::Kind::kRunOut);
    }
    plan.lines += static_cast<int>(lines.size());
  }

  // Length and time: rest to rest between turns sharper than 30 degrees.
  const auto& wps = plan.waypoints;
  double run = 0.0;
  for (std::size_t i = 1; i < wps.size(); ++i) {
    const Eigen::Vector2d d = (wps[i].p_N - wps[i - 1].p_N).head<2>();
    plan.path_length_m += d.norm();
    run += d.norm();
    bool stop = i + 1 == wps.size();
    if (!stop) {
      const Eigen::Vector2d e = (wps[i + 1].p_N - wps[i].p_N).head<2>();
      stop = d.norm() > 1e-9 && e.norm() > 1e-9 && d.normalized().dot(e.normalized()) < std::cos(30 * kDeg);
    }
    if (stop) plan.flight_time_s += RestToRestTime(run, p.speed_m_s, p.accel_m_s2), run = 0.0;
  }

  for (const auto& q : strips)
    for (const auto& v : q) bb_lo = bb_lo.cwiseMin(v), bb_hi = bb_hi.cwiseMax(v);
  if (!strips.empty()) {
    const double cell = std::max({(bb_hi - bb_lo).maxCoeff() / 1024.0, std::min(W, L) / 16.0, 1e-3});
    CoverageGrid grid(bb_lo, bb_hi, cell);
    for (const auto& q : strips) grid.Fill(q);
    plan.covered_area_m2 = grid.Area();
  }
  return plan;
}

Polygon2 PolygonToNed(const std::vector<GeodeticPoint>& area, const LocalNedFrame& frame) {
  Polygon2 poly;
  poly.reserve(area.size());
  for (std::size_t i = 0; i < area.size(); ++i) {
    GeodeticPoint g = area[i];
    g.altitude_m = frame.home().altitude_m;
    try {
      ValidateGeodetic(g);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("polygon vertex " + std::to_string(i) + ": " + e.what());
    }
    poly.push_back(frame.ToNed(g).head<2>());
  }
  return poly;
}

SurveyPlan PlanSurvey(const std::vector<GeodeticPoint>& area, const GeodeticPoint& home,
                      const SurveyParams& p) {
  LocalNedFrame frame(home);
  return PlanSurvey(PolygonToNed(area, frame), p);
}

}  // namespace uav::waypoints
