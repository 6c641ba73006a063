// Render speed (issue 4 item 7): one 640x480 frame of the named scenes, flying so the camera
// moves between frames (tile binning and clouds are redone every frame). A stereo pair counts as
// two frames.
#include <benchmark/benchmark.h>

#include "uav/vision/stereo_range.hpp"
#include "uav/world/renderer.hpp"

namespace {

using uav::world::Scene;

Scene LoadScene(const char* name) {
  return Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/" + name + ".scene.json");
}

// Survey camera over the village at 40 m, flying north at 3 m/s and capturing at 5 Hz.
void BM_DownwardVillage(benchmark::State& state) {
  const Scene scene = LoadScene("survey_village");
  const uav::world::Renderer renderer(scene, *scene.downward_camera());
  int64_t frame = 0;
  for (auto _ : state) {
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.translation() = Eigen::Vector3d(-60 + 0.6 * (frame % 200), 25, -state.range(0));
    const auto f = renderer.Render(T_NB * scene.downward_camera()->T_BC, 200000 * frame);
    benchmark::DoNotOptimize(f.image.data);
    ++frame;
  }
  state.SetLabel("640x480 at " + std::to_string(state.range(0)) + " m");
}
BENCHMARK(BM_DownwardVillage)->Arg(10)->Arg(40)->Unit(benchmark::kMillisecond)->UseRealTime();

// Stereo pair with the laser in the room, and in the forest, walking forward.
void BM_StereoPair(benchmark::State& state, const char* scene_name) {
  const Scene scene = LoadScene(scene_name);
  const uav::world::StereoRenderer renderer(scene, *scene.stereo_camera());
  int64_t frame = 0;
  for (auto _ : state) {
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.translation() = Eigen::Vector3d(-3 + 0.05 * (frame % 60), 0, -1.5);
    const auto f = renderer.Render(T_NB, 66667 * frame);
    benchmark::DoNotOptimize(f.left.image.data);
    ++frame;
  }
  state.SetLabel("2 frames 640x480");
}
BENCHMARK_CAPTURE(BM_StereoPair, indoor_room, "indoor_room")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_StereoPair, forest, "forest")->Unit(benchmark::kMillisecond)->UseRealTime();

// The STEREO worker's consumer: rectification, matching at half resolution and the corridor
// range for one rendered forest pair.
void BM_StereoRange(benchmark::State& state) {
  const Scene scene = LoadScene("forest");
  const uav::world::StereoSetup& setup = *scene.stereo_camera();
  const uav::world::StereoRenderer renderer(scene, setup);
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(4, 3, -1.5);
  const auto pair = renderer.Render(T_NB, 1000000);
  const uav::vision::StereoRange range({setup.left.intrinsics, setup.right.intrinsics, setup.T_LR()}, uav::vision::StereoRangeParams());
  for (auto _ : state) {
    const auto r = range.Process(pair.left.image, pair.right.image);
    benchmark::DoNotOptimize(r.range_m);
  }
  state.SetLabel("640x480 pair, matched at 320x240");
}
BENCHMARK(BM_StereoRange)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
