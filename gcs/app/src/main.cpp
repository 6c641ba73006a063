// uav-gcs: the ground control station. The same panels run in a GLFW window or headless.
#include <algorithm>
#include <vector>
#include <unistd.h>

#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <memory>
#include <optional>

#include <CLI/CLI.hpp>
#include <imgui.h>

#include "demo_script.hpp"
#include "uav/gcs/speaker.hpp"
#include "uav/gcs/spoken_alerts.hpp"
#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/log_replay.hpp"
#include "uav/gcs/mavlink_link.hpp"
#include "uav/wire/bus.hpp"
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"
#include "uav/gcs/script.hpp"
#include "uav/gcs/script_input.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/time.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/process_memory.hpp"
#include "uav/shared/vehicle_enums.hpp"

namespace {
volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }
double Now() { return uav::MonotonicMicros() * 1e-6; }

// Scripts and the Replay panel drive the replay through this. A seek back rebuilds the model, so
// the panel's seeks wait for the start of the next frame (`deferred`), when no panel holds it.
class ReplayScriptControl : public uav::gcs::ReplayControl {
 public:
  ReplayScriptControl(uav::gcs::LogReplay& r, bool deferred) : r_(r), deferred_(deferred) {}
  void Seek(double t) override {
    if (deferred_) pending_ = t;
    else r_.Seek(t);
  }
  void ApplyPending() {
    if (pending_) r_.Seek(*pending_);
    pending_.reset();
  }
  void Pause() override { r_.Pause(); }
  void Play() override { r_.Play(); }
  bool SetSpeed(double speed) override { return r_.SetSpeed(speed); }
  double speed() const override { return r_.speed(); }
  std::size_t events() const override { return r_.events(); }
  std::string path() const override { return r_.path(); }
  double position() const override { return r_.position(); }
  double duration() const override { return r_.duration(); }
  bool paused() const override { return r_.paused(); }
  std::size_t dispatched() const override { return r_.dispatched(); }
  std::string damage() const override { return r_.damage(); }

