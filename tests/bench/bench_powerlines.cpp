// Power-line speed at 640x480: the image detector (thin filter, Sobel, EDLines or LSD, grouping,
// fits) on a rendered view of the village's power line and on the real photos resized to it
// (target: 20 ms), and detection plus ranging in 3-D on a stereo pair (rectification of both
// images, the right image's thin filter, the oriented window search; target: the stereo pair's
// rate, 15 pairs/s (67 ms) on this 2-core machine).
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/vision/power_line_detector.hpp"
#include "uav/vision/power_line_stereo.hpp"
#include "uav/world/renderer.hpp"
#include "uav/world/scene.hpp"

namespace {

cv::Mat VillageView() {
  const auto scene = uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/power_lines_village.scene.json");
  const uav::world::CameraSetup cam = scene.stereo_camera()->left;
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() = uav::RotationNBFromEuler({0.0, 8 * M_PI / 180, 10 * M_PI / 180}) * uav::RotationBCForward();
  T_NC.translation() = Eigen::Vector3d(0, 15, -6);
  return uav::world::Renderer(scene, cam).Render(T_NC, 1'000'000).image;
}

// Arg 0: EDLines pieces (the detector's default), 1: LSD's (the vehicle's, pwl_segments 0).
void BM_PowerLines(benchmark::State& state) {
  const cv::Mat image = VillageView();
  uav::vision::PowerLineParams params;
  params.segments = state.range(0) == 0 ? uav::vision::PowerLineParams::Segments::kEdLines
                                        : uav::vision::PowerLineParams::Segments::kLsd;
  const uav::vision::PowerLineDetector detector(params);
  std::size_t wires = 0;
  for (auto _ : state) wires = detector.Detect(image).size();
  state.counters["wires"] = static_cast<double>(wires);
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PowerLines)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

// The real photos of ../shared/data (50 over mountains, 40 over towns, 540 x 360) resized to the
// camera's 640 x 480, one photo an iteration in turn: the time is the mean over the photos.
// Arg as BM_PowerLines.
void BM_PowerLinesRealPhotos(benchmark::State& state) {
  static const std::vector<cv::Mat> photos = [] {
    std::vector<cv::Mat> out;
    for (const char* set : {"/powerlines_real/images", "/powerlines_real_urban/images"})
      for (const std::string& file : uav::ImageFilesIn(std::string(UAV_SHARED_DATA) + set)) {
        cv::Mat photo = cv::imread(file), resized;
        if (photo.empty()) continue;
        cv::resize(photo, resized, cv::Size(640, 480), 0, 0, cv::INTER_AREA);
        out.push_back(resized);
      }
    return out;
  }();
  if (photos.empty()) {
    state.SkipWithError("no real photos under " UAV_SHARED_DATA);
    return;
  }
  uav::vision::PowerLineParams params;
  params.segments = state.range(0) == 0 ? uav::vision::PowerLineParams::Segments::kEdLines
                                        : uav::vision::PowerLineParams::Segments::kLsd;
  const uav::vision::PowerLineDetector detector(params);
  std::size_t next = 0, wires = 0;
  for (auto _ : state) wires += detector.Detect(photos[next++ % photos.size()]).size();
  state.counters["photos"] = static_cast<double>(photos.size());
  state.counters["wires_per_photo"] = static_cast<double>(wires) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PowerLinesRealPhotos)->Arg(0)->Arg(1)->Iterations(270)->Unit(benchmark::kMillisecond);

// The scene's rig (rolled 45 degrees), facing the line across it from 15 m.
void BM_PowerLinesStereo(benchmark::State& state) {
  const auto scene = uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/power_lines_village.scene.json");
  const uav::world::StereoSetup& rig = *scene.stereo_camera();
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.linear() = uav::RotationNBFromEuler({0.0, 8 * M_PI / 180, 0.0});
  T_NB.translation() = Eigen::Vector3d(5, 0, -7);
  const uav::world::StereoFrame pair = uav::world::StereoRenderer(scene, rig).Render(T_NB, 1'000'000);
  const uav::vision::PowerLineStereo stereo({rig.left.intrinsics, rig.right.intrinsics, rig.T_LR()});
  std::size_t ranged = 0;
  for (auto _ : state) {
    ranged = 0;
    for (const auto& w : stereo.Process(pair.left.image, pair.right.image)) ranged += w.ranged();
  }
  state.counters["ranged_wires"] = static_cast<double>(ranged);
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PowerLinesStereo)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
