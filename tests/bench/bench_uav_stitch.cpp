// bench_uav_stitch [--frames 100,300,1000] [--opencv-frames 30] [--work DIR] [--folder PHOTOS]
// The whole uav-stitch process (read, register, adjust jointly, render without seams, write the
// GeoTIFF) on capture folders of 960x540 frames as the onboard camera thread writes them: wall
// time per frame and the process's peak memory for each folder size, then OpenCV's
// cv::Stitcher in SCANS mode and uav-stitch (the median of five runs) side by side on the same
// first frames. With --folder, only the side-by-side run, on the first photos of any folder
// (real frames). Prints a JSON
// report on stdout; progress on stderr.
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/stitching.hpp>

#include "uav/runtime/camera_worker.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/sim/sim_cameras.hpp"
#include "uav/world/scene.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

struct Run {
  int exit_code = -1;
  double seconds = 0.0;
};

// Runs a program and measures its wall time. (Its peak memory comes from its own report: a
// spawned child's rusage counts the parent's memory from before the exec.)
Run Measure(const std::vector<std::string>& args, const std::string& log) {
  std::vector<char*> argv;
  for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  const auto start = std::chrono::steady_clock::now();
  pid_t pid = 0;
  Run run;
  if (posix_spawn(&pid, argv[0], &actions, nullptr, argv.data(), environ) != 0) {
    posix_spawn_file_actions_destroy(&actions);
    throw std::runtime_error("cannot run " + args[0]);
  }
  posix_spawn_file_actions_destroy(&actions);
  int status = 0;
  waitpid(pid, &status, 0);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return run;
}

