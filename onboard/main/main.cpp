// uav-onboard: the flight stack's five threads (thesis Table 2.1) and its vision workers, on the
// simulator (--sim) or on the bench with recorded or live cameras (--rig).
#include <algorithm>
#include <cmath>
#include <csignal>
#include <functional>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include <CLI/CLI.hpp>

#include "uav/runtime/bench_flight.hpp"
#include "uav/runtime/link_worker.hpp"
#include "uav/runtime/rig_file.hpp"
#include "uav/runtime/mission_store.hpp"
#include "uav/waypoints/stored_paths.hpp"
#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/sensing.hpp"
#include "uav/simflight/sim_flight.hpp"
#include "uav/runtime/workers.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/process_memory.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/shared/time.hpp"
#include "uav/sim/sim_vehicle.hpp"
#include "uav/world/scene.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

uav::GeodeticPoint ParseHome(const std::string& text) {
  const auto v = uav::ParseDecimalList(text, 3);
  if (!v)
    throw std::invalid_argument("--home must be LAT,LON,ALT (degrees, degrees, metres), got '" +
                                text + "'");
  uav::GeodeticPoint g{(*v)[0], (*v)[1], (*v)[2]};
  uav::ValidateGeodetic(g);
  return g;
}

double ParseSpeed(const std::string& text) {
  if (text == "max") return 0.0;
  const std::optional<double> v = uav::ParseDecimal(text);
  if (!v || !(*v >= 0.1 && *v <= 1000.0))
    throw std::invalid_argument("--speed must be 'max' or a factor in [0.1, 1000], got '" + text + "'");
  return *v;
}

struct CommandLine {
  bool sim = false;
  std::string vehicle_id = "UAV1";
  std::string lcm_url = uav::kDefaultLcmUrl;
  std::string speed_text = "1";
  std::string log_dir;
  std::string home_text = "1.2966,103.7764,15";  // NUS, Singapore: where the thesis flew
  std::string params_path = uav::ResourcePath("vehicles/x650.params");
  std::string paths_dir = uav::waypoints::kStoredPathsDir;
  double duration_s = 0.0;
  std::string scene_path;
  std::vector<std::string> param_overrides;
  std::string key_path;
  bool insecure = false;
  bool list_params = false;
  std::string benchmark_path;
  std::string rig_path;
  std::string mavlink;
  int mavlink_sysid = 1;
  std::string mavlink_video = "127.0.0.1:5600";
};

