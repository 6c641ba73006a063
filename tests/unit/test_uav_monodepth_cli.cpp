// uav-monodepth on a capture folder written by the onboard camera thread (CameraWorker): 8 s
// north at 3 m/s and 20 m over the village at 10 Hz, JPEG images and captures.csv as the vehicle
// writes them, one row with a non-finite navigation solution. Checks the CSV against the
// renderer's exact depth in each cell and the refused frame's reason.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "uav/runtime/camera_worker.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/sim/sim_cameras.hpp"
#include "uav/world/renderer.hpp"
#include "uav/world/scene.hpp"

namespace uav::runtime {
namespace {

std::string Slurp(const std::string& path) { return ReadTextFile(path, "output"); }

// One CSV line split at commas outside quotes.
std::vector<std::string> Fields(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) out.emplace_back();
    else out.back() += c;
  }
  return out;
}

TEST(UavMonodepth, GridPerFrameFromACaptureFolderAgainstTheExactDepth) {
  const world::Scene scene =
      world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
  const std::string dir = (std::filesystem::temp_directory_path() / "uav_test_monodepth_cli").string();
  std::filesystem::remove_all(dir);
  Blackboard board;
  board.Update([](BlackboardData& d) { d.capture_interval_s = 0.1; });
  CameraWorker::Options options;
  options.capture_dir = dir + "/captures";
  options.home = GeodeticPoint{52.2383, 4.5234, 40};
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  world::CameraSetup setup = *scene.downward_camera();
  setup.rate_hz = 10;
  sim::SimCamera camera(scene, setup, [&](int64_t) { return T_NB; });
  world::Renderer truth(scene, setup);
  CameraWorker worker(camera, board, options);
  const int frames = 80, bad_frame = 50;
  std::vector<cv::Mat> exact_depth;
  for (int i = 0; i < frames; ++i) {
    const int64_t utime = 1'000'000 + i * 100'000;
    T_NB.translation() = Eigen::Vector3d(-20 + 0.3 * i, 12, -20);
    board.Update([&](BlackboardData& d) {
      d.estimate.utime = utime;
      d.estimate.p_N = T_NB.translation();
      if (i == bad_frame) d.estimate.p_N.x() = std::nan("");
      d.estimate.euler = EulerAngles();
    });
    worker.Tick(utime);
    exact_depth.push_back(truth.Render(T_NB * setup.T_BC, utime).depth);
  }
  ASSERT_EQ(worker.captures(), frames);
  const std::string command = std::string(UAV_MONODEPTH_BIN) + " " + dir + "/captures --out " + dir + "/grid.csv > " + dir +
                              "/stdout.txt 2> " + dir + "/stderr.txt";
  ASSERT_EQ(std::system(command.c_str()), 0) << Slurp(dir + "/stderr.txt");
  const std::string summary = Slurp(dir + "/stdout.txt");
  EXPECT_NE(summary.find("\"frames\": 80"), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"healthy_frames\": 79"), std::string::npos) << summary;

  std::istringstream csv(Slurp(dir + "/grid.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line, "frame,utime,file,row,col,state,depth_m,sigma_m,features,confidence,reason");
  std::vector<double> errors;
  int rows = 0, known_after_first_second = 0, cells_after_first_second = 0;
  while (std::getline(csv, line)) {
    ++rows;
    const auto f = Fields(line);
    ASSERT_EQ(f.size(), 11u) << line;
    const int frame = std::stoi(f[0]), r = std::stoi(f[3]), c = std::stoi(f[4]);
    if (frame == bad_frame) {
      EXPECT_EQ(f[5], "unknown") << line;
      EXPECT_NE(f[10].find("no navigation sample"), std::string::npos) << line;
      EXPECT_NE(f[10].find("est_n"), std::string::npos) << line;  // the column that is not finite
      continue;
    }
    if (frame < 10) continue;
    ++cells_after_first_second;
    if (f[5] == "unknown") continue;
    ++known_after_first_second;
    // Against the median exact depth over the cell: the cell is the mean of its features,
    // which sample the cell's surfaces.
    const cv::Mat& depth = exact_depth[frame];
    const int w = depth.cols / 4, h = depth.rows / 3;
    const cv::Mat cell = depth(cv::Rect(c * w, r * h, w, h));
    std::vector<float> z(cell.begin<float>(), cell.end<float>());
    std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
    errors.push_back(std::abs(std::stod(f[6]) - z[z.size() / 2]) / z[z.size() / 2]);
  }
  EXPECT_EQ(rows, 12 * frames);
  ASSERT_FALSE(errors.empty());
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], p95 = errors[errors.size() * 95 / 100];
  std::printf("uav-monodepth on %d captures: %d of %d cells known after the first second, error against the cell's median exact depth: median %.2f %%, p95 %.2f %%\n",
              frames, known_after_first_second, cells_after_first_second, 100 * median, 100 * p95);
  EXPECT_GT(known_after_first_second, 0.9 * cells_after_first_second);
  EXPECT_LT(median, 0.03);
  EXPECT_LT(p95, 0.15);  // a cell half on a roof: its features' mean against the area's median

  // One truncated capture: named and skipped (a dropped frame), the folder is still measured.
  const std::string victim = dir + "/captures/IMG_000020.jpg";
  const std::string whole = Slurp(victim);
  std::ofstream(victim, std::ios::binary | std::ios::trunc) << whole.substr(0, whole.size() / 3);
  ASSERT_EQ(std::system(command.c_str()), 0) << Slurp(dir + "/stderr.txt");
  const std::string again = Slurp(dir + "/stdout.txt");
  EXPECT_NE(again.find("\"frames\": 79"), std::string::npos) << again;
  EXPECT_NE(again.find("IMG_000020.jpg: corrupt JPEG (Premature end of JPEG file)"), std::string::npos) << again;
  EXPECT_NE(Slurp(dir + "/stderr.txt").find("skipped " + victim), std::string::npos);
  if (!HasFailure()) std::filesystem::remove_all(dir);
}

TEST(UavMonodepth, RefusesAFolderWithoutASessionByName) {
  const std::string dir = (std::filesystem::temp_directory_path() / "uav_test_monodepth_empty").string();
  std::filesystem::create_directories(dir);
  const std::string command = std::string(UAV_MONODEPTH_BIN) + " " + dir + " --out " + dir + "/grid.csv > " + dir + "/out.txt 2>&1";
  EXPECT_EQ(WEXITSTATUS(std::system(command.c_str())), 2);
  EXPECT_NE(Slurp(dir + "/out.txt").find("session.json"), std::string::npos) << Slurp(dir + "/out.txt");
  EXPECT_FALSE(std::filesystem::exists(dir + "/grid.csv"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uav::runtime
