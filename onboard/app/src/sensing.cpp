#include "uav/app/sensing.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "uav/app/active_stereo_worker.hpp"
#include "uav/app/avoid_worker.hpp"
#include "uav/app/camera_worker.hpp"
#include "uav/app/lockstep_scheduler.hpp"
#include "uav/app/mono_depth_worker.hpp"
#include "uav/app/stereo_worker.hpp"
#include "uav/app/stitch_worker.hpp"
#include "uav/app/track_worker.hpp"
#include "uav/app/vo_worker.hpp"
#include "uav/sim/sim_cameras.hpp"
#include "uav/world/scene.hpp"

namespace uav::app {

namespace {
constexpr int64_t kMonitorPeriodUs = 100'000;
constexpr int64_t kReportPeriodUs = 1'000'000;

int64_t LatencyUs(const ParameterSet& p, const char* name, bool measured) {
  return measured ? 0 : static_cast<int64_t>(std::lround(p.Get(name) * 1e3));
}
}  // namespace

struct Sensing::Impl {
  Blackboard& board;
  Options options;
  sim::TruthPoseHistory truth;
  std::unique_ptr<sim::SimCamera> downward_camera;
  std::vector<std::unique_ptr<sim::SimStereoCamera>> stereo_rigs;  // the scene's, in order
  std::unique_ptr<sim::SimGimbalCamera> gimbal_camera;
  std::unique_ptr<CameraWorker> cam;
  std::unique_ptr<StitchWorker> stitch;
  std::unique_ptr<TrackWorker> trk;
  std::unique_ptr<MonoDepthWorker> mdepth;
  std::unique_ptr<StereoWorker> stereo;
  std::unique_ptr<StereoWorker> wires;  // a second pair for wires alone (pwl_rig)
  std::unique_ptr<ActiveStereoWorker> active_stereo;
  std::unique_ptr<VoWorker> vo;
  std::unique_ptr<AvoidWorker> avd;  // obstacle avoidance's planner, on what STEREO senses
  double avd_rate_hz = 10.0;
  int stereo_rig = -1, wire_rig = -1, active_stereo_rig = -1, vo_rig = -1;  // which rig each runs on
  // The vehicle file's latencies [us] by worker (0: measured).
  std::map<std::string, int64_t> latency_us;
  bool measured = false;  // latencies measured (real time), not the vehicle file's
  int64_t last_monitor_utime = -1;
  int64_t last_report_utime = -1;  // the last sensing report for the GCS
  struct Announced {
    bool healthy = true;          // what the operator was last told
    int64_t changed_utime = -1;   // since when the worker has been otherwise (-1: it has not)
  };
  std::map<std::string, Announced> announced;
  struct RateChoice {
    int decimation = 1;               // offered every decimation-th frame of its camera
    int64_t decided_utime = -1;
  };
  std::map<std::string, RateChoice> rates;