void DeclareOptions(CLI::App& cli, CommandLine& o) {
  cli.add_flag("--list-params", o.list_params,
               "print every vehicle parameter the program declares (name, default, unit, limits, description) and exit");
  auto* sim = cli.add_flag("--sim", o.sim, "run against the simulated vehicle the --params file describes (the X650 quadrotor, thesis 2.4; U-Lion, 2.6)");
  cli.add_option("--rig", o.rig_path,
                 "bench mode: run the vision workers on the recorded or live cameras this rig file describes "
                 "(docs/vehicle/rigs.md), with control off; the pose from the recording's ground truth or the odometry")
      ->check(CLI::ExistingFile)
      ->excludes(sim);
  cli.add_option("--vehicle-id", o.vehicle_id, "vehicle id; channels are <ID>/<TOPIC>")->capture_default_str();
  cli.add_option("--lcm-url", o.lcm_url, "LCM URL")->capture_default_str();
  cli.add_option("--speed", o.speed_text, "vehicle-clock seconds per wall second, or 'max' (a recording plays as fast as the workers go, no frame dropped)")->capture_default_str();
  cli.add_option("--log-dir", o.log_dir, "write the CSV flight log into this directory");
  cli.add_option("--home", o.home_text, "home position LAT,LON,ALT (deg, deg, m WGS84)")->capture_default_str();
  cli.add_option("--params", o.params_path, "vehicle parameter file")->capture_default_str();
  cli.add_option("--param", o.param_overrides,
                 "override a vehicle-file parameter, NAME=VALUE, checked against its limits (repeatable; e.g. "
                 "wind_speed=5)");
  cli.add_option("--paths", o.paths_dir, "directory of stored paths for 'track N'")->capture_default_str();
  cli.add_option("--scene", o.scene_path,
                 "simulated world (resources/scenes/*.scene.json): renders the scene's cameras and runs the vision "
                 "workers the vehicle file puts on them; the downward camera streams to the GCS and records survey "
                 "captures into LOG_DIR/captures_<utime>");
  auto* key_option = cli.add_option(
      "--key", o.key_path,
      "signing key (uav-keygen FILE, mode 0600): only commands, missions, targets, file requests and GCS "
      "heartbeats signed with it are executed; the newest accepted timestamp is kept in FILE.last");
  cli.add_flag("--insecure", o.insecure, "no signing key: execute unsigned messages from anyone on the network")
      ->excludes(key_option);
  cli.add_option("--mavlink", o.mavlink,
                 "also speak MAVLink 2 as a PX4 vehicle to QGroundControl or Mission Planner: udp:HOST:PORT "
                 "(udp:127.0.0.1:14550), udpin:[HOST:]PORT or serial:DEVICE[:BAUD]. Frames are signed with --key "
                 "(make it with uav-keygen --passphrase and type the passphrase into the GCS); unsigned ones are "
                 "refused unless --insecure (docs/user-guide/mavlink.md)");
  cli.add_option("--mavlink-sysid", o.mavlink_sysid, "MAVLink system id of this vehicle")
      ->check(CLI::Range(1, 254))
      ->capture_default_str();
  cli.add_option("--mavlink-video", o.mavlink_video,
                 "HOST:PORT for the video camera's RTP/H.264 stream (QGroundControl's default UDP 5600), 'off' for none")
      ->capture_default_str();
  cli.add_option("--sensing-benchmark", o.benchmark_path,
                 "at exit, write the sensing benchmark (JSON: each vision worker's rate against its camera's, latency, "
                 "drops; the work per frame and, of it, the camera's capture (rendering, decoding); the control loop's period; CPU "
                 "use) to this file, '-' for stdout (needs --scene or --rig)");
  cli.add_option("--duration", o.duration_s, "stop after this many simulated seconds (0: run until signalled)")
      ->check(CLI::Range(0.0, 1e7));
}

// Throws std::invalid_argument naming what is wrong with the command line.
void Check(const CommandLine& o) {
  if (!o.sim && o.rig_path.empty())
    throw std::invalid_argument("no flight controller backend in this build: use --sim (the simulator) or --rig FILE (the bench: "
                                "recorded or live cameras, control off)");
  if (!o.scene_path.empty() && !o.sim) throw std::invalid_argument("--scene is the simulator's world: it needs --sim");
  if (!o.benchmark_path.empty() && o.scene_path.empty() && o.rig_path.empty())
    throw std::invalid_argument("--sensing-benchmark measures the vision workers: give a --scene with cameras or a --rig");
  if (!uav::IsValidVehicleId(o.vehicle_id))
    throw std::invalid_argument("--vehicle-id must be 1-32 characters of [A-Za-z0-9_-], got '" + o.vehicle_id + "'");
  if (o.key_path.empty() && !o.insecure)
    throw std::invalid_argument("give --key FILE (make one with uav-keygen FILE) or, to accept unsigned "
                                "commands from anyone on the network, --insecure");
}

uav::ParameterSet LoadParameters(const CommandLine& o) {
  uav::ParameterSet params = uav::ParameterSet::LoadFile(o.params_path, uav::VehicleParameterSchema());
  for (const auto& assignment : o.param_overrides) params = params.WithAssignment(assignment);
  return params;
}

uav::waypoints::VehicleLimits MissionLimits(const uav::ParameterSet& p) {
  return uav::waypoints::VehicleLimits::Of([&p](const std::string& name) { return p.Get(name); });
}

// Blocks SIGINT and SIGTERM in every thread; a dedicated thread waits for them and stops `scheduler`.
sigset_t BlockTerminationSignals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  return signals;
}

void StopOnSignal(sigset_t signals, uav::runtime::LockstepScheduler& scheduler) {
  std::thread([signals, &scheduler] {
    int sig = 0;
    sigwait(&signals, &sig);
    scheduler.Stop();
  }).detach();
}