// A zig-zag survey at 40 m over the village with a 960x540 downward camera: 1 m between frames
// (5 m/s at 5 Hz), lines `line_frames` m long and 24 m apart (about 60 % side overlap), written
// by the onboard camera thread into `dir` (JPEG Q95, captures.csv, session.json).
void FlySurvey(const uav::world::Scene& scene, int frames, int line_frames, const std::string& dir) {
  uav::world::CameraSetup setup = *scene.downward_camera();
  const double scale = 960.0 / setup.intrinsics.width;
  uav::CameraIntrinsics& k = setup.intrinsics;
  k.fx *= scale;
  k.fy *= scale;
  k.width = 960;
  k.height = 540;
  k.cx = (k.width - 1) / 2.0;
  k.cy = (k.height - 1) / 2.0;
  uav::runtime::Blackboard board;
  board.Update([](uav::runtime::BlackboardData& d) { d.capture_interval_s = 0.2; });
  uav::runtime::CameraWorker::Options options;
  options.capture_dir = dir;
  options.home.latitude_deg = 52.2383;
  options.home.longitude_deg = 4.5234;
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  uav::sim::SimCamera camera(scene, setup, [&](int64_t) { return T_NB; });
  uav::runtime::CameraWorker worker(camera, board, options);
  const int turn_frames = 8;  // 24 m across at 3 m per frame
  Eigen::Vector2d p(-0.5 * line_frames, -120);
  double direction = 1;
  uav::ProgressBar progress(frames);
  for (int i = 0; i < frames; ++i) {
    // Nose along the line, so the image's long side spans the lines.
    const int in_cycle = i % (line_frames + turn_frames);
    T_NB.linear() = uav::RotationNBFromEuler({0, 0, direction > 0 ? 0.0 : M_PI});
    T_NB.translation() = Eigen::Vector3d(p.x(), p.y(), -40);
    board.Update([&](uav::runtime::BlackboardData& d) {
      d.estimate.p_N = T_NB.translation();
      d.estimate.euler = uav::EulerFromRotationNB(T_NB.linear());
    });
    worker.Tick(1'000'000 + i * 200'000LL);
    if (in_cycle < line_frames - 1) p.x() += direction;
    else if (in_cycle < line_frames + turn_frames - 1) p.y() += 3;
    if (in_cycle == line_frames + turn_frames - 1) direction = -direction;
    progress.Update(i + 1);
  }
  progress.Finish(frames);
}

// The first `frames` captures of `full` as a folder of their own (images linked, not copied).
std::string Subset(const std::string& full, int frames, const std::string& dir) {
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(full + "/session.json", dir + "/session.json");
  std::ifstream in(full + "/captures.csv");
  std::ofstream out(dir + "/captures.csv");
  std::string line;
  std::getline(in, line);
  out << line << "\n";
  for (int i = 0; i < frames && std::getline(in, line); ++i) {
    out << line << "\n";
    const std::string file = line.substr(line.find(',', line.find(',') + 1) + 1);
    const std::string name = file.substr(0, file.find(','));
    fs::create_symlink(fs::absolute(full + "/" + name), dir + "/" + name);
  }
  return dir;
}

std::vector<std::string> FirstImages(const std::string& dir, int frames) {
  std::ifstream in(dir + "/captures.csv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> files;
  while (static_cast<int>(files.size()) < frames && std::getline(in, line)) {
    const std::string file = line.substr(line.find(',', line.find(',') + 1) + 1);
    files.push_back(dir + "/" + file.substr(0, file.find(',')));
  }
  return files;
}

json Report(const std::string& path) {
  std::ifstream in(path);
  return in ? json::parse(in, nullptr, false) : json();
}

// uav-stitch (the median of five runs) and cv::Stitcher in SCANS mode on the same images: `dir`
// is what uav-stitch is given, `images` what OpenCV is given (already decoded, as its API takes
// them; uav-stitch's time includes reading the files).
json SideBySide(const std::string& dir, const std::vector<std::string>& images) {
  std::fprintf(stderr, "bench_uav_stitch: uav-stitch and cv::Stitcher (SCANS) on the same %zu frames...\n", images.size());
  // A second on a machine shared with others varies by a tenth: the median of five runs.
  std::vector<double> ours_s;
  int ours_exit = 0;
  for (int r = 0; r < 5; ++r) {
    const Run run = Measure({UAV_STITCH_BIN, dir, "--out", dir + "/map", "--report", dir + "/report.json"}, dir + "/log.txt");
    ours_s.push_back(run.seconds);
    ours_exit = std::max(ours_exit, run.exit_code);
  }
  std::sort(ours_s.begin(), ours_s.end());
  const double ours_median_s = ours_s[ours_s.size() / 2];
  const json ours = Report(dir + "/report.json");
  std::vector<cv::Mat> decoded;
  for (const std::string& f : images) decoded.push_back(cv::imread(f, cv::IMREAD_COLOR));
  const auto start = std::chrono::steady_clock::now();
  cv::Ptr<cv::Stitcher> stitcher = cv::Stitcher::create(cv::Stitcher::SCANS);
  cv::Mat pano;
  const cv::Stitcher::Status status = stitcher->stitch(decoded, pano);
  const double opencv_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  cv::imwrite(dir + "/opencv_scans.jpg", pano.empty() ? cv::Mat(1, 1, CV_8UC3) : pano);
  return {{"frames", images.size()},
          {"uav_stitch_seconds", ours_median_s},
          {"uav_stitch_seconds_all_runs", ours_s},
          {"uav_stitch_exit_code", ours_exit},
          {"uav_stitch_placed", ours.value("placed", 0)},
          {"uav_stitch_seconds_by_stage", ours.value("seconds", json::object())},
          {"opencv_scans_seconds", opencv_s},
          {"opencv_scans_status", static_cast<int>(status)},
          {"opencv_scans_size", {pano.cols, pano.rows}},
          {"speedup", opencv_s / ours_median_s}};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"bench_uav_stitch: the whole uav-stitch process on 960x540 survey folders, and cv::Stitcher SCANS beside it"};
  std::vector<int> sizes = {100, 300, 1000};
  int opencv_frames = 30;
  std::string work = (fs::temp_directory_path() / "bench_uav_stitch").string();
  cli.add_option("--frames", sizes, "folder sizes to stitch")->delimiter(',')->capture_default_str();
  cli.add_option("--opencv-frames", opencv_frames, "frames for the side-by-side run with cv::Stitcher (0: skip)")
      ->capture_default_str();
  cli.add_option("--work", work, "scratch folder (rendered surveys, maps)")->capture_default_str();
  std::string folder;
  cli.add_option("--folder", folder,
                 "instead of the rendered surveys: the side-by-side run on the first --opencv-frames photos of this "
                 "folder (any folder uav-stitch takes, in name order)")
      ->check(CLI::ExistingDirectory);
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    if (!folder.empty()) {
      std::vector<std::string> images = uav::ImageFilesIn(folder);
      if (opencv_frames <= 0) throw std::invalid_argument("--opencv-frames must be positive with --folder");
      if (images.size() > static_cast<size_t>(opencv_frames)) images.resize(opencv_frames);
      if (images.size() < 2) throw std::invalid_argument(folder + ": fewer than 2 photos");
      // The photos linked into a folder of their own (uav-stitch takes a whole folder).
      const std::string dir = work + "/folder";
      fs::remove_all(dir);
      fs::create_directories(dir);
      for (const std::string& f : images) fs::create_symlink(fs::absolute(f), dir + "/" + fs::path(f).filename().string());
      const json report = {{"folder", fs::absolute(folder).string()},
                           {"hardware_threads", std::thread::hardware_concurrency()},
                           {"side_by_side", SideBySide(dir, images)}};
      std::printf("%s\n", report.dump(2).c_str());
      return 0;
    }
    const uav::world::Scene scene =
        uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
    const int largest = std::max(*std::max_element(sizes.begin(), sizes.end()), opencv_frames);
    const std::string full = work + "/survey";
    fs::remove_all(work);
    std::fprintf(stderr, "bench_uav_stitch: flying %d frames at 960x540...\n", largest);
    FlySurvey(scene, largest, 80, full);
    json report = {{"camera", "960x540 downward, 40 m, 1 m between frames, lines 80 m long and 24 m apart"},
                   {"hardware_threads", std::thread::hardware_concurrency()},
                   {"runs", json::array()}};
    for (int n : sizes) {
      const std::string dir = Subset(full, n, work + "/survey_" + std::to_string(n));
      std::fprintf(stderr, "bench_uav_stitch: uav-stitch on %d frames...\n", n);
      const Run run = Measure({UAV_STITCH_BIN, dir, "--out", dir + "/map", "--report", dir + "/report.json"},
                              dir + "/log.txt");
      const json r = Report(dir + "/report.json");
      report["runs"].push_back({{"frames", n},
                                {"exit_code", run.exit_code},
                                {"seconds", run.seconds},
                                {"ms_per_frame", 1e3 * run.seconds / n},
                                {"peak_memory_mb", r.value("peak_memory_mb", 0.0)},
                                {"seconds_by_stage", r.value("seconds", json::object())},
                                {"placed", r.value("placed", 0)},
                                {"align_seconds_matching", r.contains("alignment") ? r["alignment"].value("seconds_matching", 0.0) : 0.0},
                                {"align_seconds_solving", r.contains("alignment") ? r["alignment"].value("seconds_solving", 0.0) : 0.0},
                                {"cross_p95_before_px", r.contains("alignment") ? r["alignment"]["cross_before"].value("p95_px", 0.0) : 0.0},
                                {"cross_p95_after_px", r.contains("alignment") ? r["alignment"]["cross_after"].value("p95_px", 0.0) : 0.0},
                                {"pairs_rejected", r.contains("alignment") ? r["alignment"].value("pairs_rejected", 0) : 0}});
    }
    if (opencv_frames > 0) {
      const std::string dir = Subset(full, opencv_frames, work + "/survey_opencv");
      report["side_by_side"] = SideBySide(dir, FirstImages(full, opencv_frames));
    }
    std::printf("%s\n", report.dump(2).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_uav_stitch: %s\n", e.what());
    return 2;
  }
}
