// Stereo obstacle chain speed (thesis 3.5) on a rendered 640x480 forest pair (a person and a
// pole within range, trees beyond): rectification, disparity, reprojection, range gate, voxel
// grid, ground plane, clustering and cylinders, each stage's mean time as a counter.
// Target: 25 pairs/s (40 ms) for the whole chain on this 2-core machine.
#include <chrono>

#include <benchmark/benchmark.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/stereo_obstacles.hpp"
#include "uav/world/renderer.hpp"
#include "uav/world/scene.hpp"

namespace {

void BM_StereoObstacles(benchmark::State& state) {
  const auto scene = uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/forest.scene.json");
  const uav::world::StereoSetup& rig = *scene.stereo_camera();
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(3, 0, -1.5);
  const uav::world::StereoFrame pair = uav::world::StereoRenderer(scene, rig).Render(T_NB, 1'000'000);
  const uav::vision::StereoRectifier rectifier({rig.left.intrinsics, rig.right.intrinsics, rig.T_LR()});
  uav::vision::ObstacleParams params;
  params.disparity.matcher = static_cast<uav::vision::MatcherKind>(state.range(0));
  params.disparity.wls_filter = state.range(1) != 0;
  const uav::vision::StereoObstacleDetector detector(rectifier.geometry(), params);
  const Eigen::Isometry3d T_NL = T_NB * rig.left.T_BC;
  uav::vision::StereoStageTimes sum;
  double rectify_ms = 0;
  std::size_t obstacles = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat l, r;
    rectifier.Rectify(pair.left.image, pair.right.image, &l, &r);
    rectify_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const uav::vision::StereoObstacles found = detector.Process(l, r, T_NL);
    obstacles = found.obstacles.size();
    sum.disparity_ms += found.times.disparity_ms;
    sum.reproject_ms += found.times.reproject_ms;
    sum.voxel_ms += found.times.voxel_ms;
    sum.ground_ms += found.times.ground_ms;
    sum.cluster_ms += found.times.cluster_ms;
    sum.cylinders_ms += found.times.cylinders_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["obstacles"] = static_cast<double>(obstacles);
  state.counters["rectify_ms"] = rectify_ms / n;
  state.counters["disparity_ms"] = sum.disparity_ms / n;
  state.counters["reproject_ms"] = sum.reproject_ms / n;
  state.counters["voxel_ms"] = sum.voxel_ms / n;
  state.counters["ground_ms"] = sum.ground_ms / n;
  state.counters["cluster_ms"] = sum.cluster_ms / n;
  state.counters["cylinders_ms"] = sum.cylinders_ms / n;
  state.counters["pairs_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
}
// {matcher (0 BM, 1 SGBM), WLS}
BENCHMARK(BM_StereoObstacles)->Args({1, 0})->Args({0, 0})->Args({1, 1})->ArgNames({"sgbm", "wls"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
