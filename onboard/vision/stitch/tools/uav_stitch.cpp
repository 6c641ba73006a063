// uav-stitch IMAGES_DIR --out MAP [--poses POSES.csv] [--report REPORT.json] [--detector gftt|orb|sift]
// The onboard stitcher on a folder of captures (as uav-onboard writes them: IMG_*.jpg,
// captures.csv with the navigation solution per image, session.json with home and camera).
// Writes MAP.tif (GeoTIFF), MAP.png + .pgw + .prj, MAP.kml, and a JSON report.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/map_export.hpp"
#include "uav/vision/map_stitcher.hpp"

namespace {

using json = nlohmann::json;

struct Capture {
  std::string file;
  int64_t utime = 0;
  Eigen::Vector3d p_N;
  uav::EulerAngles euler;
};

struct Session {
  uav::GeodeticPoint home;
  uav::CameraIntrinsics camera;
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
};

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(what); }

Session ReadSession(const std::string& path) {
  json j;
  try {
    j = json::parse(uav::ReadTextFile(path, "session file"));
    Session s;
    s.home.latitude_deg = j.at("home").at("latitude_deg");
    s.home.longitude_deg = j.at("home").at("longitude_deg");
    s.home.altitude_m = j.at("home").at("altitude_m");
    const json& c = j.at("camera");
    s.camera.width = c.at("width");
    s.camera.height = c.at("height");
    s.camera.fx = c.at("fx");
    s.camera.fy = c.at("fy");
    s.camera.cx = c.at("cx");
    s.camera.cy = c.at("cy");
    for (int i = 0; i < 5; ++i) s.camera.distortion[i] = c.at("distortion").at(i);
    for (int i = 0; i < 9; ++i) s.T_BC.linear()(i / 3, i % 3) = c.at("R_BC").at(i);
    for (int i = 0; i < 3; ++i) s.T_BC.translation()(i) = c.at("p_B").at(i);
    uav::ValidateGeodetic(s.home);
    uav::ValidateIntrinsics(s.camera);
    return s;
  } catch (const json::exception& e) {
    Fail(path + ": " + e.what());
  }
}

// captures.csv: the estimate columns are what the vehicle knew (the truth columns are for tests).
std::vector<Capture> ReadPoses(const std::string& path) {
  std::istringstream in(uav::ReadTextFile(path, "poses file"));
  std::string line;
  if (!std::getline(in, line)) Fail(path + ": empty");
  std::map<std::string, int> col;
  {
    std::istringstream h(line);
    std::string name;
    for (int i = 0; std::getline(h, name, ','); ++i) col[name] = i;
  }
  for (const char* need : {"utime", "file", "est_north_m", "est_east_m", "est_down_m", "est_roll_rad", "est_pitch_rad", "est_yaw_rad"})
    if (!col.count(need)) Fail(path + ": no column '" + std::string(need) + "'");
  std::vector<Capture> out;
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.empty()) continue;
    std::vector<std::string> f;
    std::istringstream r(line);
    for (std::string v; std::getline(r, v, ',');) f.push_back(v);
    if (f.size() < col.size()) Fail(path + ":" + std::to_string(row) + ": " + std::to_string(f.size()) + " fields, the header has " + std::to_string(col.size()));
    auto num = [&](const char* name) {
      try {
        size_t used = 0;
        const double v = std::stod(f[col[name]], &used);
        if (!std::isfinite(v) || used != f[col[name]].size()) throw std::invalid_argument("");
        return v;
      } catch (const std::exception&) {
        Fail(path + ":" + std::to_string(row) + ": " + name + " is not a finite number: '" + f[col[name]] + "'");
      }
    };
    Capture c;
    c.file = f[col["file"]];
    c.utime = static_cast<int64_t>(num("utime"));
    c.p_N = Eigen::Vector3d(num("est_north_m"), num("est_east_m"), num("est_down_m"));
    c.euler.phi = num("est_roll_rad");
    c.euler.theta = num("est_pitch_rad");
    c.euler.psi = num("est_yaw_rad");
    out.push_back(c);
  }
  return out;
}

