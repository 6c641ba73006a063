// Depth from motion speed at 640x480 (thesis 3.4): one frame of MonoDepthEstimator::Update
// (grey conversion, Lucas-Kanade forward and back, the measurement and EKF of every feature,
// topping up features, the grid) on the survey village seen from 20 m at 10 Hz and 3 m/s.
// Target: 30 frames/s or more on this 2-core machine.
#include <vector>

#include <benchmark/benchmark.h>

#include "uav/vision/mono_depth.hpp"
#include "uav/world/renderer.hpp"

namespace {

struct Clip {
  uav::world::CameraSetup camera;
  std::vector<cv::Mat> frames;
  std::vector<Eigen::Isometry3d> poses;
};

const Clip& VillageClip() {
  static const Clip clip = [] {
    const uav::world::Scene scene =
        uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
    Clip c;
    c.camera = *scene.downward_camera();
    const uav::world::Renderer renderer(scene, c.camera);
    for (int i = 0; i < 40; ++i) {
      Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
      T_NB.translation() = Eigen::Vector3d(-30 + 0.3 * i, 40, -20);
      c.poses.push_back(T_NB * c.camera.T_BC);
      c.frames.push_back(renderer.Render(c.poses.back(), 1'000'000 + i * 100'000).image);
    }
    return c;
  }();
  return clip;
}

void BM_MonoDepthFrame(benchmark::State& state) {
  const Clip& clip = VillageClip();
  uav::vision::MonoDepthEstimator estimator(clip.camera.intrinsics, uav::vision::MonoDepthParams{});
  std::size_t i = 0;
  int64_t utime = 1'000'000;
  for (auto _ : state) {
    // Forward through the clip and back again, so the motion never stops.
    const std::size_t k = (i / clip.frames.size()) % 2 == 0 ? i % clip.frames.size() : clip.frames.size() - 1 - i % clip.frames.size();
    const auto grid = estimator.Update(clip.frames[k], utime, clip.poses[k]);
    benchmark::DoNotOptimize(grid.cells.data());
    utime += 100'000;
    ++i;
  }
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_MonoDepthFrame)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
