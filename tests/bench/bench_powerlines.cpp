// Power-line detector speed at 640x480, on a rendered view of the village's power line (thin
// filter, Sobel, LSD, grouping, fits). Target: 20 frames/s (50 ms) on this 2-core machine.
#include <benchmark/benchmark.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/power_line_detector.hpp"
#include "uav/world/renderer.hpp"
#include "uav/world/scene.hpp"

namespace {

cv::Mat VillageView() {
  const auto scene = uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/power_lines_village.scene.json");
  const uav::world::CameraSetup cam = scene.stereo_camera()->left;
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() = uav::RotationNBFromEuler({0.0, 8 * M_PI / 180, 10 * M_PI / 180}) * uav::world::RotationBCForward();
  T_NC.translation() = Eigen::Vector3d(0, 15, -6);
  return uav::world::Renderer(scene, cam).Render(T_NC, 1'000'000).image;
}

void BM_PowerLines(benchmark::State& state) {
  const cv::Mat image = VillageView();
  const uav::vision::PowerLineDetector detector;
  std::size_t wires = 0;
  for (auto _ : state) wires = detector.Detect(image).size();
  state.counters["wires"] = static_cast<double>(wires);
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_PowerLines)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
