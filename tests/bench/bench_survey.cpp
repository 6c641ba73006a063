// Survey planning speed (issue 3 target: a 1 km^2 concave polygon at 2 cm/px in <= 50 ms).
#include <benchmark/benchmark.h>

#include "uav/waypoints/survey.hpp"

namespace uav::waypoints {
namespace {

// L-shaped: 1200 m x 1000 m minus a 400 m x 500 m corner = 1.0 km^2.
Polygon2 ConcaveSquareKilometre() {
  return {{0, 0}, {0, 1000}, {700, 1000}, {700, 600}, {1200, 600}, {1200, 0}};
}

void PlanAt2cm(benchmark::State& state, CameraSpec camera, const char* label) {
  SurveyParams p;
  p.camera = camera;
  p.gsd_cm_per_px = 2.0;
  p.grid_angle_deg = 17.0;
  const Polygon2 area = ConcaveSquareKilometre();
  std::size_t images = 0, lines = 0;
  for (auto _ : state) {
    const SurveyPlan plan = PlanSurvey(area, p);
    images = plan.captures.size();
    lines = plan.lines;
    benchmark::DoNotOptimize(plan.covered_area_m2);
  }
  state.counters["images"] = static_cast<double>(images);
  state.counters["lines"] = static_cast<double>(lines);
  state.SetLabel(label);
}

// The simulator's 640x480 camera flies at 9.6 m for 2 cm/px: ~200 lines, ~400k images at 5 Hz.
void BM_Plan1km2_SimCamera(benchmark::State& s) { PlanAt2cm(s, {4.8, 3.6, 3.6, 640, 480, true}, "640x480, 9.6 m"); }
// A 20 MP mapping camera flies at 86 m for 2 cm/px.
void BM_Plan1km2_Rx100(benchmark::State& s) { PlanAt2cm(s, {13.2, 8.8, 10.4, 5472, 3648, true}, "RX100, 86 m"); }
BENCHMARK(BM_Plan1km2_SimCamera)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);
BENCHMARK(BM_Plan1km2_Rx100)->Unit(benchmark::kMillisecond)->Repetitions(5)->ReportAggregatesOnly(true);

}  // namespace
}  // namespace uav::waypoints

BENCHMARK_MAIN();
