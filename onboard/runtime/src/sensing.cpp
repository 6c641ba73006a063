#include "uav/runtime/sensing.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>

#include <nlohmann/json.hpp>
#include <stdexcept>

#include "uav/runtime/active_stereo_worker.hpp"
#include "uav/runtime/avoid_worker.hpp"
#include "uav/runtime/camera_worker.hpp"
#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/mono_depth_worker.hpp"
#include "uav/runtime/stereo_worker.hpp"
#include "uav/runtime/stitch_worker.hpp"
#include "uav/runtime/track_worker.hpp"
#include "uav/runtime/vo_worker.hpp"
#include "uav/hal/camera.hpp"

namespace uav::runtime {

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
  SensorRig rig;
  std::unique_ptr<CameraWorker> cam;
  std::unique_ptr<StitchWorker> stitch;
  std::unique_ptr<TrackWorker> trk;
  std::unique_ptr<MonoDepthWorker> mdepth;
  std::unique_ptr<StereoWorker> stereo;
  std::unique_ptr<StereoWorker> wires;  // a second pair for wires alone
  std::unique_ptr<ActiveStereoWorker> active_stereo;
  std::unique_ptr<VoWorker> vo;
  std::unique_ptr<AvoidWorker> avd;  // obstacle avoidance's planner, on what STEREO senses
  double avd_rate_hz = 10.0;
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
  // Each worker's camera, for its health: a camera with no usable image makes its workers unhealthy.
  std::map<std::string, std::function<std::string()>> camera_problem;

  Impl(Blackboard& b, const Options& o, const SensorRig& r) : board(b), options(o), rig(r) {}
};

Sensing::Sensing(const SensorRig& rig, const ParameterSet& params, Blackboard& board, const Options& options)
    : impl_(std::make_unique<Impl>(board, options, rig)) {
  Impl& s = *impl_;
  if (rig.empty()) throw std::invalid_argument("the rig has no camera that feeds a vision worker");
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
  if (rig.survey) {
    CameraWorker::Options cam_options;
    if (!options.log_dir.empty())
      cam_options.capture_dir = options.log_dir + "/captures_" + std::to_string(options.start_utime);
    cam_options.home = options.home;
    s.cam = std::make_unique<CameraWorker>(*rig.survey, board, cam_options);
    if (!options.log_dir.empty())
      s.stitch = std::make_unique<StitchWorker>(
          rig.survey->info().intrinsics, board,
          StitchWorker::Options{options.log_dir + "/maps_" + std::to_string(options.start_utime), options.home});
  }
  if (rig.tracking) s.trk = std::make_unique<TrackWorker>(*rig.tracking, board, TrackWorkerParams::FromParameters(params));
  // Depth from motion on the frames the survey or the tracking camera shares.
  const auto mdp = MonoDepthWorkerParams::FromParameters(params);
  if (rig.depth == SensorRig::DepthCamera::kSurvey && rig.survey)
    s.mdepth = std::make_unique<MonoDepthWorker>(rig.survey->info(), board, mdp.estimator, mdp.to_map);
  if (rig.depth == SensorRig::DepthCamera::kTracking && rig.tracking)
    s.mdepth = std::make_unique<MonoDepthWorker>(rig.tracking->info(), board, mdp.estimator, mdp.to_map);
  BuildStereo(params);
}

void Sensing::BuildStereo(const ParameterSet& params) {
  // What runs on the stereo pairs: active stereo on a downward pair whose laser dots give the
  // height, visual odometry, obstacles, and wires (on the obstacle pair, or alone on a second
  // pair: rolled about its axis, it ranges the level wires whose image runs along the first
  // pair's baseline, thesis 3.6). Algorithms on one pair take its exposures in turn (AddTo): the
  // projector on for one, off for the next.
  Impl& s = *impl_;
  const SensorRig& rig = s.rig;
  if (rig.active_stereo) s.active_stereo = std::make_unique<ActiveStereoWorker>(*rig.active_stereo, s.board, ActiveStereoWorkerParams::FromParameters(params));
  if (rig.odometry) {
    auto vop = VoWorkerParams::FromParameters(params);
    // A pair shared with active stereo streams the lit pairs, with the dots the GCS draws over them.
    vop.stream_video = rig.odometry != rig.active_stereo;
    vop.gyro_aided = s.options.imu;
    // With a log, the odometry's own trajectory as KITTI poses (uav-vo's format, for uav-vo-eval).
    if (!s.options.log_dir.empty()) vop.poses_path = s.options.log_dir + "/vo_" + std::to_string(s.options.start_utime) + ".txt";
    s.vo = std::make_unique<VoWorker>(*rig.odometry, s.board, vop);
  }
  const StereoWorkerParams obs = StereoWorkerParams::FromParameters(params);
  if (rig.obstacles) {
    StereoWorkerParams p = obs;
    p.power_lines = rig.wires == rig.obstacles;
    s.stereo = std::make_unique<StereoWorker>(*rig.obstacles, s.board, p);
  }
  if (rig.wires && rig.wires != rig.obstacles) {
    StereoWorkerParams p = obs;
    p.detect_obstacles = false;
    p.power_lines = true;
    s.wires = std::make_unique<StereoWorker>(*rig.wires, s.board, p);
  }
  const auto avd = avoid::AvoidanceParams::FromParameters(params);
  if (avd.enabled && !s.stereo)
    throw std::invalid_argument("avd_enable 1 needs obstacles on a stereo pair, and the rig gives none (obs_enable 0, or every pair is taken by odometry or active stereo: obs_rig)");
  s.avd_rate_hz = avd.rate_hz;
  if (avd.enabled)
    s.avd = std::make_unique<AvoidWorker>(
        s.board, avd, s.options.log_dir.empty() ? "" : s.options.log_dir + "/map_" + std::to_string(s.options.start_utime) + ".bt");
}

