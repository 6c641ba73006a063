// Visual odometry speed at 640x480 (thesis ch. 5): one rectified pair through StereoVo::Process
// (frame-to-frame and keyframe LK, stereo LK on the tracked points, RANSAC, LM refinement, and a
// new keyframe when one is due) along the village racetrack at 20 m and 6 m/s, for each motion
// method; and the 9-state VO+IMU Kalman filter (Eq. 5.40-5.45): one 50 Hz prediction and one
// 10 Hz correction. Target: 30 pairs/s or more on this 2-core machine.
#include <vector>

#include <benchmark/benchmark.h>

#include "uav/nav/vo_imu_filter.hpp"
#include "unit/vo_flight.hpp"

namespace {

using uav::vision::RectifiedPair;

struct Flight {
  uav::vision::RectifiedGeometry geometry;
  std::vector<RectifiedPair> pairs;
};

const Flight& Racetrack() {
  static const Flight flight = [] {
    const uav::world::Scene scene = uav::vision::testing::VoVillage();
    const uav::vision::testing::StereoFlightRenderer render(scene);
    Flight f{render.geometry(), {}};
    for (int i = 0; i < 120; ++i)
      f.pairs.push_back(render.Render(uav::vision::testing::RacetrackPose(i * 0.6, 20.0, 6.0), 1'000'000 + i * 100'000LL).pair);
    return f;
  }();
  return flight;
}

void BM_StereoVoPair(benchmark::State& state) {
  const Flight& flight = Racetrack();
  const auto& pairs = flight.pairs;
  uav::vision::VoParams params;
  params.method = static_cast<uav::vision::VoMethod>(state.range(0));
  state.SetLabel(uav::vision::Name(params.method));
  auto vo = std::make_unique<uav::vision::StereoVo>(flight.geometry, params);
  std::size_t i = 0;
  int64_t utime = 0;
  for (auto _ : state) {
    if (i == pairs.size()) {  // the flight is replayed from a fresh odometry
      state.PauseTiming();
      vo = std::make_unique<uav::vision::StereoVo>(flight.geometry, params);
      i = 0;
      state.ResumeTiming();
    }
    RectifiedPair p = pairs[i++];
    p.left_utime = p.right_utime = (utime += 100'000);
    const auto r = vo->Process(p);
    benchmark::DoNotOptimize(r.T_WC);
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_StereoVoPair)->Arg(0)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_VoImuFilterPredict(benchmark::State& state) {
  uav::nav::VoImuFilter f;
  f.Reset(Eigen::Vector3d(1, 2, -20), Eigen::Vector3d(3, 0, 0), 0.5, 0.2);
  const Eigen::Vector3d a(0.1, -0.2, 0.05);
  for (auto _ : state) {
    f.Predict(a, 0.02);
    benchmark::DoNotOptimize(f.p_N());
  }
}
BENCHMARK(BM_VoImuFilterPredict);

void BM_VoImuFilterCorrect(benchmark::State& state) {
  uav::nav::VoImuFilter f;
  f.Reset(Eigen::Vector3d(1, 2, -20), Eigen::Vector3d(3, 0, 0), 0.5, 0.2);
  const Eigen::Vector3d a(0.1, -0.2, 0.05), z(1.01, 2.0, -20.02);
  for (auto _ : state) {
    f.Predict(a, 0.02);  // keeps the covariance from collapsing
    f.Correct(z, 0.1);
    benchmark::DoNotOptimize(f.p_N());
  }
}
BENCHMARK(BM_VoImuFilterCorrect);

}  // namespace

BENCHMARK_MAIN();
