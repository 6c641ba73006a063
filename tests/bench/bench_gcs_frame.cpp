// One headless GCS frame (issue 6 item 9: target <= 4 ms): every panel drawn by the same code as
// the window, with 20 signals plotted, each holding 30 minutes at 50 Hz (90,000 samples), on two
// plot panels (half of them on the right axis), the telemetry tree open, the map with its trail.
// Arguments: the plot window in seconds (60: the default; 1800: all 30 minutes on screen).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include <imgui.h>

#include "unit/gcs_test_util.hpp"
#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"

namespace {

void BM_GcsFrame(benchmark::State& state) {
  using namespace uav::gcs;
  auto platform = MakeNullPlatform(1600, 900);
  GcsModel model("bench", 1);
  model.OnHeartbeat("UAV1", 1, Hb(2, true), 0.0);
  constexpr int kSamples = 30 * 60 * 50;
  // 20 of the state's signals, each a sine of its own frequency.
  for (int i = 0; i < kSamples; ++i) {
    uav::VehicleState s;
    s.utime = static_cast<int64_t>(i) * 20000;
    const auto w = [&](int k) { return std::sin(0.001 * i * (k + 1)) * (k + 1); };
    s.p_N = {w(0), w(1), w(2)};
    s.v_B = {w(3), w(4), w(5)};
    s.euler = {w(6), w(7), w(8)};
    s.w_B = {w(9), w(10), w(11)};
    s.f_B = {w(12), w(13), w(14)};
    for (int k = 0; k < 4; ++k) s.rotor_input[k] = w(15 + k);
    s.servo_input[0] = w(19);
    model.OnState("UAV1", i + 1, s, i * 0.02);
  }
  for (int k = 0; k < 20; ++k) {
    const SignalRef signal{SignalGroupId::kState, k};
    if (k == 10) model.plots().Add();
    model.plots().Toggle(signal);
    if (k % 2) model.plots().SetAxis(model.plots().active(), signal, PlotAxis::kRight);
  }
  model.plots().SetWindow(static_cast<double>(state.range(0)));
  UiContext ctx;
  ctx.now = kSamples * 0.02;
  for (auto _ : state) {
    platform->NewFrame(1.0 / 60);
    ImGui::NewFrame();
    DrawGcs(model, ctx);
    platform->Render();
  }
  state.counters["signals"] = 20;
  state.counters["samples_each"] = kSamples;
}
BENCHMARK(BM_GcsFrame)->Arg(60)->Arg(1800)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
