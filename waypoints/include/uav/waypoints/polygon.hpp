#pragma once
// Plane polygons in local metres (x north, y east, or any other right-handed plane frame) for
// survey planning: validation, area, point-in-polygon and the cross-sections the sweep uses.
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav::waypoints {

using Polygon2 = std::vector<Eigen::Vector2d>;  // vertices in order, not closed (last != first)

// Largest polygon accepted, in vertices: a hand-drawn survey area has tens.
constexpr std::size_t kMaxPolygonVertices = 1000;

// Throws std::invalid_argument naming what is wrong: fewer than 3 or more than
// kMaxPolygonVertices vertices, a non-finite coordinate, a repeated consecutive vertex, two edges
// that cross ("edges 2 and 5 cross"), or an area below 1 m^2.
void ValidatePolygon(const Polygon2& poly);

double SignedArea(const Polygon2& poly);  // > 0 counter-clockwise in (x, y)
bool Contains(const Polygon2& poly, const Eigen::Vector2d& p);  // even-odd rule

// Returns an empty string when no two non-adjacent edges cross, else "edges i and j cross".
std::string FindSelfIntersection(const Polygon2& poly);

// Rotates every vertex by -angle (so a direction at `angle` from +x becomes +x).
Polygon2 RotateInto(const Polygon2& poly, double angle_rad);

struct Interval {
  double lo, hi;
};

// The projection onto x of the part of the polygon with y in [y_lo, y_hi]: the x intervals a
// footprint band of that width must cover. Exact for any simple polygon (convex or not): between
// consecutive vertex heights every crossing pair of edges bounds a trapezoid, whose x extent is
// taken at both ends of the slab. Intervals come back sorted and disjoint.
std::vector<Interval> BandProjection(const Polygon2& poly, double y_lo, double y_hi);

}  // namespace uav::waypoints