// What runs the same on every vehicle: the log (DLG) and the link (CMM) threads on the vehicle's
// blackboard and clock, the run until its end or a signal, the sensing benchmark and the exit
// line. `vehicle` says what it is for the start line; `run` drives the clock.
struct Vehicle {
  std::string description;  // "simulated X650 quadrotor", "bench (recorded or live sensors)"
  uav::runtime::Blackboard& board;
  uav::runtime::LockstepScheduler& scheduler;
  uav::runtime::Sensing* sensing;
  std::vector<uav::runtime::LogColumn> log_columns;
  std::function<void()> run;
};

int RunWithLink(const CommandLine& o, const uav::ParameterSet& params, const uav::GeodeticPoint& home, int64_t start,
                double speed, uav::runtime::MissionStore& missions, const Vehicle& v, sigset_t signals) {
  const auto vehicle_params = uav::hal::VehicleParams::FromParameters(params);
  auto limits_of = [](const uav::ParameterSet& p) {
    return uav::waypoints::VehicleLimits::Of([&p](const std::string& name) { return p.Get(name); });
  };
  // Uploads are checked against the parameters as they are now (a lowered fs_fence_alt counts).
  missions.SetLimitsSource([&board = v.board, &params, limits_of] {
    const auto live = board.Snapshot().params;
    return limits_of(live ? *live : params);
  });
  std::unique_ptr<uav::runtime::FlightLog> log;
  if (!o.log_dir.empty())
    log = std::make_unique<uav::runtime::FlightLog>(o.log_dir, start, vehicle_params.attitude_mode, home, v.log_columns);
  const std::string log_path = log ? log->path() : "";
  uav::runtime::LogWorker dlg(std::move(log), v.board);
  std::unique_ptr<uav::runtime::EventLog> events;
  if (!o.log_dir.empty()) events = std::make_unique<uav::runtime::EventLog>(o.log_dir, start);
  const std::string events_path = events ? events->path() : "";
  auto link_params = uav::runtime::LinkParams::FromParameters(params, vehicle_params.attitude_mode);
  link_params.sim_rate_asked = speed;
  if (!o.key_path.empty()) {
    link_params.signing_key = uav::SigningKey::LoadFile(o.key_path);
    link_params.signing_state_file = o.key_path + ".last";
  }
  if (!o.mavlink.empty()) {
    uav::runtime::MavlinkParams m;
    m.endpoint = o.mavlink;
    m.system_id = o.mavlink_sysid;
    m.insecure = o.insecure;
    if (o.mavlink_video == "off") {
      m.video_host.clear();
    } else {
      const std::size_t colon = o.mavlink_video.rfind(':');
      if (colon == std::string::npos) throw std::invalid_argument("--mavlink-video: expected HOST:PORT or off, got '" + o.mavlink_video + "'");
      m.video_host = o.mavlink_video.substr(0, colon);
      m.video_port = std::stoi(o.mavlink_video.substr(colon + 1));
    }
    link_params.mavlink = m;
  }
  uav::runtime::LinkWorker cmm(o.vehicle_id, o.lcm_url, link_params, v.board, missions, std::move(events));
  uav::runtime::LockstepScheduler& scheduler = v.scheduler;
  constexpr int64_t kPeriodUs = 20'000;  // 50 Hz, as the control threads (thesis 2.3.2)
  scheduler.AddWorker("DLG", 3, kPeriodUs, [&](int64_t t) { dlg.Tick(t); });
  scheduler.AddWorker("CMM", 3, kPeriodUs, [&](int64_t t) { cmm.Tick(t); });
  StopOnSignal(signals, scheduler);

  const std::string signing = link_params.signing_key ? "signed with key " + link_params.signing_key->Id()
                                                      : "INSECURE (unsigned commands from anyone are executed)";
  const std::string mavlink = o.mavlink.empty() ? "" : ", MAVLink " + o.mavlink;
  std::printf("uav-onboard: vehicle %s, %s, speed %s, LCM %s%s, %s%s%s%s%s\n", o.vehicle_id.c_str(), v.description.c_str(),
              o.speed_text.c_str(), o.lcm_url.c_str(), mavlink.c_str(), signing.c_str(), log_path.empty() ? "" : ", log ", log_path.c_str(),
              events_path.empty() ? "" : ", events ", events_path.c_str());
  std::fflush(stdout);
  v.run();
  const double vehicle_s = (scheduler.now() - start) * 1e-6;
  if (v.sensing && !o.benchmark_path.empty()) {
    const std::string json = v.sensing->BenchmarkJson(scheduler, speed, vehicle_s, (uav::WallTimeMicros() - start) * 1e-6);
    if (o.benchmark_path == "-") std::fputs(json.c_str(), stdout);
    else uav::WriteFileAtomically(o.benchmark_path, json);
  }
  std::printf("uav-onboard: stopped after %.1f s %s%s\n", vehicle_s, o.sim ? "simulated" : "on the vehicle clock",
              v.sensing ? v.sensing->Summary().c_str() : "");
  return 0;
}