Sensing::~Sensing() = default;

const avoid::OccupancyMap* Sensing::avoidance_map() const { return impl_->avd ? &impl_->avd->map() : nullptr; }

void Sensing::AddTo(LockstepScheduler& scheduler, int64_t step_us) {
  Impl& s = *impl_;
  // Camera periods on the physics grid (5 Hz -> 200 ms).
  auto period = [&](double rate_hz) {
    return std::max<int64_t>(step_us, static_cast<int64_t>(std::lround(1e6 / rate_hz / step_us)) * step_us);
  };
  auto add = [&](const std::string& name, VisionWorker& worker, VisionTiming timing) {
    if (name == "CAM" || name == "STITCH") s.camera_problem[name] = [c = s.rig.survey] { return c->problem(); };
    if (name == "TRK") s.camera_problem[name] = [c = s.rig.tracking] { return c->problem(); };
    timing.latency_us = s.latency_us.at(name);
    auto outbox = std::make_shared<Outbox>();
    scheduler.AddVisionWorker(name, timing,
                              {[&worker](int64_t t) { worker.BeginFrame(t); }, [&worker, outbox] { worker.Work(*outbox); },
                               [&worker, outbox] { outbox->ApplyTo(worker.board()); }});
  };
  if (s.cam) add("CAM", *s.cam, {period(s.rig.survey->info().rate_hz), 0, 0, true, 1'000'000, s.rig.survey->info().name});
  // The stitcher takes every capture waiting (none is dropped); its map at landing takes seconds.
  if (s.stitch) add("STITCH", *s.stitch, {100'000, 0, 0, false, 120'000'000, s.rig.survey->info().name});
  if (s.trk) add("TRK", *s.trk, {period(s.rig.tracking->info().rate_hz), 0, 0, true, 1'000'000, s.rig.tracking->info().name});
  if (s.mdepth) add("MDEPTH", *s.mdepth, {period(s.mdepth->rate_hz()), 0, 0, true, 1'000'000, s.mdepth->camera()});
  if (s.avd) add("AVD", *s.avd, {period(impl_->avd_rate_hz), 0, 0, true, 1'000'000, ""});
  // A pair with the dot projector exposes in turn for its algorithms (active stereo lit, the
  // odometry and the obstacles dark); a pair without one gives each of them every frame.
  std::vector<hal::StereoCamera*> pairs = s.rig.stereo_pairs;
  for (hal::StereoCamera* p : {s.rig.active_stereo, s.rig.odometry, s.rig.obstacles, s.rig.wires})
    if (p && std::find(pairs.begin(), pairs.end(), p) == pairs.end()) pairs.push_back(p);
  for (hal::StereoCamera* pair : pairs) {
    std::vector<std::pair<std::string, VisionWorker*>> on_pair;
    if (s.active_stereo && s.rig.active_stereo == pair) on_pair.emplace_back("ASTEREO", s.active_stereo.get());
    if (s.vo && s.rig.odometry == pair) on_pair.emplace_back("VO", s.vo.get());
    if (s.stereo && s.rig.obstacles == pair) on_pair.emplace_back("STEREO", s.stereo.get());
    if (s.wires && s.rig.wires == pair) on_pair.emplace_back("WIRES", s.wires.get());
    const hal::CameraInfo& left = pair->left();
    const int64_t frame = period(left.rate_hz);
    const bool in_turn = s.active_stereo && s.rig.active_stereo == pair;
    const int64_t each = in_turn ? frame * static_cast<int64_t>(on_pair.size()) : frame;
    for (std::size_t i = 0; i < on_pair.size(); ++i) {
      s.camera_problem[on_pair[i].first] = [pair] { return pair->problem(); };
      add(on_pair[i].first, *on_pair[i].second, {each, in_turn ? frame * static_cast<int64_t>(i) : 0, 0, true, 1'000'000, left.name});
    }
  }
}

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
  for (SensingWorker& w : report.workers) {
    ChooseRate(utime, w, scheduler);
    // A camera that stopped, stalled, ended or gives garbage: its workers have nothing to work on.
    if (const auto c = s.camera_problem.find(w.name); c != s.camera_problem.end())
      if (const std::string problem = c->second(); !problem.empty()) {
        w.healthy = false;
        w.reason = "camera " + w.rig + ": " + problem;
      }
  }
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
                            {"capture_p50_ms", w.capture_p50_ms},
                            {"perception_p50_ms", w.compute_p50_ms - w.capture_p50_ms},
                            {"results", w.results},
                            {"dropped", w.dropped},
                            {"healthy", w.healthy},
                            {"reason", w.reason}});
  }
  return j.dump(2) + "\n";
}

std::map<std::string, int64_t> Sensing::ParameterVersions() const {
  const Impl& s = *impl_;
  std::map<std::string, int64_t> v;
  const std::pair<const char*, const VisionWorker*> workers[] = {
      {"CAM", s.cam.get()},         {"STITCH", s.stitch.get()}, {"TRK", s.trk.get()},
      {"MDEPTH", s.mdepth.get()},   {"STEREO", s.stereo.get()}, {"WIRES", s.wires.get()},
      {"ASTEREO", s.active_stereo.get()}, {"VO", s.vo.get()},   {"AVD", s.avd.get()}};
  for (const auto& [name, w] : workers)
    if (w) v[name] = w->params_version();
  return v;
}

double Sensing::ObstacleMargin() const { return impl_->stereo ? impl_->stereo->safety_margin_m() : -1.0; }
double Sensing::PlannerMargin() const { return impl_->avd ? impl_->avd->params().margin_m : -1.0; }

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

}  // namespace uav::runtime
