// uav-gcs: the ground control station. The same panels run in a GLFW window or headless.
#include <algorithm>
#include <vector>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <memory>

#include <CLI/CLI.hpp>
#include <imgui.h>

#include "demo_script.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"
#include "uav/gcs/script.hpp"
#include "uav/gcs/script_input.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/time.hpp"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }
double Now() { return uav::MonotonicMicros() * 1e-6; }
}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-gcs: ground control station"};
  std::string lcm_url = uav::kDefaultLcmUrl;
  std::string name = "gcs-" + std::to_string(getpid());
  bool headless = false, demo = false;
  std::string script_path, vehicle, layout = "uav-gcs.ini";
  double exit_after = 0.0;
  std::string download_dir;
  cli.add_option("--lcm-url", lcm_url, "LCM URL")->capture_default_str();
  cli.add_option("--name", name, "this GCS's name on the bus (commands are answered to it)");
  cli.add_flag("--headless", headless, "no window: ImGui null backend, same panels");
  cli.add_option("--script", script_path, "run a script of operator steps, exit 0 only if all pass");
  cli.add_flag("--demo", demo, "run the built-in demo flight script")->excludes("--script");
  cli.add_option("--vehicle", vehicle, "vehicle to show first (default: the first one heard)");
  cli.add_option("--layout", layout, "window layout file, kept between runs")->capture_default_str();
  cli.add_option("--download-dir", download_dir,
                 "download every map a vehicle offers into this directory as soon as it is offered");
  cli.add_option("--exit-after", exit_after, "quit after this many seconds (0: never)")->check(CLI::Range(0.0, 1e6));
  CLI11_PARSE(cli, argc, argv);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  try {
    std::unique_ptr<uav::gcs::ScriptRunner> runner;
    if (demo) runner = std::make_unique<uav::gcs::ScriptRunner>(uav::gcs::Script::Parse(uav::gcs::kDemoScript, "demo"), stdout);
    else if (!script_path.empty()) runner = std::make_unique<uav::gcs::ScriptRunner>(uav::gcs::Script::LoadFile(script_path), stdout);

    uav::gcs::GcsModel model(name, uav::WallTimeMicros());
    uav::gcs::GcsLink link(lcm_url, model);
    std::unique_ptr<uav::gcs::Platform> platform =
        headless ? uav::gcs::MakeNullPlatform(1600, 900)
                 : uav::gcs::MakeGlfwPlatform(1600, 900, "uav-gcs", layout);
    uav::gcs::UiContext ctx;
    if (!download_dir.empty()) {
      model.SetDownloadDir(download_dir);
      ctx.state.download_dir = download_dir;
    }
    uav::gcs::Platform* p = platform.get();
    uav::gcs::ImGuiScriptDriver driver(
        ctx, p->has_display() ? uav::gcs::ImGuiScriptDriver::ScreenshotFn(
                                    [p](const std::string& path, std::string* err) { return p->Screenshot(path, err); })
                              : nullptr);
    std::printf("uav-gcs %s: %s, LCM %s%s\n", name.c_str(), headless ? "headless" : "window",
                lcm_url.c_str(), runner ? (demo ? ", demo script" : (", script " + script_path).c_str()) : "");
    std::fflush(stdout);

    const double start = Now();
    ctx.start_time = start;
    ctx.update_texture = [&platform](int slot, const uint8_t* rgba, int w, int h) {
      return platform->UpdateTexture(slot, rgba, w, h);
    };
    double last = start;
    std::vector<double> frame_ms;  // work per frame (panels, draw data, rendering), for the exit line
    while (!g_stop) {
      const double now = Now();
      ctx.now = now;
      link.Poll(headless ? 15 : 0, now);  // headless: the receive wait paces the loop (~60 Hz)
      model.Tick(now);
      if (!vehicle.empty() && model.selected_id() != vehicle) model.SelectVehicle(vehicle);
      if (!p->NewFrame(now - last)) break;
      last = now;
      const double work_start = Now();
      driver.ApplyNextEvent();
      ImGui::NewFrame();
      uav::gcs::DrawGcs(model, ctx);
      p->Render();
      frame_ms.push_back(1e3 * (Now() - work_start));
      if (runner && !runner->Update(model, driver, Now())) break;
      if (exit_after > 0 && now - start > exit_after) break;
    }
    if (!frame_ms.empty()) {
      const double seconds = Now() - start;
      std::sort(frame_ms.begin(), frame_ms.end());
      std::printf("uav-gcs: %zu frames in %.1f s (%.0f per second), work per frame median %.2f ms, 99th percentile %.2f ms\n",
                  frame_ms.size(), seconds, frame_ms.size() / std::max(seconds, 1e-9), frame_ms[frame_ms.size() / 2],
                  frame_ms[frame_ms.size() * 99 / 100]);
    }
    if (runner) {
      const int failed = runner->failed() ? 1 : 0;
      std::printf("script %s: %d passed, %d failed%s\n", demo ? "demo" : script_path.c_str(), runner->passed(),
                  failed, g_stop ? " (interrupted)" : "");
      return failed || g_stop || !runner->finished() ? 1 : 0;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-gcs: %s\n", e.what());
    return 2;
  }
}
