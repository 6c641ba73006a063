// Survey planning: coverage is proven by rasterising the footprint of every planned image at its
// planned pose (from the capture heading and the camera, not from the planner's grid), over
// convex, concave and rotated areas.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "uav/waypoints/survey.hpp"

namespace uav::waypoints {
namespace {

// The simulator's downward camera: 4.8 x 3.6 mm, 3.6 mm lens, 640 x 480 px.
const CameraSpec kSimCam{4.8, 3.6, 3.6, 640, 480, true};

Polygon2 Rotated(Polygon2 poly, double deg) {
  const double a = deg * M_PI / 180.0, c = std::cos(a), s = std::sin(a);
  for (auto& v : poly) v = Eigen::Vector2d(c * v.x() - s * v.y(), s * v.x() + c * v.y());
  return poly;
}

struct CoverageResult {
  double covered_fraction;        // polygon cells seen by at least one image
  double interior_full_fraction;  // interior cells seen by the number of images the overlaps imply
  int interior_cells;
};

// Rasterises the polygon and every footprint. "Interior" cells are those at least one footprint
// diagonal from the boundary; there the requested overlaps imply each point is seen by at least
// floor(1/(1-front)) * floor(1/(1-side)) images per pass.
CoverageResult MeasureCoverage(const Polygon2& poly, const SurveyParams& p, const SurveyPlan& plan) {
  const double cell = std::min(plan.footprint.across_m, plan.footprint.along_m) / 24.0;
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  for (const auto& v : poly) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const int rows = static_cast<int>((hi.x() - lo.x()) / cell) + 1, cols = static_cast<int>((hi.y() - lo.y()) / cell) + 1;
  cv::Mat inside(rows, cols, CV_8U, cv::Scalar(0));
  for (int r = 0; r < rows; ++r)
    for (int k = 0; k < cols; ++k) inside.at<uint8_t>(r, k) = Contains(poly, {lo.x() + r * cell, lo.y() + k * cell}) ? 255 : 0;

  // Counts exactly at cell centres (closed footprints), so rasterisation cannot shave the
  // overlap at the limit where it holds with equality.
  cv::Mat count(rows, cols, CV_16U, cv::Scalar(0));
  for (const auto& c : plan.captures) {
    const auto q = FootprintCorners(p, plan.altitude_m, c);
    Eigen::Vector2d qlo = q[0], qhi = q[0];
    for (const auto& v : q) qlo = qlo.cwiseMin(v), qhi = qhi.cwiseMax(v);
    const int r0 = std::max(0, static_cast<int>((qlo.x() - lo.x()) / cell) - 1);
    const int r1 = std::min(rows - 1, static_cast<int>((qhi.x() - lo.x()) / cell) + 1);
    const int c0 = std::max(0, static_cast<int>((qlo.y() - lo.y()) / cell) - 1);
    const int c1 = std::min(cols - 1, static_cast<int>((qhi.y() - lo.y()) / cell) + 1);
    for (int r = r0; r <= r1; ++r)
      for (int k = c0; k <= c1; ++k) {
        const Eigen::Vector2d pt(lo.x() + r * cell, lo.y() + k * cell);
        bool in = true;
        for (int i = 0; i < 4 && in; ++i) {
          const Eigen::Vector2d e = q[(i + 1) % 4] - q[i], d = pt - q[i];
          in = e.x() * d.y() - e.y() * d.x() <= 1e-9;  // corners run clockwise in (north, east)
        }
        count.at<uint16_t>(r, k) += in;
      }
  }

  const double reach = std::hypot(plan.footprint.across_m, plan.footprint.along_m) / cell;
  const int k = 2 * static_cast<int>(std::ceil(reach)) + 1;
  cv::Mat interior;
  // Outside the raster is outside the polygon (OpenCV's default border would not erode there).
  cv::erode(inside, interior, cv::getStructuringElement(cv::MORPH_ELLIPSE, {k, k}), {-1, -1}, 1,
            cv::BORDER_CONSTANT, cv::Scalar(0));

  const int passes = p.crosshatch ? 2 : 1;
  const int need = passes * static_cast<int>(std::floor(1.0 / (1.0 - p.front_overlap) + 1e-9)) *
                   static_cast<int>(std::floor(1.0 / (1.0 - p.side_overlap) + 1e-9));
  long in = 0, covered = 0, interior_n = 0, interior_full = 0;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) {
      if (!inside.at<uint8_t>(r, c)) continue;
      const int n = count.at<uint16_t>(r, c);
      ++in;
      covered += n >= 1;
      if (interior.at<uint8_t>(r, c)) ++interior_n, interior_full += n >= need;
    }
  return {static_cast<double>(covered) / in, interior_n ? static_cast<double>(interior_full) / interior_n : 1.0,
          static_cast<int>(interior_n)};
}

struct Case {
  const char* name;
  Polygon2 area;
  double grid_angle_deg;
  int entry_corner;
  bool crosshatch;
  bool landscape;
  double mount_yaw_deg;
  bool by_distance;
};

Polygon2 Rect(double n, double e) { return {{0, 0}, {n, 0}, {n, e}, {0, e}}; }
Polygon2 LShape() { return {{0, 0}, {0, 240}, {110, 240}, {110, 100}, {230, 100}, {230, 0}}; }
Polygon2 UShape() { return {{0, 0}, {0, 240}, {200, 240}, {200, 170}, {60, 170}, {60, 70}, {200, 70}, {200, 0}}; }

class SurveyCoverage : public testing::TestWithParam<Case> {};

TEST_P(SurveyCoverage, EveryPointIsSeenWithTheRequestedOverlap) {
  const Case& c = GetParam();
  SurveyParams p;
  p.camera = kSimCam;
  p.camera.landscape = c.landscape;
  p.camera_mount_yaw_deg = c.mount_yaw_deg;
  p.altitude_m = 12.0;  // footprint 16 x 12 m
  p.front_overlap = 0.75;
  p.side_overlap = 0.6;
  p.grid_angle_deg = c.grid_angle_deg;
  p.entry_corner = c.entry_corner;
  p.crosshatch = c.crosshatch;
  p.speed_m_s = 3.0;
  if (c.by_distance) p.trigger_distance_m = TriggerDistance(FootprintAt(p.camera, p.altitude_m), p.front_overlap);
  const SurveyPlan plan = PlanSurvey(c.area, p);
  ASSERT_TRUE(plan.ok()) << plan.overlap_problem;
  const CoverageResult r = MeasureCoverage(c.area, p, plan);
  EXPECT_GE(r.covered_fraction, 0.999) << c.name;
  EXPECT_GT(r.interior_cells, 1000) << c.name << ": the test area is too small to have an interior";
  EXPECT_GE(r.interior_full_fraction, 0.999) << c.name;
  EXPECT_NEAR(plan.polygon_area_m2, std::abs(SignedArea(c.area)), 1e-6);
  EXPECT_GE(plan.covered_area_m2, plan.polygon_area_m2);
}

INSTANTIATE_TEST_SUITE_P(
    Areas, SurveyCoverage,
    testing::Values(Case{"convex_rectangle", Rect(200, 150), 0, 0, false, true, 0, true},
                    Case{"convex_rectangle_by_rate", Rect(200, 150), 0, 0, false, true, 0, false},
                    Case{"rotated_quadrilateral", Rotated({{0, 0}, {180, 30}, {210, 200}, {-20, 160}}, 25), 30, 1, false, true, 0, true},
                    Case{"concave_l", LShape(), 0, 2, false, true, 0, true},
                    Case{"concave_l_across", LShape(), 90, 3, false, true, 0, true},
                    Case{"concave_u_gap", UShape(), 0, 0, false, true, 0, true},
                    Case{"concave_u_along_gap", UShape(), 90, 0, false, true, 0, true},
                    Case{"rotated_concave", Rotated(LShape(), 37), 17, 1, false, true, 0, true},
                    Case{"crosshatch", Rect(160, 160), 20, 0, true, true, 0, true},
                    Case{"portrait_mount_yaw", Rotated(UShape(), -50), 65, 2, false, false, 90, true}),
    [](const testing::TestParamInfo<Case>& info) { return std::string(info.param.name); });

TEST(SurveyCoverageCheck, FailsWhenALineIsMissing) {
  // The measurement itself must be able to fail: drop one line's images.
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 12.0;
  p.trigger_distance_m = 3.0;
  SurveyPlan plan = PlanSurvey(Rect(200, 150), p);
  const int dropped = plan.lines / 2;
  plan.captures.erase(std::remove_if(plan.captures.begin(), plan.captures.end(),
                                     [&](const SurveyCapture& c) { return c.line == dropped; }),
                      plan.captures.end());
  const CoverageResult r = MeasureCoverage(Rect(200, 150), p, plan);
  EXPECT_LT(r.interior_full_fraction, 0.99);
}

TEST(Survey, GeometryFollowsTheCameraCalculation) {
  SurveyParams p;
  p.camera = kSimCam;
  p.gsd_cm_per_px = 2.0;  // altitude = 2 * 640 * 3.6 / (4.8 * 100) = 9.6 m
  p.front_overlap = 0.8;
  p.side_overlap = 0.7;
  p.trigger_distance_m = 1.0;
  const SurveyPlan plan = PlanSurvey(Rect(100, 100), p);
  EXPECT_NEAR(plan.altitude_m, 9.6, 1e-9);
  EXPECT_NEAR(plan.footprint.gsd_cm_per_px, 2.0, 1e-9);
  EXPECT_NEAR(plan.line_spacing_m, 12.8 * 0.3, 1e-9);
  EXPECT_NEAR(plan.required_trigger_distance_m, 9.6 * 0.2, 1e-9);
  for (const auto& c : plan.captures) EXPECT_NEAR(c.p_N.z(), -9.6, 1e-9);
  // Lines are parallel to the grid angle (0: north), so each line has one east coordinate.
  for (const auto& w : plan.waypoints) {
    const auto& first = *std::find_if(plan.waypoints.begin(), plan.waypoints.end(), [&](const SurveyWaypoint& o) { return o.line == w.line; });
    EXPECT_NEAR(w.p_N.y(), first.p_N.y(), 1e-9);
  }
}

TEST(Survey, ZigZagAlternatesAndEntryCornerChoosesTheStart) {
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 20.0;
  p.trigger_distance_m = 2.0;
  p.turnaround_m = 0;
  const Polygon2 area = Rect(100, 100);
  Eigen::Vector2d starts[4];
  for (int corner = 0; corner < 4; ++corner) {
    p.entry_corner = corner;
    const SurveyPlan plan = PlanSurvey(area, p);
    starts[corner] = plan.waypoints.front().p_N.head<2>();
    // Direction alternates line by line.
    double prev = 0;
    for (int line = 0; line < plan.lines; ++line) {
      std::vector<SurveyWaypoint> wps;
      for (const auto& w : plan.waypoints)
        if (w.line == line) wps.push_back(w);
      const double dir = wps.back().p_N.x() - wps.front().p_N.x();
      if (line > 0) {
        EXPECT_LT(dir * prev, 0) << "line " << line;
      }
      prev = dir;
    }
  }
  EXPECT_LT(starts[0].x(), 50);  // corner 0: south-west (left of a northbound grid), flying north
  EXPECT_LT(starts[0].y(), 50);
  EXPECT_GT(starts[1].x(), 50);  // corner 1: same line, flown south
  EXPECT_LT(starts[1].y(), 50);
  EXPECT_LT(starts[2].x(), 50);  // corner 2: the east-most line
  EXPECT_GT(starts[2].y(), 50);
  EXPECT_GT(starts[3].x(), 50);
  EXPECT_GT(starts[3].y(), 50);
}

// A fixed wing cannot turn onto the next line 21 m across with a 30 m radius: the lines are
// flown out of order, each at least two radii from the last, and cover exactly what the
// adjacent order covers.
TEST(Survey, AFixedWingFliesLinesAtLeastTwoTurnRadiiApart) {
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 40;
  p.speed_m_s = 12;
  p.turnaround_m = 40;
  const Polygon2 area = {{0, 0}, {300, 0}, {300, 200}, {0, 200}};
  const SurveyPlan adjacent = PlanSurvey(area, p);
  p.turn_radius_m = 30;
  const SurveyPlan wing = PlanSurvey(area, p);
  ASSERT_TRUE(wing.ok());
  EXPECT_EQ(wing.lines, adjacent.lines);
  EXPECT_EQ(wing.captures.size(), adjacent.captures.size());
  EXPECT_EQ(wing.tight_turns, 0);
  // Each line's east coordinate, in the order flown.
  auto order = [](const SurveyPlan& plan) {
    std::vector<double> east;
    for (const auto& w : plan.waypoints)
      if (w.kind == SurveyWaypoint::Kind::kCaptureStart) east.push_back(w.p_N.y());
    return east;
  };
  const std::vector<double> flown = order(wing);
  std::vector<double> sorted = flown, adjacent_east = order(adjacent);
  std::sort(sorted.begin(), sorted.end());
  std::sort(adjacent_east.begin(), adjacent_east.end());
  ASSERT_EQ(sorted.size(), adjacent_east.size());
  for (std::size_t i = 0; i < sorted.size(); ++i) EXPECT_NEAR(sorted[i], adjacent_east[i], 1e-9);  // each line once
  for (std::size_t i = 1; i < flown.size(); ++i) EXPECT_GE(std::abs(flown[i] - flown[i - 1]), 60.0 - 1e-6) << i;
  EXPECT_LT(adjacent.line_spacing_m, 60.0);  // the adjacent order would turn tighter
  // Each line is flown the other way from the last: the vehicle turns around.
  std::vector<double> yaw;
  for (const auto& w : wing.waypoints)
    if (w.kind == SurveyWaypoint::Kind::kCaptureStart) yaw.push_back(w.yaw_rad);
  for (std::size_t i = 1; i < yaw.size(); ++i)
    EXPECT_NEAR(std::abs(std::remainder(yaw[i] - yaw[i - 1], 2 * M_PI)), M_PI, 1e-9) << i;
  const CoverageResult a = MeasureCoverage(area, p, adjacent), b = MeasureCoverage(area, p, wing);
  EXPECT_DOUBLE_EQ(a.covered_fraction, b.covered_fraction);
  // With lines too few to skip (two, 21 m apart), the one turn is counted as tight.
  p.turn_radius_m = 200;
  const SurveyPlan narrow = PlanSurvey(Polygon2{{0, 0}, {300, 0}, {300, 70}, {0, 70}}, p);
  EXPECT_EQ(narrow.tight_turns, narrow.lines - 1);
  p.turn_radius_m = -1;
  EXPECT_THROW(PlanSurvey(area, p), std::invalid_argument);
}

TEST(Survey, ReportsWhenSpeedAndRateCannotGiveTheFrontOverlap) {
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 12.0;          // along-track footprint 12 m
  p.front_overlap = 0.75;       // images at most 3 m apart
  p.capture_rate_hz = 1.0;
  p.speed_m_s = 3.0;            // 3 m apart: just enough
  EXPECT_TRUE(PlanSurvey(Rect(100, 100), p).ok());
  p.speed_m_s = 3.1;
  const SurveyPlan plan = PlanSurvey(Rect(100, 100), p);
  EXPECT_FALSE(plan.ok());
  EXPECT_NEAR(plan.suggested_speed_m_s, 3.0, 1e-9);
  EXPECT_NE(plan.overlap_problem.find("fly at 3 m/s or slower"), std::string::npos) << plan.overlap_problem;
  p.trigger_distance_m = 3.5;
  EXPECT_NE(PlanSurvey(Rect(100, 100), p).overlap_problem.find("trigger distance"), std::string::npos);
}

TEST(Survey, FlightTimeAndImageCountOfASingleLine) {
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 30.0;  // footprint 40 x 30 m: one line covers a 20 m wide strip
  p.trigger_distance_m = 5.0;
  p.turnaround_m = 10.0;
  p.speed_m_s = 4.0;
  p.accel_m_s2 = 2.0;
  const SurveyPlan plan = PlanSurvey(Rect(200, 20), p);
  ASSERT_EQ(plan.lines, 1);
  // Span 200 m, footprint 30 m along: centres over 170 m at 5 m: 35 images.
  EXPECT_EQ(plan.captures.size(), 35u);
  EXPECT_NEAR(plan.path_length_m, 170.0 + 2 * 10.0, 1e-9);
  EXPECT_NEAR(plan.flight_time_s, 190.0 / 4.0 + 4.0 / 2.0, 1e-9);
}

TEST(Survey, RejectsBadAreasAndParameters) {
  SurveyParams p;
  p.camera = kSimCam;
  p.altitude_m = 20;
  auto message = [&](const Polygon2& a, const SurveyParams& q) {
    try {
      PlanSurvey(a, q);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message({{0, 0}, {10, 10}, {20, 20}}, p).find("zero-area"), std::string::npos);
  EXPECT_NE(message({{0, 0}, {10, 10}, {0, 10}, {10, 0}}, p).find("self-intersecting"), std::string::npos);
  EXPECT_NE(message({{0, 0}, {10, 0}}, p).find("at least 3"), std::string::npos);
  EXPECT_NE(message({{0, 0}, {NAN, 0}, {0, 10}}, p).find("finite"), std::string::npos);
  SurveyParams q = p;
  q.altitude_m = 121;
  EXPECT_NE(message(Rect(50, 50), q).find("altitude_m"), std::string::npos);
  q = p, q.altitude_m = 120;
  EXPECT_EQ(message(Rect(50, 50), q), "no error");
  q = p, q.side_overlap = 0.96;
  EXPECT_NE(message(Rect(50, 50), q).find("side_overlap"), std::string::npos);
  q = p, q.speed_m_s = NAN;
  EXPECT_NE(message(Rect(50, 50), q).find("speed_m_s"), std::string::npos);
  q = p, q.entry_corner = 4;
  EXPECT_NE(message(Rect(50, 50), q).find("entry_corner"), std::string::npos);
}

TEST(Polygon, BandProjectionMatchesBruteForce) {
  const Polygon2 poly = Rotated(UShape(), 23);
  for (double y = -100; y < 300; y += 17.3) {  // NOLINT
    const auto ivs = BandProjection(poly, y - 6, y + 6);
    // Sample the band densely: every inside point's x must be in an interval, and every
    // interval end must be approached by inside points.
    for (double yy = y - 6; yy <= y + 6; yy += 0.25)
      for (double x = -200; x < 400; x += 0.5)
        if (Contains(poly, {x, yy})) {
          bool in = false;
          for (const auto& iv : ivs) in |= x >= iv.lo - 1e-9 && x <= iv.hi + 1e-9;
          ASSERT_TRUE(in) << x << "," << yy;
        }  // NOLINT
    for (const auto& iv : ivs) {
      bool lo_hit = false, hi_hit = false;
      for (double yy = y - 6; yy <= y + 6; yy += 0.01) {
        lo_hit |= Contains(poly, {iv.lo + 0.2, yy});
        hi_hit |= Contains(poly, {iv.hi - 0.2, yy});
      }
      EXPECT_TRUE(lo_hit && hi_hit) << iv.lo << ".." << iv.hi;
    }
  }
}

}  // namespace
}  // namespace uav::waypoints
