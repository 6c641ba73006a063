// uav-survey: plans a zig-zag survey over a latitude/longitude polygon and writes the mission
// (.plan, QGC WPL), the capture plan (CSV), a picture of the plan (PNG) and a JSON report.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/text_file.hpp"
#include "uav/waypoints/mission_file.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace wp = uav::waypoints;

namespace {

// "LAT,LON" pairs separated by spaces, semicolons or new lines; '#' starts a comment.
std::vector<uav::GeodeticPoint> ParseVertices(const std::string& text, const std::string& origin) {
  std::vector<uav::GeodeticPoint> out;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    line = line.substr(0, line.find('#'));
    for (char& c : line)
      if (c == ';' || c == '\t') c = ' ';
    std::istringstream words(line);
    std::string word;
    while (words >> word) {
      const auto lat_lon = uav::ParseDecimalList(word, 2);
      if (!lat_lon)
        throw std::invalid_argument(origin + ":" + std::to_string(line_no) + ": \"" + word +
                                    "\" is not LAT,LON (decimal degrees)");
      out.push_back({(*lat_lon)[0], (*lat_lon)[1], 0.0});
    }
  }
  return out;
}

uav::GeodeticPoint ParseHome(const std::string& s) {
  const auto v = uav::ParseDecimalList(s, 3);
  if (!v) throw std::invalid_argument("--home must be LAT,LON,ALT in decimal degrees and metres, got '" + s + "'");
  uav::GeodeticPoint g{(*v)[0], (*v)[1], (*v)[2]};
  uav::ValidateGeodetic(g);
  return g;
}

