// uav-stitch IMAGES_DIR --out MAP [--poses POSES.csv] [--camera FILE] [--report REPORT.json] [--detector ...]
// The onboard stitcher on a folder of images. Two kinds of folder:
//  - a capture folder as uav-onboard writes it (IMG_*.jpg, captures.csv with the navigation
//    solution per image, session.json with home and camera): a geo-referenced map;
//  - any folder of photos (no session.json): the images in name order, chained by registration
//    alone into a map in the first image's pixels (not geo-referenced).
// Then all frames are adjusted jointly and the map is rendered again without seams. Writes
// MAP.tif (GeoTIFF), MAP.png + .pgw + .prj, MAP.kml (a pixel map: MAP.png only), and a JSON
// report with every frame's placement and the alignment's residuals.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/capture_folder.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/geodesy.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/map_export.hpp"
#include "uav/vision/map_stitcher.hpp"

namespace {

using json = nlohmann::json;

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(what); }

struct Input {
  std::string path;
  int64_t utime = 0;
  std::optional<Eigen::Isometry3d> T_NC;
};

json Residuals(const uav::vision::ResidualStats& s) {
  return {{"matches", s.matches}, {"median_px", s.median_px}, {"p95_px", s.p95_px}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-stitch: stitch a folder of survey images into a map, adjusted jointly and blended without seams"};
  std::string dir, out, poses_path, camera_path, report_path, detector = "gftt";
  cli.add_option("IMAGES_DIR", dir, "a capture folder (IMG_*.jpg, captures.csv, session.json) or any folder of photos")
      ->required();
  cli.add_option("--out", out, "output prefix: writes OUT.tif, OUT.png (+ .pgw, .prj) and OUT.kml")->required();
  cli.add_option("--poses", poses_path, "poses CSV in captures.csv's format (default IMAGES_DIR/captures.csv)");
  cli.add_option("--camera", camera_path, "camera file (resources/cameras/*.camera) overriding the intrinsics");
  cli.add_option("--report", report_path, "write a JSON report here");
  cli.add_option("--detector", detector,
                 "gftt: good features + Lucas-Kanade (thesis); orb: FAST + ORB + brute force; sift: SIFT + FLANN")
      ->capture_default_str();
  CLI11_PARSE(cli, argc, argv);
  try {
    const bool capture_folder = std::filesystem::exists(dir + "/session.json");
    uav::CaptureSession session;
    std::vector<Input> inputs;
    std::vector<std::string> skipped;
    if (capture_folder) {
      session = uav::ReadCaptureSession(dir + "/session.json");
      if (poses_path.empty()) poses_path = dir + "/captures.csv";
      for (const uav::CaptureRow& c : uav::ReadCaptureRows(poses_path)) {
        if (!c.T_NB_estimate) Fail(c.problem);
        inputs.push_back({dir + "/" + c.file, c.utime, *c.T_NB_estimate * session.T_BC});
      }
    } else {
      if (!poses_path.empty()) Fail(dir + ": --poses needs the folder's session.json (home and camera mount)");
      for (const std::string& f : uav::ImageFilesIn(dir)) inputs.push_back({f, static_cast<int64_t>(inputs.size()), {}});
      if (inputs.empty()) Fail(dir + ": no images (and no session.json)");
      // Without a camera file, a pinhole without distortion over the first image's size: enough
      // for a map in pixels.
      const cv::Mat first = cv::imread(inputs[0].path, cv::IMREAD_COLOR);
      if (first.empty()) Fail(inputs[0].path + ": not an image");
      session.camera.width = first.cols;
      session.camera.height = first.rows;
      session.camera.fx = session.camera.fy = first.cols;
      session.camera.cx = (first.cols - 1) / 2.0;
      session.camera.cy = (first.rows - 1) / 2.0;
    }
    if (inputs.empty()) Fail(poses_path + ": no captures");
    if (!camera_path.empty()) session.camera = uav::IntrinsicsFromParameters(uav::ParameterSet::LoadFile(camera_path));
    uav::vision::StitcherParams params;
    params.registration.detector = uav::vision::ParseDetector(detector);
    uav::vision::MapStitcher stitcher(session.camera, params);
    std::vector<double> ms;
    std::map<std::string, int> failures;
    std::vector<std::string> placed_files;
    int registered = 0;
    uav::ProgressBar progress(inputs.size());
    for (size_t i = 0; i < inputs.size(); ++i) {
      const Input& in = inputs[i];
      const cv::Mat image = cv::imread(in.path, cv::IMREAD_COLOR);
      // A frame that cannot be used is named and left out; the others still are.
      std::string problem;
      if (image.empty()) problem = "missing or not an image";
      else if (image.cols != session.camera.width || image.rows != session.camera.height)
        problem = std::to_string(image.cols) + "x" + std::to_string(image.rows) + ", the camera's is " +
                  std::to_string(session.camera.width) + "x" + std::to_string(session.camera.height) + " (another camera?)";
      if (!problem.empty()) {
        skipped.push_back(in.path + ": " + problem);
        std::fprintf(stderr, "\nuav-stitch: skipped %s: %s\n", in.path.c_str(), problem.c_str());
        continue;
      }
      const uav::vision::StitchStep step = stitcher.Add({image, in.utime, in.T_NC});
      if (step.placed) placed_files.push_back(std::filesystem::path(in.path).filename().string());
      registered += step.registered;
      if (!step.failure.empty()) ++failures[step.failure.substr(0, step.failure.find(" ("))];
      ms.push_back(step.seconds * 1e3);
      progress.Update(i + 1);
    }
    progress.Finish(inputs.size());
    if (stitcher.frames() == 0) Fail(dir + ": no frame could be placed");
    std::fprintf(stderr, "uav-stitch: adjusting %d frames jointly...\n", stitcher.frames());
    const uav::vision::AlignmentReport alignment = stitcher.Align();
    std::fprintf(stderr, "uav-stitch: rendering the map without seams...\n");
    const uav::vision::Mosaic map = stitcher.RenderSeamless();
    std::vector<std::string> files;
    if (map.georeferenced) {
      files = uav::vision::ExportMap(map, session.home, out);
    } else {
      // A map in pixels: a PNG with the unmapped area transparent, nothing to place it on Earth.
      cv::Mat bgra;
      cv::cvtColor(map.bgr, bgra, cv::COLOR_BGR2BGRA);
      cv::Mat channels[4];
      cv::split(bgra, channels);
      channels[3] = map.mask;
      cv::merge(channels, 4, bgra);
      std::vector<uint8_t> png;
      cv::imencode(".png", bgra, png);
      uav::WriteFileAtomically(out + ".png", std::string(png.begin(), png.end()));
      files.push_back(out + ".png");
    }
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    json placements = json::array();
    const std::vector<uav::vision::FramePlacement> placed = stitcher.Placements();
    const uav::LocalNedFrame ned(session.home);
    for (size_t k = 0; k < placed.size(); ++k) {
      const uav::vision::FramePlacement& p = placed[k];
      json corners = json::array(), corners_deg = json::array();
      for (const Eigen::Vector2d& c : p.corners_NE) {
        corners.push_back({c.x(), c.y()});
        if (map.georeferenced) {
          const uav::GeodeticPoint g = ned.ToGeodetic({c.x(), c.y(), 0.0});
          corners_deg.push_back({g.latitude_deg, g.longitude_deg});
        }
      }
      json H = json::array();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) H.push_back(p.H_map_img(r, c));
      json row = {{"file", placed_files[k]}, {"utime", p.utime}, {"registered", p.registered}, {"H_map_img", H},
                  {map.georeferenced ? "corners_ne_m" : "corners_map_px", corners}};
      if (map.georeferenced) row["corners_lat_lon_deg"] = corners_deg;
      placements.push_back(row);
    }
    const uav::vision::GeoBox box = uav::vision::MapBounds(map, session.home);
    json report = {{"detector", detector},
                   {"frames", inputs.size()},
                   {"placed", stitcher.frames()},
                   {"registered", registered},
                   {"skipped", skipped},
                   {"failures", failures},
                   {"georeferenced", map.georeferenced},
                   {"ms_per_frame_median", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
                   {"ms_per_frame_max", sorted.empty() ? 0.0 : sorted.back()},
                   {"alignment",
                    {{"adjusted", alignment.adjusted},
                     {"solver", alignment.message},
                     {"along_track_pairs", alignment.consecutive_pairs},
                     {"cross_pass_pairs", alignment.cross_pairs},
                     {"cross_before", Residuals(alignment.cross_before)},
                     {"cross_after", Residuals(alignment.cross_after)},
                     {"all_before", Residuals(alignment.all_before)},
                     {"all_after", Residuals(alignment.all_after)},
                     {"matches_dropped", alignment.matches_dropped},
                     {"seconds_matching", alignment.seconds_matching},
                     {"seconds_solving", alignment.seconds_solving}}},
                   {"map_width_px", map.bgr.cols},
                   {"map_height_px", map.bgr.rows},
                   {"gsd_m", map.gsd_m},
                   {"tiles", stitcher.tiles()},
                   {"memory_mb", stitcher.memory_bytes() / 1e6},
                   {"files", files},
                   {"placements", placements}};
    if (map.georeferenced)
      report["bounds_deg"] = {{"north", box.north_deg}, {"south", box.south_deg}, {"east", box.east_deg}, {"west", box.west_deg}};
    if (!report_path.empty()) uav::WriteFileAtomically(report_path, report.dump(2) + "\n");
    std::printf("uav-stitch: %d of %zu frames placed (%d by registration), %dx%d px at %.3f m/px, median %.1f ms/frame\n",
                stitcher.frames(), inputs.size(), registered, map.bgr.cols, map.bgr.rows, map.gsd_m,
                sorted.empty() ? 0.0 : sorted[sorted.size() / 2]);
    std::printf("uav-stitch: alignment %s: cross-pass residual p95 %.2f -> %.2f px (%d pairs), all matches p95 %.2f -> %.2f px\n",
                alignment.adjusted ? "adjusted" : ("not adjusted (" + alignment.message + ")").c_str(),
                alignment.cross_before.p95_px, alignment.cross_after.p95_px, alignment.cross_pairs,
                alignment.all_before.p95_px, alignment.all_after.p95_px);
    for (const auto& f : files) std::printf("uav-stitch: wrote %s\n", f.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stitch: %s\n", e.what());
    return 2;
  }
}