void Progress(size_t done, size_t total) {
  const int width = 40;
  const int filled = static_cast<int>(width * done / std::max<size_t>(total, 1));
  std::fprintf(stderr, "\r[%s%s] %zu/%zu", std::string(filled, '#').c_str(), std::string(width - filled, ' ').c_str(), done, total);
  if (done == total) std::fprintf(stderr, "\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-stitch: stitch a folder of survey captures into a geo-referenced map"};
  std::string dir, out, poses_path, report_path, detector = "gftt";
  cli.add_option("IMAGES_DIR", dir, "folder of captures (IMG_*.jpg, captures.csv, session.json)")->required();
  cli.add_option("--out", out, "output prefix: writes OUT.tif, OUT.png (+ .pgw, .prj) and OUT.kml")->required();
  cli.add_option("--poses", poses_path, "poses CSV (default IMAGES_DIR/captures.csv)");
  cli.add_option("--report", report_path, "write a JSON report here");
  cli.add_option("--detector", detector,
                 "gftt: good features + Lucas-Kanade (thesis); orb: FAST + ORB + brute force; sift: SIFT + FLANN")
      ->capture_default_str();
  CLI11_PARSE(cli, argc, argv);
  try {
    if (poses_path.empty()) poses_path = dir + "/captures.csv";
    const Session session = ReadSession(dir + "/session.json");
    const std::vector<Capture> captures = ReadPoses(poses_path);
    if (captures.empty()) Fail(poses_path + ": no captures");
    uav::vision::StitcherParams params;
    params.registration.detector = uav::vision::ParseDetector(detector);
    uav::vision::MapStitcher stitcher(session.camera, params);
    std::vector<double> ms;
    std::map<std::string, int> failures;
    int registered = 0, placed = 0;
    for (size_t i = 0; i < captures.size(); ++i) {
      const Capture& c = captures[i];
      const cv::Mat image = cv::imread(dir + "/" + c.file, cv::IMREAD_COLOR);
      if (image.empty()) Fail(dir + "/" + c.file + ": missing or not an image");
      Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
      T_NB.linear() = uav::RotationNBFromEuler(c.euler);
      T_NB.translation() = c.p_N;
      const uav::vision::StitchStep step = stitcher.Add({image, c.utime, T_NB * session.T_BC});
      placed += step.placed;
      registered += step.registered;
      if (!step.failure.empty()) ++failures[step.failure.substr(0, step.failure.find(" ("))];
      ms.push_back(step.seconds * 1e3);
      Progress(i + 1, captures.size());
    }
    const uav::vision::Mosaic map = stitcher.Render();
    const std::vector<std::string> files = uav::vision::ExportMap(map, session.home, out);
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const uav::vision::GeoBox box = uav::vision::MapBounds(map, session.home);
    json report = {{"detector", detector},
                   {"frames", captures.size()},
                   {"placed", placed},
                   {"registered", registered},
                   {"fallbacks", placed - registered - 1},
                   {"failures", failures},
                   {"ms_per_frame_median", sorted[sorted.size() / 2]},
                   {"ms_per_frame_max", sorted.back()},
                   {"map_width_px", map.bgr.cols},
                   {"map_height_px", map.bgr.rows},
                   {"gsd_m", map.gsd_m},
                   {"tiles", stitcher.tiles()},
                   {"tile_memory_mb", stitcher.memory_bytes() / 1e6},
                   {"bounds_deg", {{"north", box.north_deg}, {"south", box.south_deg}, {"east", box.east_deg}, {"west", box.west_deg}}},
                   {"files", files}};
    if (!report_path.empty()) uav::WriteFileAtomically(report_path, report.dump(2) + "\n");
    std::printf("uav-stitch: %d of %zu frames placed (%d by registration), %dx%d px at %.3f m/px, median %.1f ms/frame\n",
                placed, captures.size(), registered, map.bgr.cols, map.bgr.rows, map.gsd_m, sorted[sorted.size() / 2]);
    for (const auto& f : files) std::printf("uav-stitch: wrote %s\n", f.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stitch: %s\n", e.what());
    return 2;
  }
}