// The five threads of Table 2.1 (the simulated flight's IMU, CTL and SVO, the log and the link)
// and the scene's sensing, until the duration has passed or a signal came.
int Fly(const CommandLine& o) {
  const double speed = ParseSpeed(o.speed_text);
  const uav::GeodeticPoint home = ParseHome(o.home_text);
  const uav::ParameterSet params = LoadParameters(o);
  const sigset_t signals = BlockTerminationSignals();
  const int64_t start = uav::WallTimeMicros();
  std::unique_ptr<uav::world::Scene> scene;
  if (!o.scene_path.empty()) scene = std::make_unique<uav::world::Scene>(uav::world::Scene::LoadFile(o.scene_path));
  const bool tail_sitter = params.Get("vehicle_type") == static_cast<double>(uav::VehicleType::kTailSitter);
  uav::runtime::MissionStore missions(o.paths_dir, home, MissionLimits(params));
  uav::simflight::SimFlight flight(params, {home, start, speed, o.duration_s, scene.get(), o.log_dir, &missions});
  flight.control().ServeParameters(params);
  const Vehicle v{std::string("simulated ") + (tail_sitter ? "U-Lion tail-sitter" : "X650 quadrotor"), flight.board(),
                  flight.scheduler(), flight.sensing(), flight.LogColumns(), [&flight] { flight.Run(); }};
  return RunWithLink(o, params, home, start, speed, missions, v, signals);
}

// The runtime on the rig file's recorded or live cameras, with no actuators (bench_flight.hpp).
int Bench(const CommandLine& o) {
  const double speed = ParseSpeed(o.speed_text);
  const uav::GeodeticPoint home = ParseHome(o.home_text);
  const uav::ParameterSet params = LoadParameters(o);
  const int64_t start = uav::WallTimeMicros();
  const std::unique_ptr<uav::runtime::RigFile> rig = uav::runtime::RigFile::Load(o.rig_path, start);
  const sigset_t signals = BlockTerminationSignals();
  uav::runtime::MissionStore missions(o.paths_dir, home, MissionLimits(params));
  uav::runtime::BenchFlight bench(params, *rig, {home, start, speed, o.duration_s, o.log_dir});
  std::printf("uav-onboard: rig %s\n%s", o.rig_path.c_str(), rig->Describe().c_str());
  const Vehicle v{std::string("bench: control off, ") + bench.PoseDescription(), bench.board(), bench.scheduler(),
                  &bench.sensing(), {}, [&bench] { bench.Run(); }};
  return RunWithLink(o, params, home, start, speed, missions, v, signals);
}

}  // namespace

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  CLI::App cli{"uav-onboard: onboard flight stack (threads IMU, CTL, SVO, DLG, CMM, and the vision workers)"};
  CommandLine options;
  DeclareOptions(cli, options);
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (options.list_params) {
    std::cout << uav::DescribeSchema(uav::VehicleParameterSchema());
    return 0;
  }
  try {
    Check(options);
    return options.sim ? Fly(options) : Bench(options);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-onboard: %s\n", e.what());
    return 2;
  }
}
