// Tracking speed at 640x480 (thesis 3.7): one frame of CamShift including the BGR to HSV
// conversion and back projection, the correlation filter including the grey conversion, and
// OpenCV's KCF and CSRT on the same frames. Targets on this 2-core machine: 500 frames/s for
// CamShift; the correlation filter at 3x CSRT's frame rate or more.
#include <vector>

#include <benchmark/benchmark.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/target_tracker.hpp"
#include "uav/world/renderer.hpp"

namespace {

struct Clip {
  std::vector<cv::Mat> frames;
  cv::Rect first_box;
};

// A red ball rolling across grass, 20 frames at 10 Hz, seen from 2 m up.
Clip RenderClip() {
  uav::world::Scene scene(5);
  scene.SetGround(uav::world::GroundSpec{});
  const int ball = scene.AddSphere("ball", Eigen::Vector3d(10, -2, -0.35), 0.35, "red");
  uav::world::ObjectPath path;
  path.waypoints_NE = {{10, -2}, {10, 2}};
  path.speed_mps = 1.0;
  path.loop = false;
  scene.SetPath(ball, path);
  uav::world::CameraSetup cam;
  cam.name = "gimbal";
  cam.intrinsics.width = 640;
  cam.intrinsics.height = 480;
  cam.intrinsics.fx = cam.intrinsics.fy = 500;
  cam.intrinsics.cx = 319.5;
  cam.intrinsics.cy = 239.5;
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() = uav::RotationNBFromEuler({0.0, -8 * M_PI / 180, 0.0}) * uav::RotationBCForward();
  T_NC.translation() = Eigen::Vector3d(0, 0, -2);
  const uav::world::Renderer renderer(scene, cam);
  Clip clip;
  for (int k = 0; k < 20; ++k) {
    const uav::world::Frame f = renderer.Render(T_NC, k * 100'000);
    if (k == 0) clip.first_box = uav::world::ObjectBox(f, ball);
    clip.frames.push_back(f.image);
  }
  return clip;
}

const Clip& TheClip() {
  static const Clip clip = RenderClip();
  return clip;
}

void BM_Track(benchmark::State& state) {
  const Clip& clip = TheClip();
  uav::vision::TrackerParams p;
  p.kind = static_cast<uav::vision::TrackerKind>(state.range(0));
  uav::vision::TargetTracker tracker(p);
  tracker.Start(clip.frames[0], 0.0, clip.first_box);
  std::size_t k = 1;
  int step = 1;
  double t_s = 0.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(tracker.Update(clip.frames[k], t_s += 0.1));
    // Back and forth through the clip, so the target keeps moving slowly.
    if (k + step >= clip.frames.size() || k + step == 0) step = -step;
    k += step;
  }
  state.SetLabel(uav::vision::Name(p.kind));
  state.counters["frames_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Track)
    ->Arg(static_cast<int>(uav::vision::TrackerKind::kCamShift))
    ->Arg(static_cast<int>(uav::vision::TrackerKind::kCorrelation))
    ->Arg(static_cast<int>(uav::vision::TrackerKind::kKcf))
    ->Arg(static_cast<int>(uav::vision::TrackerKind::kCsrt))
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