void DrawPicture(const std::string& path, const wp::Polygon2& area, const wp::SurveyParams& p,
                 const wp::SurveyPlan& plan) {
  // North up, east right; 1600 px on the long side.
  Eigen::Vector2d lo(1e300, 1e300), hi(-1e300, -1e300);
  auto grow = [&](const Eigen::Vector2d& v) { lo = lo.cwiseMin(v), hi = hi.cwiseMax(v); };
  for (const auto& v : area) grow(v);
  for (const auto& w : plan.waypoints) grow(w.p_N.head<2>());
  const double margin = 0.5 * std::max(plan.footprint.across_m, plan.footprint.along_m);
  lo -= Eigen::Vector2d::Constant(margin), hi += Eigen::Vector2d::Constant(margin);
  const double scale = 1600.0 / std::max(hi.x() - lo.x(), hi.y() - lo.y());
  const int rows = static_cast<int>((hi.x() - lo.x()) * scale) + 1, cols = static_cast<int>((hi.y() - lo.y()) * scale) + 1;
  auto px = [&](const Eigen::Vector2d& n) {
    return cv::Point(static_cast<int>((n.y() - lo.y()) * scale), static_cast<int>((hi.x() - n.x()) * scale));
  };
  cv::Mat img(rows, cols, CV_8UC3, cv::Scalar(250, 250, 250));
  cv::Mat cover(rows, cols, CV_8UC1, cv::Scalar(0));
  for (const auto& c : plan.captures) {
    std::vector<cv::Point> q;
    for (const auto& v : wp::FootprintCorners(p, plan.altitude_m, c)) q.push_back(px(v));
    cv::fillConvexPoly(cover, q, cv::Scalar(255));
  }
  img.setTo(cv::Scalar(235, 215, 190), cover);
  std::vector<cv::Point> poly;
  for (const auto& v : area) poly.push_back(px(v));
  cv::polylines(img, poly, true, cv::Scalar(0, 120, 0), 3, cv::LINE_AA);
  for (std::size_t i = 1; i < plan.waypoints.size(); ++i)
    cv::line(img, px(plan.waypoints[i - 1].p_N.head<2>()), px(plan.waypoints[i].p_N.head<2>()),
             cv::Scalar(200, 60, 20), 2, cv::LINE_AA);
  const std::size_t stride = std::max<std::size_t>(1, plan.captures.size() / 4000);
  for (std::size_t i = 0; i < plan.captures.size(); i += stride)
    cv::circle(img, px(plan.captures[i].p_N.head<2>()), 2, cv::Scalar(0, 0, 200), cv::FILLED);
  if (!plan.waypoints.empty()) cv::circle(img, px(plan.waypoints.front().p_N.head<2>()), 9, cv::Scalar(0, 160, 0), 3);
  cv::circle(img, px(Eigen::Vector2d::Zero()), 8, cv::Scalar(0, 0, 0), cv::FILLED);  // home
  std::vector<uchar> png;
  cv::imencode(".png", img, png);
  uav::WriteFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"Plans a zig-zag survey over a polygon and writes the mission files"};
  std::string polygon_text, polygon_file, home_text, camera_file = uav::ResourcePath("cameras/sim_downward_640x480.camera");
  std::string plan_out, wpl_out, captures_out, picture_out;
  wp::SurveyParams p;
  double front_pct = 75, side_pct = 60;
  bool portrait = false;
  bool list_camera_params = false;
  cli.add_flag("--list-camera-params", list_camera_params,
               "print every camera-file parameter (name, default, unit, limits, description) and exit");
  cli.add_option("--polygon", polygon_text, "area vertices \"LAT,LON LAT,LON ...\" (degrees)");
  cli.add_option("--polygon-file", polygon_file, "file of LAT,LON vertices, one or more per line");
  cli.add_option("--home", home_text, "home LAT,LON,ALT (default: first vertex at 0 m)");
  cli.add_option("--camera", camera_file, "camera file (resources/cameras/*.camera)")->capture_default_str();
  cli.add_flag("--portrait", portrait, "image height across the flight direction");
  cli.add_option("--mount-yaw", p.camera_mount_yaw_deg, "camera mounting yaw [deg] relative to body forward");
  auto* alt = cli.add_option("--altitude", p.altitude_m, "altitude above home [m], 1..120");
  cli.add_option("--gsd", p.gsd_cm_per_px, "ground sample distance [cm/px] instead of --altitude")->excludes(alt);
  cli.add_option("--front-overlap", front_pct, "front overlap [%]")->capture_default_str();
  cli.add_option("--side-overlap", side_pct, "side overlap [%]")->capture_default_str();
  cli.add_option("--angle", p.grid_angle_deg, "bearing of the survey lines [deg from north]")->capture_default_str();
  cli.add_option("--entry", p.entry_corner, "entry corner 0..3")->capture_default_str();
  cli.add_option("--turnaround", p.turnaround_m, "run-in/run-out beyond each line [m]")->capture_default_str();
  cli.add_option("--turn-radius", p.turn_radius_m,
                 "a fixed wing's turn radius [m]: consecutive lines at least two radii apart (0: adjacent lines in turn)")
      ->capture_default_str();
  cli.add_option("--speed", p.speed_m_s, "ground speed [m/s]")->capture_default_str();
  cli.add_option("--rate", p.capture_rate_hz, "capture rate [Hz]")->capture_default_str();
  cli.add_option("--trigger-distance", p.trigger_distance_m, "capture every N m instead of by rate");
  cli.add_flag("--crosshatch", p.crosshatch, "second pass at +90 degrees");
  uav::OutputFile(cli.add_option("--plan", plan_out, "write a QGroundControl .plan"));
  uav::OutputFile(cli.add_option("--wpl", wpl_out, "write a QGC WPL 110 file"));
  uav::OutputFile(cli.add_option("--captures", captures_out, "write the capture plan as CSV"));
  uav::OutputFile(cli.add_option("--picture", picture_out, "draw the plan as PNG"));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (list_camera_params) {
    std::cout << uav::DescribeSchema(uav::CameraParameterSchema());
    return 0;
  }

  try {
    std::vector<uav::GeodeticPoint> area;
    if (!polygon_file.empty()) area = ParseVertices(uav::ReadTextFile(polygon_file, "polygon file"), polygon_file);
    else if (!polygon_text.empty()) area = ParseVertices(polygon_text, "--polygon");
    else throw std::invalid_argument("give the area with --polygon or --polygon-file");
    if (area.empty()) throw std::invalid_argument("the polygon has no vertices");
    if (p.altitude_m == 0 && p.gsd_cm_per_px == 0) throw std::invalid_argument("give --altitude or --gsd");
    const uav::GeodeticPoint home =
        home_text.empty() ? uav::GeodeticPoint{area[0].latitude_deg, area[0].longitude_deg, 0.0} : ParseHome(home_text);
    p.camera = wp::CameraFromParameters(uav::ParameterSet::LoadFile(camera_file, uav::CameraParameterSchema()));
    if (portrait) p.camera.landscape = false;
    p.front_overlap = front_pct / 100.0;
    p.side_overlap = side_pct / 100.0;

    uav::LocalNedFrame frame(home);
    const wp::Polygon2 area_N = wp::PolygonToNed(area, frame);
    const wp::SurveyPlan plan = wp::PlanSurvey(area_N, p);

    nlohmann::json report = {
        {"altitude_m", plan.altitude_m},
        {"gsd_cm_per_px", plan.footprint.gsd_cm_per_px},
        {"footprint_across_m", plan.footprint.across_m},
        {"footprint_along_m", plan.footprint.along_m},
        {"line_spacing_m", plan.line_spacing_m},
        {"required_trigger_distance_m", plan.required_trigger_distance_m},
        {"capture_spacing_m", plan.capture_spacing_m},
        {"lines", plan.lines},
        {"turn_radius_m", p.turn_radius_m},
        {"tight_turns", plan.tight_turns},
        {"waypoints", plan.waypoints.size()},
        {"images", plan.captures.size()},
        {"path_length_m", plan.path_length_m},
        {"flight_time_s", plan.flight_time_s},
        {"polygon_area_m2", plan.polygon_area_m2},
        {"covered_area_m2", plan.covered_area_m2},
        {"ok", plan.ok()}};
    if (!plan.ok()) {
      report["problem"] = plan.overlap_problem;
      if (plan.suggested_speed_m_s > 0) report["suggested_speed_m_s"] = plan.suggested_speed_m_s;
    }
    std::cout << report.dump(2) << std::endl;
    if (!picture_out.empty()) DrawPicture(picture_out, area_N, p, plan);
    if (!plan.ok()) {
      std::cerr << "uav-survey: " << plan.overlap_problem << "; no mission written" << std::endl;
      return 2;
    }
    const wp::Mission mission = wp::MissionFromSurvey(area, home, p, plan);
    if (!plan_out.empty()) wp::WriteMissionFile(plan_out, mission);
    if (!wpl_out.empty()) wp::WriteMissionFile(wpl_out, mission);
    if (!captures_out.empty()) {
      std::ostringstream csv;
      csv.precision(10);
      csv << "index,pass,line,latitude_deg,longitude_deg,altitude_m,north_m,east_m,down_m,yaw_deg\n";
      for (std::size_t i = 0; i < plan.captures.size(); ++i) {
        const auto& c = plan.captures[i];
        const uav::GeodeticPoint g = frame.ToGeodetic(c.p_N);
        csv << i << ',' << c.pass << ',' << c.line << ',' << g.latitude_deg << ',' << g.longitude_deg << ','
            << -c.p_N.z() << ',' << c.p_N.x() << ',' << c.p_N.y() << ',' << c.p_N.z() << ','
            << c.yaw_rad * 180.0 / M_PI << '\n';
      }
      uav::WriteFileAtomically(captures_out, csv.str());
    }
  } catch (const std::exception& e) {
    std::cerr << "uav-survey: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}
