// uav-stitch IMAGES_DIR --out MAP [--poses POSES.csv] [--camera FILE] [--ground-altitude M] [--report REPORT.json]
// The onboard stitcher on a folder of images. Three kinds of folder:
//  - a capture folder as uav-onboard writes it (IMG_*.jpg, captures.csv with the navigation
//    solution per image, session.json with home and camera): a geo-referenced map;
//  - geotagged photos as drones write them (EXIF GPS position and focal length, DJI-style XMP
//    gimbal angles and height above take-off where present): a geo-referenced map;
//  - any other folder of photos: the images in name order, chained by registration alone into a
//    map in the first image's pixels (not geo-referenced).
// Then all frames are adjusted jointly and the map is rendered again without seams. Writes
// MAP.tif (GeoTIFF), MAP.png + .pgw + .prj, MAP.kml (a pixel map: MAP.png only), and a JSON
// report with every frame's placement and the alignment's residuals.
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <map>
#include <optional>
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
#include "uav/vision/photo_geotag.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

using json = nlohmann::json;

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument(what); }

struct Input {
  std::string path;
  int64_t utime = 0;
  std::optional<Eigen::Isometry3d> T_NC;
};

// This process's peak resident memory [MB] (the kernel's high-water mark; 0 where /proc is absent).
double PeakMemoryMb() {
  std::ifstream status("/proc/self/status");
  std::string key;
  while (status >> key) {
    if (key == "VmHWM:") {
      double kb = 0;
      status >> kb;
      return kb / 1024.0;
    }
    status.ignore(1 << 20, '\n');
  }
  return 0.0;
}

// Poses from the photos' geotags. Photos without a usable geotag, or from another camera than
// the first geotagged one, are named in `skipped`. Throws when no photo is geotagged.
struct GeotaggedFolder {
  uav::GeodeticPoint home;  // the ground under the first photo
  uav::CameraIntrinsics camera;  // from the first photo's EXIF; left for --camera when one is given
  std::string camera_name;
  std::vector<Input> inputs;
  int yaw_from_course = 0;  // photos whose heading came from the track, not a tag
};

GeotaggedFolder ReadGeotaggedFolder(const std::vector<std::string>& files, bool camera_given,
                                    std::optional<double> ground_altitude_m, std::vector<std::string>* skipped) {
  struct Tagged {
    std::string path;
    uav::vision::PhotoGeotag tag;
  };
  std::vector<Tagged> tagged;
  for (const std::string& f : files) {
    try {
      Tagged t{f, uav::vision::ReadPhotoGeotag(f)};
      // Heights: above take-off (XMP RelativeAltitude, barometric) unless the ground's altitude
      // is given, then the GPS altitude over it.
      if (!ground_altitude_m && !t.tag.height_above_takeoff_m)
        throw std::invalid_argument(f + ": no height above the ground (XMP RelativeAltitude); give --ground-altitude M, "
                                        "the ground's altitude in the photos' GPS altitude reference");
      if (ground_altitude_m && !t.tag.has_altitude) throw std::invalid_argument(f + ": no EXIF GPSAltitude");
      if (!tagged.empty() && (t.tag.camera != tagged[0].tag.camera || t.tag.width != tagged[0].tag.width ||
                              t.tag.height != tagged[0].tag.height))
        throw std::invalid_argument(f + ": another camera ('" + t.tag.camera + "' at " + std::to_string(t.tag.width) + "x" +
                                    std::to_string(t.tag.height) + "; the survey's is '" + tagged[0].tag.camera + "' at " +
                                    std::to_string(tagged[0].tag.width) + "x" + std::to_string(tagged[0].tag.height) + ")");
      tagged.push_back(std::move(t));
    } catch (const std::invalid_argument& e) {
      skipped->push_back(e.what());
      std::fprintf(stderr, "uav-stitch: skipped %s\n", e.what());
    }
  }
  if (tagged.empty()) Fail("no geotagged photo could be used");
  GeotaggedFolder out;
  const uav::vision::PhotoGeotag& first = tagged[0].tag;
  if (!camera_given) out.camera = uav::vision::IntrinsicsFromGeotag(first, tagged[0].path);  // else --camera's
  out.camera_name = first.camera;
  // The NED origin: on the ground under the first photo.
  out.home = first.position;
  out.home.altitude_m = ground_altitude_m ? *ground_altitude_m
                        : first.has_altitude ? first.position.altitude_m - *first.height_above_takeoff_m
                                             : 0.0;
  const uav::LocalNedFrame ned(out.home);
  std::vector<Eigen::Vector3d> p_N;
  for (const Tagged& t : tagged) {
    Eigen::Vector3d p = ned.ToNed(t.tag.position);
    if (!ground_altitude_m) p.z() = -*t.tag.height_above_takeoff_m;
    p_N.push_back(p);
  }
  for (size_t i = 0; i < tagged.size(); ++i) {
    const uav::vision::PhotoGeotag& tag = tagged[i].tag;
    double yaw_deg = 0.0;
    if (tag.yaw_deg) {
      yaw_deg = *tag.yaw_deg;
    } else {
      // No heading in the tags: the course over ground between the neighbouring photos (a
      // survey camera's image top looks along the track).
      const Eigen::Vector3d d = p_N[std::min(i + 1, p_N.size() - 1)] - p_N[i > 0 ? i - 1 : 0];
      yaw_deg = std::atan2(d.y(), d.x()) * 180.0 / M_PI;
      ++out.yaw_from_course;
    }
    Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
    T_NC.linear() = uav::vision::RotationNCFromGeotag(yaw_deg, tag.pitch_deg.value_or(-90.0), tag.roll_deg.value_or(0.0));
    T_NC.translation() = p_N[i];
    out.inputs.push_back({tagged[i].path, tag.utime.value_or(static_cast<int64_t>(i) * 1'000'000), T_NC});
  }
  return out;
}

