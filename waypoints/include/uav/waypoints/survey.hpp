#pragma once
// Zig-zag (lawnmower) survey planning over a polygon (thesis 6.1, Fig. 6.3: "a sweep pattern path
// is generated online automatically from the GPS coordinates to maximize the image coverage").
// The camera calculation is QGroundControl's (camera_geometry.hpp); the sweep guarantees coverage
// of the whole polygon, convex or concave, which the tests prove by rasterising every footprint.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/camera_geometry.hpp"
#include "uav/waypoints/polygon.hpp"

namespace uav::waypoints {

// Highest survey altitude above home [m]: the legal ceiling for small UAVs (EU/US 120 m), the
// same limit as the command grammar's takeoff.
constexpr double kMaxSurveyAltitude_m = 120.0;

struct SurveyParams {
  CameraSpec camera;
  double camera_mount_yaw_deg = 0.0;  // camera image-up relative to body forward, clockwise
  double altitude_m = 0.0;            // above home; 0: derived from gsd_cm_per_px
  double gsd_cm_per_px = 0.0;         // used only when altitude_m is 0
  double front_overlap = 0.75;        // [0, 0.95] fraction of the footprint along track
  double side_overlap = 0.60;         // [0, 0.95] fraction of the footprint across track
  double grid_angle_deg = 0.0;        // bearing of the survey lines, clockwise from north
  // 0: first line on the left of the grid direction, flown along it; 1: that line flown against
  // it; 2: the last (right-most) line, flown along; 3: the last line flown against.
  int entry_corner = 0;
  double turnaround_m = 5.0;          // straight run-in/run-out beyond each capture leg
  // > 0 for a fixed wing: the radius of its turns at the survey speed. Lines closer than two
  // radii are not flown one after the other: the next line is the nearest unflown one at least
  // that far across (0, 3, 6, 2, 5, ... for lines a third of the distance apart).
  double turn_radius_m = 0.0;
  double speed_m_s = 3.0;             // ground speed on the capture legs
  double capture_rate_hz = 5.0;       // thesis 6.1: images at 5 Hz for the KLT tracker
  double trigger_distance_m = 0.0;    // > 0: capture every this many metres instead of by rate
  bool crosshatch = false;            // second pass with the grid at +90 degrees
  double accel_m_s2 = 1.0;            // for the flight-time estimate only
};

// Throws std::invalid_argument naming the field and its limits.
void ValidateSurveyParams(const SurveyParams& p);
// altitude_m, or the altitude that gives gsd_cm_per_px.
double SurveyAltitude(const SurveyParams& p);

struct SurveyCapture {
  Eigen::Vector3d p_N;  // [m] camera position in the local NED frame at home
  double yaw_rad;       // vehicle heading at the capture
  int pass;             // 0, or 1 for the crosshatch pass
  int line;             // survey line within the pass
};

struct SurveyWaypoint {
  enum class Kind { kRunIn, kCaptureStart, kCaptureEnd, kRunOut };
  Eigen::Vector3d p_N;  // [m] local NED at home
  double yaw_rad;       // heading to hold from here on
  Kind kind;
  int pass;
  int line;
};

struct SurveyPlan {
  double altitude_m = 0.0;
  Footprint footprint{};
  double line_spacing_m = 0.0;
  double required_trigger_distance_m = 0.0;  // footprint along * (1 - front overlap)
  double capture_spacing_m = 0.0;            // what the plan actually uses
  int lines = 0;                             // over all passes
  // With turn_radius_m: turns between lines closer than two radii (where no unflown line was
  // far enough across; the vehicle widens such a turn into a loop).
  int tight_turns = 0;
  std::vector<SurveyWaypoint> waypoints;
  std::vector<SurveyCapture> captures;
  double path_length_m = 0.0;   // first to last waypoint
  double flight_time_s = 0.0;   // first to last waypoint, with acceleration at each turn
  double polygon_area_m2 = 0.0;
  double covered_area_m2 = 0.0; // union of all footprints (inside the polygon or not)
  // Non-empty when speed and capture rate cannot give the front overlap asked for; then
  // suggested_speed_m_s is the fastest speed that can. The plan is still made (with less overlap)
  // so it can be drawn, but it must not be flown or exported as is.
  std::string overlap_problem;
  double suggested_speed_m_s = 0.0;
  bool ok() const { return overlap_problem.empty(); }
};

// Plans over a polygon given in the local NED plane (x north, y east, metres). Throws
// std::invalid_argument naming what is wrong with the polygon or the parameters.
SurveyPlan PlanSurvey(const Polygon2& area_N, const SurveyParams& p);

// The same over latitude/longitude vertices (altitude ignored), with NED at `home`.
Polygon2 PolygonToNed(const std::vector<GeodeticPoint>& area, const LocalNedFrame& frame);
SurveyPlan PlanSurvey(const std::vector<GeodeticPoint>& area, const GeodeticPoint& home,
                      const SurveyParams& p);

// Ground footprint corners (NED x, y) of an image taken at `c`, from the camera, its mounting and
// the capture heading: the rectangle the coverage test rasterises.
std::vector<Eigen::Vector2d> FootprintCorners(const SurveyParams& p, double altitude_m,
                                              const SurveyCapture& c);

}  // namespace uav::waypoints
