// One headless GCS frame (issue 6 item 9: target <= 4 ms): every panel drawn by the same code as
// the window, with 20 signals plotted, each holding 30 minutes at 50 Hz (90,000 samples), on two
// plot panels (half of them on the right axis), the telemetry tree open, the map with its trail.
// Arguments: the plot window in seconds (60: the default; 1800: all 30 minutes on screen).
#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"

namespace {

void BM_GcsFrame(benchmark::State& state) {
  using namespace uav::gcs;
  auto platform = MakeNullPlatform(1600, 900);
  GcsModel model("bench", 1);
  model.OnHeartbeat("UAV1", 1, 2, true, 0.0);
  constexpr int kSamples = 30 * 60 * 50;
  TelemetrySample s{"UAV1", "STATE", 0, 0.0, {}};
  for (int k = 0; k < 20; ++k) s.values.emplace_back(k == 0 ? "x" : k == 1 ? "y" : "s" + std::to_string(k), 0.0);
  for (int i = 0; i < kSamples; ++i) {
    s.seq = i + 1;
    s.t = i * 0.02;
    for (int k = 0; k < 20; ++k) s.values[k].second = std::sin(0.001 * i * (k + 1)) * (k + 1);
    model.OnTelemetry(s, i * 0.02);
  }
  for (int k = 0; k < 20; ++k) {
    const std::string key = "STATE." + s.values[k].first;
    if (k == 10) model.AddPlot();
    model.TogglePlotSignal(key);
    if (k % 2) model.SetSignalAxis(model.active_plot(), key, PlotAxis::kRight);
  }
  model.SetPlotWindow(static_cast<double>(state.range(0)));
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
