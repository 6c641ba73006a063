// Stitching speed (issue 7 item 8): registration + placement + warp per 640x480 frame for each
// detector of thesis Table 6.1, and a 1000-frame survey stitched end to end with its peak memory.
#include <sys/resource.h>

#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/map_stitcher.hpp"
#include "uav/world/renderer.hpp"

namespace {

using uav::vision::Detector;

struct Shot {
  cv::Mat image;
  Eigen::Isometry3d T_NC;
};

const uav::world::Scene& Village() {
  static const uav::world::Scene scene =
      uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
  return scene;
}

// A zig-zag at 40 m, 1 m per frame (5 m/s at 5 Hz), lines 30 m apart and `line` frames long.
std::vector<Shot> Render(int frames, int line) {
  const uav::world::CameraSetup& cam = *Village().downward_camera();
  const uav::world::Renderer renderer(Village(), cam);
  std::vector<Shot> shots;
  Eigen::Vector2d p(-0.5 * line, -150);
  double direction = 1;
  for (int i = 0; i < frames; ++i) {
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.translation() = Eigen::Vector3d(p.x(), p.y(), -40);
    shots.push_back({renderer.Render(T_NB * cam.T_BC, 1000000 + i * 200000LL).image, T_NB * cam.T_BC});
    if ((i + 1) % (line + 10) < line) p.x() += direction;
    else p.y() += 3;
    if ((i + 1) % (line + 10) == 0) direction = -direction;
  }
  return shots;
}

void BM_StitchFrame(benchmark::State& state, Detector detector) {
  static const std::vector<Shot> shots = Render(120, 50);
  uav::vision::StitcherParams params;
  params.registration.detector = detector;
  auto stitcher = std::make_unique<uav::vision::MapStitcher>(Village().downward_camera()->intrinsics, params);
  size_t i = 0;
  int registered = 0, frames = 0;
  for (auto _ : state) {
    if (i == shots.size()) {
      state.PauseTiming();
      stitcher = std::make_unique<uav::vision::MapStitcher>(Village().downward_camera()->intrinsics, params);
      i = 0;
      state.ResumeTiming();
    }
    const auto step = stitcher->Add({shots[i].image, 0, shots[i].T_NC});
    registered += step.registered;
    ++frames;
    ++i;
  }
  state.counters["registered_pct"] = 100.0 * registered / std::max(frames, 1);
  state.SetLabel(std::string(uav::vision::DetectorName(detector)) + ", 640x480 at 40 m");
}
BENCHMARK_CAPTURE(BM_StitchFrame, gftt, Detector::kGfttKlt)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_StitchFrame, orb, Detector::kFastOrb)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(BM_StitchFrame, sift, Detector::kSiftFlann)->Unit(benchmark::kMillisecond)->UseRealTime();

// 1000 frames: 10 lines of 90 m. The frames are rendered once, outside the timing.
void BM_StitchMission(benchmark::State& state) {
  static const std::vector<Shot> shots = Render(1000, 90);
  for (auto _ : state) {
    uav::vision::MapStitcher stitcher(Village().downward_camera()->intrinsics);
    for (const Shot& s : shots) stitcher.Add({s.image, 0, s.T_NC});
    const auto map = stitcher.Render();
    benchmark::DoNotOptimize(map.bgr.data);
    state.counters["tiles_mb"] = stitcher.memory_bytes() / 1e6;
  }
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["peak_rss_mb"] = usage.ru_maxrss / 1024.0;  // includes the 1000 rendered frames (~920 MB)
  state.SetLabel("1000 frames 640x480, gftt");
}
BENCHMARK(BM_StitchMission)->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);

}  // namespace

BENCHMARK_MAIN();