bool AnyGeotagged(const std::vector<std::string>& files) {
  for (const std::string& f : files) {
    try {
      uav::vision::ReadPhotoGeotag(f);
      return true;
    } catch (const std::invalid_argument&) {
    }
  }
  return false;
}

json Residuals(const uav::vision::ResidualStats& s) {
  return {{"matches", s.matches}, {"median_px", s.median_px}, {"p95_px", s.p95_px}};
}

}  // namespace

int main(int argc, char** argv) {
  // Every frame decodes, warps and blends buffers of megabytes. glibc would map and unmap each
  // one (a page fault per 4 kB, a fifth of the process's time); kept on the heap and not given
  // back between frames, they are reused.
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  CLI::App cli{"uav-stitch: stitch a folder of survey images into a map, adjusted jointly and blended without seams"};
  std::string dir, out, poses_path, camera_path, report_path, detector = "gftt";
  cli.add_option("IMAGES_DIR", dir, "a capture folder (IMG_*.jpg, captures.csv, session.json) or any folder of photos")
      ->required();
  uav::OutputFile(cli.add_option("--out", out, "output prefix: writes OUT.tif, OUT.png (+ .pgw, .prj) and OUT.kml"), ".tif")->required();
  cli.add_option("--poses", poses_path, "poses CSV in captures.csv's format (default IMAGES_DIR/captures.csv)");
  cli.add_option("--camera", camera_path, "camera file (resources/cameras/*.camera) overriding the intrinsics");
  std::optional<double> ground_altitude_m;
  cli.add_option("--ground-altitude", ground_altitude_m,
                 "geotagged photos: the ground's altitude [m] in the photos' GPS altitude reference (default: from the "
                 "first photo's XMP RelativeAltitude)");
  uav::OutputFile(cli.add_option("--report", report_path, "write a JSON report here"));
  cli.add_option("--detector", detector,
                 "gftt: good features + Lucas-Kanade (thesis); orb: FAST + ORB + brute force; sift: SIFT + FLANN")
      ->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  const auto start = std::chrono::steady_clock::now();
  const auto since_start = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  try {
    const bool capture_folder = std::filesystem::exists(dir + "/session.json");
    std::string kind = "capture folder", camera_name;
    int yaw_from_course = 0;
    uav::vision::StitcherParams params;
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
    } else if (const std::vector<std::string> files = uav::ImageFilesIn(dir); AnyGeotagged(files)) {
      if (!poses_path.empty()) Fail(dir + ": --poses needs the folder's session.json (home and camera mount)");
      kind = "geotagged photos";
      GeotaggedFolder folder = ReadGeotaggedFolder(files, !camera_path.empty(), ground_altitude_m, &skipped);
      session.home = folder.home;
      session.camera = folder.camera;
      inputs = std::move(folder.inputs);
      camera_name = folder.camera_name;
      yaw_from_course = folder.yaw_from_course;
      // Poses from a consumer drone's tags: GPS-grade position, a gimbal's or the track's heading.
      params.alignment.nav_position_sigma_m = 3.0;
      params.alignment.nav_yaw_sigma_rad = 0.05;
      params.alignment.nav_scale_sigma = 0.01;
      params.alignment.nav_tilt_sigma_rad = 0.03;  // a gimbal holds the camera within a degree or two
    } else {
      if (!poses_path.empty()) Fail(dir + ": --poses needs the folder's session.json (home and camera mount)");
      kind = "photos without poses";
      for (const std::string& f : files) inputs.push_back({f, static_cast<int64_t>(inputs.size()), {}});
      if (inputs.empty()) Fail(dir + ": no images (and no session.json)");
      // Without a camera file, a pinhole without distortion over the first image's size: enough
      // for a map in pixels.
      cv::Mat first;
      for (const Input& in : inputs)  // the first good one
        if (uav::ImageFileProblem(in.path).empty() &&
            !(first = cv::imread(in.path, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION)).empty())
          break;
      if (first.empty()) Fail(dir + ": no readable image");
      session.camera.width = first.cols;
      session.camera.height = first.rows;
      session.camera.fx = session.camera.fy = first.cols;
      session.camera.cx = (first.cols - 1) / 2.0;
      session.camera.cy = (first.rows - 1) / 2.0;
    }
    if (inputs.empty()) Fail(poses_path + ": no captures");
    if (!camera_path.empty()) session.camera = uav::IntrinsicsFromParameters(uav::ParameterSet::LoadFile(camera_path, uav::CameraParameterSchema()));
    params.registration.detector = uav::vision::ParseDetector(detector);
    params.live_map = false;  // only the adjusted map is written
    uav::vision::MapStitcher stitcher(session.camera, params);
    std::vector<double> ms;
    std::map<std::string, int> failures;
    std::vector<std::string> placed_files;
    int registered = 0;
    uav::ProgressBar progress(inputs.size());
    // The next image is read and prepared (decoded, its features found) while this one is added.
    struct Read {
      std::optional<uav::vision::PreparedFrame> frame;
      std::string problem;  // why the frame cannot be used
    };
    auto read = [&](size_t i) {
      Read r;
      std::ifstream file(inputs[i].path, std::ios::binary | std::ios::ate);
      std::vector<uint8_t> bytes(file ? static_cast<size_t>(std::max<std::streamoff>(0, file.tellg())) : 0);
      // One read of the whole file (a character at a time through a stream iterator was a
      // hundredth of the process).
      if (!bytes.empty() && !file.seekg(0).read(reinterpret_cast<char*>(bytes.data()), bytes.size())) bytes.clear();
      if (bytes.empty()) {
        r.problem = "missing or empty";
        return r;
      }
      // Truncated or garbled: named and skipped, never stitched as a grey smear.
      if (r.problem = uav::EncodedImageProblem(bytes.data(), bytes.size()); !r.problem.empty()) return r;
      try {
        r.frame = stitcher.Prepare({cv::Mat(), inputs[i].utime, inputs[i].T_NC, std::move(bytes)});
      } catch (const std::invalid_argument& e) {
        r.problem = e.what();
      }
      return r;
    };
    std::future<Read> next = std::async(std::launch::async, read, 0);
    for (size_t i = 0; i < inputs.size(); ++i) {
      const Input& in = inputs[i];
      Read file = next.get();
      if (i + 1 < inputs.size()) next = std::async(std::launch::async, read, i + 1);
      // A frame that cannot be used is named and left out; the others still are.
      if (!file.frame) {
        skipped.push_back(in.path + ": " + file.problem);
        std::fprintf(stderr, "\nuav-stitch: skipped %s: %s\n", in.path.c_str(), file.problem.c_str());
        continue;
      }
      const uav::vision::StitchStep step = stitcher.Add(std::move(*file.frame));
      if (step.placed) placed_files.push_back(std::filesystem::path(in.path).filename().string());
      registered += step.registered;
      if (!step.failure.empty()) ++failures[step.failure.substr(0, step.failure.find(" ("))];
      ms.push_back(step.seconds * 1e3);
      progress.Update(i + 1);
    }
    progress.Finish(inputs.size());
    if (stitcher.frames() == 0) Fail(dir + ": no frame could be placed");
    const double seconds_placing = since_start();
    std::fprintf(stderr, "uav-stitch: adjusting %d frames jointly...\n", stitcher.frames());
    const uav::vision::AlignmentReport alignment = stitcher.Align();
    const double seconds_aligning = since_start() - seconds_placing;
    std::fprintf(stderr, "uav-stitch: rendering the map without seams...\n");
    const uav::vision::Mosaic map = stitcher.RenderSeamless();
    const double seconds_rendering = since_start() - seconds_placing - seconds_aligning;
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
    const double seconds_writing = since_start() - seconds_placing - seconds_aligning - seconds_rendering;
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
    json report = {{"input", kind},
                   {"camera",
                    {{"name", camera_name},
                     {"width", session.camera.width},
                     {"height", session.camera.height},
                     {"fx", session.camera.fx},
                     {"fy", session.camera.fy}}},
                   {"headings_from_course", yaw_from_course},
                   {"detector", detector},
                   {"frames", inputs.size()},
                   {"placed", stitcher.frames()},
                   {"registered", registered},
                   {"skipped", skipped},
                   {"failures", failures},
                   {"georeferenced", map.georeferenced},
                   {"ms_per_frame_median", sorted.empty() ? 0.0 : sorted[sorted.size() / 2]},
                   {"seconds",
                    {{"reading_and_placing", seconds_placing},
                     {"aligning", seconds_aligning},
                     {"rendering", seconds_rendering},
                     {"writing", seconds_writing}}},
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
                     {"pairs_rejected", alignment.pairs_rejected},
                     {"seconds_matching", alignment.seconds_matching},
                     {"seconds_solving", alignment.seconds_solving}}},
                   {"map_width_px", map.bgr.cols},
                   {"map_height_px", map.bgr.rows},
                   {"gsd_m", map.gsd_m},
                   {"tiles", stitcher.tiles()},
                   {"memory_mb", stitcher.memory_bytes() / 1e6},
                   {"peak_memory_mb", PeakMemoryMb()},
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