  Impl(Blackboard& b, const Options& o) : board(b), options(o) {}
};

Sensing::Sensing(const world::Scene& scene, const ParameterSet& params, Blackboard& board, const Options& options)
    : impl_(std::make_unique<Impl>(board, options)) {
  Impl& s = *impl_;
  if (!scene.downward_camera() && !scene.stereo_camera() && !scene.gimbal_camera())
    throw std::invalid_argument("the scene declares no camera");
  const bool measured = options.measured_latency || params.Get("vis_measured") != 0.0;
  s.measured = measured;
  s.latency_us = {{"CAM", LatencyUs(params, "cam_latency", measured)},
                  {"STITCH", LatencyUs(params, "map_latency", measured)},
                  {"TRK", LatencyUs(params, "trk_latency", measured)},
                  {"MDEPTH", LatencyUs(params, "mdp_latency", measured)},
                  {"STEREO", LatencyUs(params, "obs_latency", measured)},
                  {"WIRES", LatencyUs(params, "obs_latency", measured)},
                  {"ASTEREO", LatencyUs(params, "asv_latency", measured)},
                  {"VO", LatencyUs(params, "vo_latency", measured)},
                  {"AVD", LatencyUs(params, "avd_latency", measured)}};
  // Cameras see the world from the true pose at their exposure, as real ones do.
  const sim::TruthPose truth = s.truth.Lookup();
  if (scene.downward_camera()) {
    CameraWorker::Options cam_options;
    if (!options.log_dir.empty())
      cam_options.capture_dir = options.log_dir + "/captures_" + std::to_string(options.start_utime);
    cam_options.home = options.home;
    s.downward_camera = std::make_unique<sim::SimCamera>(scene, *scene.downward_camera(), truth);
    s.cam = std::make_unique<CameraWorker>(*s.downward_camera, board, cam_options);
    if (!options.log_dir.empty())
      s.stitch = std::make_unique<StitchWorker>(
          scene.downward_camera()->intrinsics, board,
          StitchWorker::Options{options.log_dir + "/maps_" + std::to_string(options.start_utime), options.home});
  }
  if (scene.gimbal_camera()) {
    const auto trk_params = TrackWorkerParams::FromParameters(params);
    s.gimbal_camera =
        std::make_unique<sim::SimGimbalCamera>(scene, *scene.gimbal_camera(), truth, trk_params.gimbal_pitch_rad);
    s.trk = std::make_unique<TrackWorker>(*s.gimbal_camera, board, trk_params);
  }
  // Depth from motion on the chosen camera, when the scene has it.
  const auto mdp = MonoDepthWorkerParams::FromParameters(params);
  if (mdp.camera == 1 && s.downward_camera)
    s.mdepth = std::make_unique<MonoDepthWorker>(s.downward_camera->info(), board, mdp.estimator, mdp.to_map);
  if (mdp.camera == 2 && s.gimbal_camera)
    s.mdepth = std::make_unique<MonoDepthWorker>(s.gimbal_camera->info(), board, mdp.estimator, mdp.to_map);
  BuildStereo(scene, params);
}

void Sensing::BuildStereo(const world::Scene& scene, const ParameterSet& params) {
  // The stereo rigs and what runs on each (the vehicle file's *_rig): active stereo on a downward
  // rig whose laser dots give the height (asv_enable), visual odometry (vo_enable), obstacles
  // and wires (obs_rig; by default the first rig none of the others uses), and wires alone on a
  // second pair (pwl_rig: rolled about its axis, it ranges the level wires whose image runs along
  // the first pair's baseline, thesis 3.6). Algorithms on one rig take its exposures in turn
  // (AddTo): the projector on for one, off for the next.
  Impl& s = *impl_;
  const int rigs = static_cast<int>(scene.stereo_rigs().size());
  if (rigs == 0) return;
  const sim::TruthPose truth = s.truth.Lookup();
  for (const world::StereoSetup& rig : scene.stereo_rigs())
    s.stereo_rigs.push_back(std::make_unique<sim::SimStereoCamera>(scene, rig, truth));
  auto rig_of = [&](const char* name) {
    const int k = static_cast<int>(params.Get(name));
    if (k >= rigs)
      throw std::invalid_argument(std::string(name) + " " + std::to_string(k) + ": the scene has " +
                                  std::to_string(rigs) + " stereo rig" + (rigs == 1 ? "" : "s") + " (from 0)");
    return k;
  };
  const auto asv = ActiveStereoWorkerParams::FromParameters(params);
  auto vop = VoWorkerParams::FromParameters(params);
  if (asv.enabled) {
    s.active_stereo_rig = rig_of("asv_rig");
    s.active_stereo = std::make_unique<ActiveStereoWorker>(*s.stereo_rigs[s.active_stereo_rig], s.board, asv);
  }
  if (vop.enabled) {
    s.vo_rig = rig_of("vo_rig");
    // A rig shared with active stereo streams the lit pairs, with the dots the GCS draws over them.
    vop.stream_video = s.vo_rig != s.active_stereo_rig;
    s.vo = std::make_unique<VoWorker>(*s.stereo_rigs[s.vo_rig], s.board, vop);
  }
  const StereoWorkerParams obs = StereoWorkerParams::FromParameters(params);
  if (obs.power_lines) s.wire_rig = rig_of("pwl_rig");
  if (params.Get("obs_enable") != 0.0) {
    s.stereo_rig = rig_of("obs_rig");
    for (int k = 0; k < rigs && s.stereo_rig < 0; ++k)
      if (k != s.active_stereo_rig && k != s.vo_rig && k != s.wire_rig) s.stereo_rig = k;
  }
  if (s.wire_rig >= 0 && s.wire_rig == s.stereo_rig) s.wire_rig = -1;  // the one rig has both
  if (s.stereo_rig >= 0) {
    StereoWorkerParams p = obs;
    p.power_lines = obs.power_lines && s.wire_rig < 0;
    s.stereo = std::make_unique<StereoWorker>(*s.stereo_rigs[s.stereo_rig], s.board, p);
  }
  if (s.wire_rig >= 0) {
    StereoWorkerParams p = obs;
    p.detect_obstacles = false;
    s.wires = std::make_unique<StereoWorker>(*s.stereo_rigs[s.wire_rig], s.board, p);
  }
  const auto avd = avoid::AvoidanceParams::FromParameters(params);
  if (avd.enabled && !s.stereo)
    throw std::invalid_argument("avd_enable 1 needs obstacles on a stereo rig: obs_enable is 0, or every rig is taken by odometry or active stereo (obs_rig)");
  s.avd_rate_hz = avd.rate_hz;
  if (avd.enabled)
    s.avd = std::make_unique<AvoidWorker>(
        s.board, avd, s.options.log_dir.empty() ? "" : s.options.log_dir + "/map_" + std::to_string(s.options.start_utime) + ".bt");
}

Sensing::~Sensing() = default;

const avoid::OccupancyMap* Sensing::avoidance_map() const { return impl_->avd ? &impl_->avd->map() : nullptr; }

void Sensing::SetStereoFailed(int rig, bool failed) {
  if (rig < 0 || rig >= static_cast<int>(impl_->stereo_rigs.size()))
    throw std::out_of_range("stereo rig " + std::to_string(rig) + ": the scene has " + std::to_string(impl_->stereo_rigs.size()));
  impl_->stereo_rigs[static_cast<std::size_t>(rig)]->SetFailed(failed);
}

void Sensing::AddTo(LockstepScheduler& scheduler, int64_t step_us) {
  Impl& s = *impl_;
  // Camera periods on the physics grid (5 Hz -> 200 ms).
  auto period = [&](double rate_hz) {
    return std::max<int64_t>(step_us, static_cast<int64_t>(std::lround(1e6 / rate_hz / step_us)) * step_us);
  };
  auto add = [&](const std::string& name, VisionWorker& worker, VisionTiming timing) {
    timing.latency_us = s.latency_us.at(name);
    auto outbox = std::make_shared<Outbox>();
    scheduler.AddVisionWorker(name, timing,
                              {[&worker](int64_t t) { worker.Begin(t); }, [&worker, outbox] { worker.Work(*outbox); },
                               [&worker, outbox] { outbox->ApplyTo(worker.board()); }});
  };
  if (s.cam) add("CAM", *s.cam, {period(s.downward_camera->info().rate_hz), 0, 0, true, 1'000'000, s.downward_camera->info().name});
  // The stitcher takes every capture waiting (none is dropped); its map at landing takes seconds.
  if (s.stitch) add("STITCH", *s.stitch, {100'000, 0, 0, false, 120'000'000, s.downward_camera->info().name});
  if (s.trk) add("TRK", *s.trk, {period(s.gimbal_camera->info().rate_hz), 0, 0, true, 1'000'000, s.gimbal_camera->info().name});
  if (s.mdepth) add("MDEPTH", *s.mdepth, {period(s.mdepth->rate_hz()), 0, 0, true, 1'000'000, s.mdepth->camera()});
  if (s.avd) add("AVD", *s.avd, {period(impl_->avd_rate_hz), 0, 0, true, 1'000'000, ""});
  // Each rig's exposures go round its algorithms in turn: active stereo, odometry, obstacles.
  for (int k = 0; k < static_cast<int>(s.stereo_rigs.size()); ++k) {
    std::vector<std::pair<std::string, VisionWorker*>> on_rig;
    if (s.active_stereo && s.active_stereo_rig == k) on_rig.emplace_back("ASTEREO", s.active_stereo.get());
    if (s.vo && s.vo_rig == k) on_rig.emplace_back("VO", s.vo.get());
    if (s.stereo && s.stereo_rig == k) on_rig.emplace_back("STEREO", s.stereo.get());
    if (s.wires && s.wire_rig == k) on_rig.emplace_back("WIRES", s.wires.get());
    const hal::CameraInfo& left = s.stereo_rigs[k]->left();
    const int64_t frame = period(left.rate_hz);
    const int64_t each = frame * static_cast<int64_t>(on_rig.size());
    for (std::size_t i = 0; i < on_rig.size(); ++i)
      add(on_rig[i].first, *on_rig[i].second, {each, frame * static_cast<int64_t>(i), 0, true, 1'000'000, left.name});
  }
}

void Sensing::RecordTruth(int64_t utime, const Eigen::Isometry3d& T_NB) { impl_->truth.Record(utime, T_NB); }

void Sensing::ChooseRate(int64_t utime, SensingWorker& w, LockstepScheduler& scheduler) {
  // Where two cores cannot hold a worker's rate, the vehicle lowers it on purpose rather than
  // dropping whichever frames come while the worker is busy: every 2 s, a worker behind is offered
  // only every k-th frame of its camera, k = the camera's rate over what it achieved (rounded up,
  // at most kMaxDecimation), so its frames are evenly spaced and it is healthy at a rate it holds.
  // With room to spare (compute under 60 % of the next faster period) it steps back up.
  // Only where latencies are measured (real time): on a simulated clock the vehicle file's
  // latencies decide which frames are dropped, the same in every run.
  constexpr int kMaxDecimation = 8;
  constexpr int64_t kDecideEveryUs = 2'000'000;
  if (w.camera_rate_hz <= 0 || !impl_->measured) return;
  Impl::RateChoice& c = impl_->rates[w.name];
  if (c.decided_utime < 0) c.decided_utime = utime;
  if (utime - c.decided_utime >= kDecideEveryUs) {
    int k = c.decimation;
    if (!w.healthy && w.reason.rfind("behind", 0) == 0)
      k = std::min(kMaxDecimation, std::max(k + 1, static_cast<int>(std::ceil(w.camera_rate_hz / std::max(w.rate_hz, 0.1)))));
    else if (w.healthy && k > 1 && w.compute_p50_ms < 0.6 * 1e3 * (k - 1) / w.camera_rate_hz)
      --k;
    if (k != c.decimation) {
      char text[200];
      std::snprintf(text, sizeof text, "sensing: %s %s to %.1f Hz of its camera's %.1f (compute %.0f ms a frame)",
                    w.name.c_str(), k > c.decimation ? "lowered" : "raised", w.camera_rate_hz / k, w.camera_rate_hz,
                    w.compute_p50_ms);
      impl_->board.PushStatus(k > c.decimation ? Severity::kWarning : Severity::kInfo, text);
      scheduler.SetDecimation(w.name, k);
      c.decimation = k;
    }
    c.decided_utime = utime;
  }
  if (w.healthy && c.decimation > 1) {
    char text[160];
    std::snprintf(text, sizeof text, "lowered to %.1f Hz (CPU)", w.camera_rate_hz / c.decimation);
    w.reason = text;
  }
}

void Sensing::Monitor(int64_t utime, LockstepScheduler& scheduler) {
  Impl& s = *impl_;
  if (s.last_monitor_utime >= 0 && utime - s.last_monitor_utime < kMonitorPeriodUs) return;
  s.last_monitor_utime = utime;
  SensingReport report;
  report.utime = utime;
  report.measured_latency = s.measured;
  const PeriodStats control = scheduler.Period("CTL");
  report.control_period_p50_ms = control.p50_ms;
  report.control_period_p99_ms = control.p99_ms;
  report.control_period_max_ms = control.max_ms;
  report.workers = scheduler.VisionHealth();
  for (SensingWorker& w : report.workers) ChooseRate(utime, w, scheduler);
  // The operator hears of a change once it has held for a second (the telemetry has it at once):
  // a rate near its threshold must not fill the messages.
  constexpr int64_t kAnnounceAfterUs = 1'000'000;
  for (const SensingWorker& w : report.workers) {
    Impl::Announced& a = s.announced[w.name];
    if (w.healthy == a.healthy) {
      a.changed_utime = -1;
      continue;
    }
    if (a.changed_utime < 0) a.changed_utime = utime;
    if (utime - a.changed_utime < kAnnounceAfterUs) continue;
    a.healthy = w.healthy;
    a.changed_utime = -1;
    s.board.PushStatus(w.healthy ? Severity::kInfo : Severity::kWarning,
                       "sensing: " + w.name + (w.healthy ? " healthy again" : " " + w.reason));
  }
  // The GCS hears the workers' health once a second.
  if (!report.workers.empty() && (s.last_report_utime < 0 || utime - s.last_report_utime >= kReportPeriodUs)) {
    s.last_report_utime = utime;
    s.board.reports.Put(std::move(report));
  }
}

std::string Sensing::BenchmarkJson(const LockstepScheduler& scheduler, double speed, double simulated_s,
                                   double wall_s) const {
  const Impl& s = *impl_;
  nlohmann::json j;
  j["speed"] = speed;
  j["simulated_s"] = simulated_s;
  j["wall_s"] = wall_s;
  j["latency"] = s.measured ? "measured" : "vehicle file";
  const PeriodStats control = scheduler.Period("CTL");
  j["control_period_ms"] = {{"nominal", 20.0}, {"p50", control.p50_ms}, {"p99", control.p99_ms},
                            {"max", control.max_ms}, {"samples", control.samples}};
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const double user_s = usage.ru_utime.tv_sec + usage.ru_utime.tv_usec * 1e-6;
  const double system_s = usage.ru_stime.tv_sec + usage.ru_stime.tv_usec * 1e-6;
  j["cpu"] = {{"user_s", user_s}, {"system_s", system_s},
              {"cores_busy", wall_s > 0 ? (user_s + system_s) / wall_s : 0.0}};
  for (const SensingWorker& w : scheduler.VisionHealth()) {
    j["workers"].push_back({{"name", w.name},
                            {"rig", w.rig},
                            {"camera_rate_hz", w.camera_rate_hz},
                            {"configured_rate_hz", w.configured_rate_hz},
                            {"rate_hz_run", simulated_s > 0 ? w.results / simulated_s : 0.0},
                            {"rate_hz_last_2s", w.rate_hz},
                            {"latency_p50_ms", w.latency_p50_ms},
                            {"latency_p99_ms", w.latency_p99_ms},
                            {"compute_p50_ms", w.compute_p50_ms},
                            {"results", w.results},
                            {"dropped", w.dropped},
                            {"healthy", w.healthy},
                            {"reason", w.reason}});
  }
  return j.dump(2) + "\n";
}

std::string Sensing::Summary() const {
  const Impl& s = *impl_;
  std::string out;
  if (s.cam)
    out += ", " + std::to_string(s.cam->captures()) + " survey images captured, " + std::to_string(s.cam->previews()) + " previews";
  if (s.stereo) out += ", " + std::to_string(s.stereo->frames()) + " stereo pairs";
  if (s.wires) out += ", " + std::to_string(s.wires->frames()) + " pairs for wires";
  if (s.active_stereo)
    out += ", " + std::to_string(s.active_stereo->frames()) + " active stereo pairs (" +
           std::to_string(s.active_stereo->unhealthy()) + " without a height)";
  if (s.vo)
    out += ", " + std::to_string(s.vo->frames()) + " visual odometry pairs (" + std::to_string(s.vo->unhealthy()) +
           " unhealthy" + (s.vo->unhealthy() ? ": " + s.vo->UnhealthySummary(3) : "") + ")";
  if (s.trk) out += ", " + std::to_string(s.trk->frames()) + " gimbal frames";
  if (s.stitch && s.stitch->maps_written() > 0) out += ", map " + s.stitch->last_map() + ".tif";
  return out;
}

}  // namespace uav::app