 private:
  uav::gcs::LogReplay& r_;
  bool deferred_;
  std::optional<double> pending_;
};
}  // namespace

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  CLI::App cli{"uav-gcs: ground control station"};
  std::string lcm_url = uav::kDefaultLcmUrl;
  std::string name = "gcs-" + std::to_string(getpid());
  bool headless = false, demo = false, demo_ulion = false;
  std::string script_path, vehicle, layout = "uav-gcs.ini";
  double exit_after = 0.0;
  std::string download_dir;
  std::string replay_path;
  double replay_speed = 1.0;
  uav::gcs::WireWarningParams wire_warning;
  cli.add_option("--lcm-url", lcm_url, "LCM URL")->capture_default_str();
  cli.add_option("--name", name, "this GCS's name on the bus (commands are answered to it)");
  cli.add_flag("--headless", headless, "no window: ImGui null backend, same panels");
  cli.add_option("--script", script_path, "run a script of operator steps, exit 0 only if all pass");
  cli.add_flag("--demo", demo, "run the built-in demo flight script")->excludes("--script");
  cli.add_flag("--demo-ulion", demo_ulion, "run the built-in demo flight script for U-Lion (the survey on its wing)")
      ->excludes("--script")
      ->excludes("--demo");
  bool no_speech = false;
  cli.add_flag("--no-speech", no_speech, "do not speak warnings and failsafes (spoken with espeak-ng when installed)");
  cli.add_option("--vehicle", vehicle, "vehicle to show first (default: the first one heard)");
  cli.add_option("--layout", layout, "window layout file, kept between runs")->capture_default_str();
  std::string size_text = "1600x900";
  cli.add_option("--size", size_text, "window size WIDTHxHEIGHT [px] (the default layout fits 1600x900 and up)")
      ->check([](const std::string& v) {
        int w = 0, h = 0;
        char x = 0, extra = 0;
        return std::sscanf(v.c_str(), "%d%c%d%c", &w, &x, &h, &extra) == 3 && x == 'x' && w >= 640 && h >= 480 && w <= 8192 && h <= 8192
                   ? std::string()
                   : "must be WIDTHxHEIGHT, 640x480 to 8192x8192, e.g. 1920x1080";
      })
      ->capture_default_str();
  std::string basemap;
  cli.add_option("--basemap", basemap, "a GeoTIFF to draw under the map (e.g. the last survey's map)");
  cli.add_option("--download-dir", download_dir,
                 "download every map a vehicle offers into this directory as soon as it is offered");
  cli.add_option("--replay", replay_path,
                 "play an onboard event log (events_<utime>.lcmlog) into the panels; nothing is sent on any bus")
      ->check(CLI::ExistingFile);
  cli.add_option("--speed", replay_speed, "replay speed")
      ->check(CLI::Range(uav::gcs::LogReplay::kMinSpeed, uav::gcs::LogReplay::kMaxSpeed))
      ->needs("--replay")
      ->capture_default_str();
  cli.add_option("--wire-warning", wire_warning.warn_distance_m,
                 "warn (status bar, messages) when a ranged power line is nearer than this [m]")
      ->check(CLI::Range(0.5, 500.0))
      ->capture_default_str();
  std::string key_path;
  bool insecure = false;
  auto* key_option = cli.add_option("--key", key_path,
                                    "signing key shared with the vehicles (uav-keygen FILE, mode 0600): commands, "
                                    "missions, targets, file requests and heartbeats are signed with it");
  cli.add_flag("--insecure", insecure, "send unsigned (only a vehicle started with --insecure obeys); shown in red")
      ->excludes(key_option);
  std::vector<std::string> mavlink_endpoints;
  std::string mavlink_key_path, mavlink_passphrase;
  int mavlink_video_port = 5600;
  cli.add_option("--mavlink", mavlink_endpoints,
                 "MAVLink vehicles (PX4, ArduPilot) beside the bus: udpin:14550 listens as QGroundControl does, "
                 "udp:HOST:PORT connects out, serial:DEVICE[:BAUD] a telemetry radio (repeat for several)");
  auto* mavlink_key_option = cli.add_option("--mavlink-key", mavlink_key_path,
                                            "MAVLink 2 signing key file (32 bytes, mode 0600; uav-keygen): frames sent "
                                            "are signed, frames received must be")
                                 ->needs("--mavlink");
  cli.add_option("--mavlink-passphrase", mavlink_passphrase,
                 "MAVLink 2 signing from a passphrase (its SHA-256, as QGroundControl and Mission Planner make the key)")
      ->needs("--mavlink")
      ->excludes(mavlink_key_option);
  cli.add_option("--mavlink-video", mavlink_video_port, "UDP port of the vehicles' RTP/H.264 video (0: none)")
      ->check(CLI::Range(0, 65535))
      ->needs("--mavlink")
      ->capture_default_str();
  cli.add_option("--exit-after", exit_after, "quit after this many seconds (0: never)")->check(CLI::Range(0.0, 1e6));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);

  std::signal(SIGINT, OnSignal);
  std::signal(SIGTERM, OnSignal);
  try {
    // UAV_TIMEOUT_SCALE: the scripts' waits times this (tests/sanitizers/sanitize.sh sets it).
    double timeout_scale = 1.0;
    if (const char* scale = std::getenv("UAV_TIMEOUT_SCALE")) {
      char* end = nullptr;
      timeout_scale = std::strtod(scale, &end);
      if (end == scale || *end != '\0' || !(timeout_scale >= 1.0 && timeout_scale <= 100.0))
        throw std::invalid_argument(std::string("UAV_TIMEOUT_SCALE must be a number from 1 to 100, not '") + scale + "'");
    }
    std::unique_ptr<uav::gcs::ScriptRunner> runner;
    if (demo_ulion) demo = true;
    if (demo)
      runner = std::make_unique<uav::gcs::ScriptRunner>(
          uav::gcs::Script::Parse(demo_ulion ? uav::gcs::kDemoScriptULion : uav::gcs::kDemoScript, "demo"), stdout, timeout_scale);
    else if (!script_path.empty())
      runner = std::make_unique<uav::gcs::ScriptRunner>(uav::gcs::Script::LoadFile(script_path), stdout, timeout_scale);

    if (name == uav::kVehicleInitiatedSource)
      throw std::invalid_argument("--name '" + name + "' is the vehicle's own name for what it does on its own: pick another");
    const bool replaying = !replay_path.empty();
    if (!replaying && key_path.empty() && !insecure)
      throw std::invalid_argument("give --key FILE (the vehicle's key; uav-keygen FILE makes one) or, to send "
                                  "unsigned, --insecure");
    std::optional<uav::SigningKey> key;
    if (!key_path.empty()) key = uav::SigningKey::LoadFile(key_path);
    // Live: the bus and a link on it. Replay: no bus at all (nothing can be sent), a decode-only
    // link, and both rebuilt when the replay seeks back.
    std::unique_ptr<uav::Bus> bus = replaying ? nullptr : std::make_unique<uav::Bus>(lcm_url);
    std::unique_ptr<uav::gcs::GcsModel> model_ptr;
    std::unique_ptr<uav::gcs::GcsLink> link_ptr;
    uav::gcs::UiContext ctx;
    auto fresh_model = [&]() -> uav::gcs::GcsLink& {
      link_ptr.reset();
      model_ptr = std::make_unique<uav::gcs::GcsModel>(name, uav::WallTimeMicros());
      model_ptr->SetReplay(replaying);
      if (!download_dir.empty()) model_ptr->maps().SetDownloadDir(download_dir);
      model_ptr->wires().params() = wire_warning;
      if (!basemap.empty()) model_ptr->LoadBasemap(basemap, Now());
      ctx.state.basemap_version = -1;
      link_ptr = std::make_unique<uav::gcs::GcsLink>(bus.get(), *model_ptr, key);
      // The panels' caches belong to the old model's frames and tiles.
      ctx.state.live_tiles.clear();
      ctx.state.live_map_id = -1;
      ctx.state.video_frames_shown = -1;
      return *link_ptr;
    };
    std::unique_ptr<uav::gcs::LogReplay> replay;
    if (replaying) {
      replay = std::make_unique<uav::gcs::LogReplay>(replay_path, fresh_model);
      replay->SetSpeed(replay_speed);
      std::printf("uav-gcs: replaying %s: %zu events, %.1f s of flight at x%.1f%s%s\n", replay_path.c_str(),
                  replay->events(), replay->duration(), replay_speed, replay->damage().empty() ? "" : "; damaged at ",
                  replay->damage().c_str());
    } else {
      fresh_model();
    }
    // MAVLink vehicles beside the bus (live only): their entries of what the model sends go to them.
    std::vector<std::unique_ptr<uav::gcs::MavlinkLink>> mavlink_links;
    if (!mavlink_endpoints.empty() && replaying) throw std::invalid_argument("--mavlink and --replay: a replay sends nothing");
    for (std::size_t i = 0; i < mavlink_endpoints.size(); ++i) {
      uav::gcs::MavlinkLinkParams mp;
      mp.endpoint = mavlink_endpoints[i];
      if (!mavlink_key_path.empty()) mp.key = uav::SigningKey::LoadFile(mavlink_key_path);
      if (!mavlink_passphrase.empty()) mp.key = uav::SigningKey::FromPassphrase(mavlink_passphrase);
      mp.video_port = i == 0 ? mavlink_video_port : 0;  // one video port: the first link's vehicles
      mavlink_links.push_back(std::make_unique<uav::gcs::MavlinkLink>(mp, *model_ptr));
    }
    std::unique_ptr<ReplayScriptControl> panel_control, script_control;
    if (replay) {
      panel_control = std::make_unique<ReplayScriptControl>(*replay, true);
      script_control = std::make_unique<ReplayScriptControl>(*replay, false);
      ctx.replay = panel_control.get();
      if (runner) runner->SetReplay(script_control.get());  // runs after the frame's panels
    }
    int width = 1600, height = 900;
    std::sscanf(size_text.c_str(), "%dx%d", &width, &height);  // checked when parsed
    std::unique_ptr<uav::gcs::Platform> platform =
        headless ? uav::gcs::MakeNullPlatform(width, height)
                 : uav::gcs::MakeGlfwPlatform(width, height, "uav-gcs", layout);
    if (!download_dir.empty()) ctx.state.download_dir = download_dir;
    if (!basemap.empty()) ctx.state.basemap_file = basemap;
    // Spoken alerts (as QGroundControl's): live only, never in a replay or headless.
    uav::gcs::Speaker speaker;
    uav::gcs::SpokenAlerts alerts;
    if (replaying || headless) ctx.state.speech_unavailable = replaying ? "a replay is not spoken" : "headless";
    else if (!speaker.available()) ctx.state.speech_unavailable = "espeak-ng is not installed (Debian: apt-get install espeak-ng)";
    // The box shows what happens: unticked when nothing can be spoken.
    ctx.state.speak_alerts = !no_speech && ctx.state.speech_unavailable.empty();
    uav::gcs::Platform* p = platform.get();
    uav::gcs::ImGuiScriptDriver driver(
        ctx, p->has_display() ? uav::gcs::ImGuiScriptDriver::ScreenshotFn(
                                    [p](const std::string& path, std::string* err) { return p->Screenshot(path, err); })
                              : nullptr);
    std::string mavlink_note;
    for (const std::string& e : mavlink_endpoints) mavlink_note += ", MAVLink " + e;
    std::printf("uav-gcs %s: %s, %s%s%s\n", name.c_str(), headless ? "headless" : "window",
                replaying ? "replay, no bus" : ("LCM " + lcm_url).c_str(), mavlink_note.c_str(), runner ? (demo ? ", demo script" : (", script " + script_path).c_str()) : "");
    std::fflush(stdout);

    const double start = Now();
    ctx.start_time = replay ? replay->now() - replay->position() : start;  // the log's start in a replay
    ctx.update_texture = [&platform](int slot, const uint8_t* rgba, int w, int h) {
      return platform->UpdateTexture(slot, rgba, w, h);
    };
    double last = start;
    double last_replay = start;
    std::vector<double> frame_ms;  // work per frame (panels, draw data, rendering), for the exit line
    while (!g_stop) {
      const double wall = Now();
      double now = wall;
      if (replay) {
        panel_control->ApplyPending();
        replay->Advance(wall - last_replay);
        last_replay = wall;
        now = replay->now();  // the model's clock is the flight's
        if (headless) usleep(15000);
      } else if (mavlink_links.empty()) {
        link_ptr->Poll(headless ? 15 : 0, now);  // headless: the receive wait paces the loop (~60 Hz)
      } else {
        link_ptr->Receive(headless ? 15 : 0, now);
        for (auto& l : mavlink_links) l->Receive(now);
        uav::gcs::GcsOutgoing out = model_ptr->TakeOutgoing();
        for (auto& l : mavlink_links) l->Send(out, now);
        link_ptr->Send(out, now);
      }
      ctx.now = now;
      uav::gcs::GcsModel& model = *model_ptr;
      uav::gcs::GamepadState pad;
      if (p->ReadGamepad(pad.axes.data(), pad.buttons.data())) model.sticks().SetGamepad(pad);
      else model.sticks().SetGamepad(std::nullopt);
      model.Tick(now);
      if (!vehicle.empty() && model.selected_id() != vehicle) model.SelectVehicle(vehicle);
      if (!p->NewFrame(now - last)) break;
      last = now;
      const double work_start = Now();
      driver.ApplyNextEvent();
      ImGui::NewFrame();
      uav::gcs::DrawGcs(model, ctx);
      p->Render();
      for (const std::string& sentence : alerts.Take(model.log(), now))
        if (ctx.state.speak_alerts && ctx.state.speech_unavailable.empty()) speaker.Say(sentence);
      frame_ms.push_back(1e3 * (Now() - work_start));
      if (runner && !runner->Update(model, driver, Now())) break;
      if (exit_after > 0 && wall - start > exit_after) break;
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
