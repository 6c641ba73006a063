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

#include "uav/shared/capture_folder.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/map_export.hpp"
#include "uav/vision/map_stitcher.hpp"

namespace {

using json = nlohmann::json;

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(what); }

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
    const uav::CaptureSession session = uav::ReadCaptureSession(dir + "/session.json");
    const std::vector<uav::CaptureRow> captures = uav::ReadCaptureRows(poses_path);
    if (captures.empty()) Fail(poses_path + ": no captures");
    for (const uav::CaptureRow& c : captures)
      if (!c.T_NB_estimate) Fail(c.problem);
    uav::vision::StitcherParams params;
    params.registration.detector = uav::vision::ParseDetector(detector);
    uav::vision::MapStitcher stitcher(session.camera, params);
    std::vector<double> ms;
    std::map<std::string, int> failures;
    int registered = 0, placed = 0;
    uav::ProgressBar progress(captures.size());
    for (size_t i = 0; i < captures.size(); ++i) {
      const uav::CaptureRow& c = captures[i];
      const cv::Mat image = cv::imread(dir + "/" + c.file, cv::IMREAD_COLOR);
      if (image.empty()) Fail(dir + "/" + c.file + ": missing or not an image");
      const Eigen::Isometry3d& T_NB = *c.T_NB_estimate;
      const uav::vision::StitchStep step = stitcher.Add({image, c.utime, T_NB * session.T_BC});
      placed += step.placed;
      registered += step.registered;
      if (!step.failure.empty()) ++failures[step.failure.substr(0, step.failure.find(" ("))];
      ms.push_back(step.seconds * 1e3);
      progress.Update(i + 1);
    }
    progress.Finish(captures.size());
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
