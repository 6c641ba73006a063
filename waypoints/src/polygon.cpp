#include "uav/waypoints/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace uav::waypoints {
namespace {

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

// Proper or touching intersection of segments ab and cd.
bool SegmentsIntersect(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& c,
                       const Eigen::Vector2d& d) {
  const double d1 = Cross(b - a, c - a), d2 = Cross(b - a, d - a);
  const double d3 = Cross(d - c, a - c), d4 = Cross(d - c, b - c);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0)))
    return true;
  auto on_segment = [](const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    return std::min(p.x(), q.x()) <= r.x() && r.x() <= std::max(p.x(), q.x()) &&
           std::min(p.y(), q.y()) <= r.y() && r.y() <= std::max(p.y(), q.y());
  };
  return (d1 == 0 && on_segment(a, b, c)) || (d2 == 0 && on_segment(a, b, d)) ||
         (d3 == 0 && on_segment(c, d, a)) || (d4 == 0 && on_segment(c, d, b));
}

// x where edge (a, b) crosses height y; the edge must span y.
double XAt(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double y) {
  if (b.y() == a.y()) return a.x();
  return a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
}

}  // namespace

double SignedArea(const Polygon2& poly) {
  double twice = 0.0;
  for (std::size_t i = 0; i < poly.size(); ++i)
    twice += Cross(poly[i], poly[(i + 1) % poly.size()]);
  return 0.5 * twice;
}

bool Contains(const Polygon2& poly, const Eigen::Vector2d& p) {
  bool inside = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const auto& a = poly[i];
    const auto& b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < XAt(a, b, p.y())) inside = !inside;
  }
  return inside;
}

std::string FindSelfIntersection(const Polygon2& poly) {
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = i + 1; j < n; ++j) {
      if (j == i + 1 || (i == 0 && j == n - 1)) continue;  // adjacent edges share a vertex
      if (SegmentsIntersect(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]))
        return "edges " + std::to_string(i) + " and " + std::to_string(j) + " cross";
    }
  }
  return {};
}

void ValidatePolygon(const Polygon2& poly) {
  if (poly.size() < 3)
    throw std::invalid_argument("polygon needs at least 3 vertices, got " + std::to_string(poly.size()));
  if (poly.size() > kMaxPolygonVertices)
    throw std::invalid_argument("polygon has " + std::to_string(poly.size()) + " vertices, more than " +
                                std::to_string(kMaxPolygonVertices));
  for (std::size_t i = 0; i < poly.size(); ++i) {
    if (!poly[i].allFinite())
      throw std::invalid_argument("polygon vertex " + std::to_string(i) + " is not a finite number");
    if ((poly[i] - poly[(i + 1) % poly.size()]).norm() < 1e-6)
      throw std::invalid_argument("polygon vertices " + std::to_string(i) + " and " +
                                  std::to_string((i + 1) % poly.size()) + " coincide");
  }
  const std::string crossing = FindSelfIntersection(poly);
  if (!crossing.empty()) throw std::invalid_argument("polygon is self-intersecting: " + crossing);
  const double area = std::abs(SignedArea(poly));
  if (area < 1.0)
    throw std::invalid_argument("polygon area is " + std::to_string(area) + " m^2: zero-area polygons cannot be surveyed");
}

Polygon2 RotateInto(const Polygon2& poly, double angle_rad) {
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  Polygon2 out;
  out.reserve(poly.size());
  for (const auto& p : poly) out.emplace_back(c * p.x() + s * p.y(), -s * p.x() + c * p.y());
  return out;
}

std::vector<Interval> BandProjection(const Polygon2& poly, double y_lo, double y_hi) {
  const std::size_t n = poly.size();
  std::vector<double> levels{y_lo, y_hi};
  for (const auto& p : poly)
    if (p.y() > y_lo && p.y() < y_hi) levels.push_back(p.y());
  std::sort(levels.begin(), levels.end());
  levels.erase(std::unique(levels.begin(), levels.end()), levels.end());

  std::vector<Interval> pieces;
  std::vector<std::pair<double, std::size_t>> crossings;  // (x at mid-slab, edge index)
  for (std::size_t k = 0; k + 1 < levels.size(); ++k) {
    const double ya = levels[k], yb = levels[k + 1], ym = 0.5 * (ya + yb);
    crossings.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % n];
      if ((a.y() > ym) != (b.y() > ym)) crossings.emplace_back(XAt(a, b, ym), i);
    }
    std::sort(crossings.begin(), crossings.end());
    // Inside between crossings 0-1, 2-3, ...: each pair bounds a trapezoid over [ya, yb].
    for (std::size_t c = 0; c + 1 < crossings.size(); c += 2) {
      const std::size_t e0 = crossings[c].second, e1 = crossings[c + 1].second;
      const auto &a0 = poly[e0], &b0 = poly[(e0 + 1) % n], &a1 = poly[e1], &b1 = poly[(e1 + 1) % n];
      const double xs[4] = {XAt(a0, b0, ya), XAt(a0, b0, yb), XAt(a1, b1, ya), XAt(a1, b1, yb)};
      pieces.push_back({*std::min_element(xs, xs + 4), *std::max_element(xs, xs + 4)});
    }
  }
  std::sort(pieces.begin(), pieces.end(), [](const Interval& a, const Interval& b) { return a.lo < b.lo; });
  std::vector<Interval> merged;
  for (const auto& p : pieces) {
    if (!merged.empty() && p.lo <= merged.back().hi) merged.back().hi = std::max(merged.back().hi, p.hi);
    else merged.push_back(p);
  }
  return merged;
}

}  // namespace uav::waypoints
