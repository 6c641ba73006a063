// uav-ulion-bench: U-Lion's transitions measured over many closed-loop runs on the simulated
// clock (thesis 2.6.6). Each run draws a steady wind of 0-5 m/s from any direction with light
// turbulence, and a plant whose mass, thrust and aerodynamic coefficients differ from the
// vehicle file by up to +-15 %; it hovers, transitions onto the wing, cruises, transitions back
// and hovers. The same runs are flown with PX4's tail-sitter schedule (a 5 s pitch ramp,
// complete past 63 degrees at the transition airspeed) for comparison. Prints a JSON report;
// --plot draws one calm-air transition each way (pitch, airspeed, altitude against time).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/simflight/tailsitter_flight.hpp"
#include "uav/airframe/tailsitter_aero.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/process_memory.hpp"
#include "uav/shared/text_file.hpp"

namespace {

using uav::simflight::TailSitterFlight;
using uav::control::TailSitterMode;
using uav::control::TransitionSchedule;

// The targets: front <= 4 s to >= 10 m/s with altitude in -1/+2 m; back <= 3 s, +-2 m.
constexpr double kFrontTime = 4.0, kFrontLoss = 1.0, kFrontGain = 2.0, kBackTime = 3.0, kBackBand = 2.0;
constexpr double kHoverAltitude = 30.0;

struct Run {
  bool front_done = false, back_done = false, aborted = false, crashed = false;
  double front_s = 0, front_loss = 0, front_gain = 0, front_airspeed = 0;
  double back_s = 0, back_loss = 0, back_gain = 0;
  double wind = 0, mass = 1, thrust = 1, aero = 1;
  bool FrontMeets() const {
    return front_done && front_s <= kFrontTime && front_airspeed >= 10.0 && front_loss <= kFrontLoss && front_gain <= kFrontGain;
  }
  bool BackMeets() const { return back_done && back_s <= kBackTime && back_loss <= kBackBand && back_gain <= kBackBand; }
};

// One transition from the present state until the controller reaches `to`, at most 15 s.
void FlyTransition(TailSitterFlight& f, bool to_wing, const uav::control::TailSitterSetpoint& sp, Run& r) {
  const double h0 = f.altitude(), t0 = f.time();
  double lo = 0, hi = 0, fastest = 0;
  const std::string refused = f.StartTransition(to_wing);
  if (!refused.empty()) throw std::runtime_error("transition refused: " + refused);
  const TailSitterMode to = to_wing ? TailSitterMode::kCruise : TailSitterMode::kHover;
  const bool done = f.Fly(sp, 15.0, [&] {
    lo = std::min(lo, f.altitude() - h0);
    hi = std::max(hi, f.altitude() - h0);
    fastest = std::max(fastest, f.airspeed());
    if (f.controller().mode() == TailSitterMode::kTransitionToHover && to_wing) r.aborted = true;
    return f.controller().mode() == to || f.altitude() <= 0.0;
  });
  if (f.altitude() <= 0.0) r.crashed = true;
  if (to_wing) {
    r.front_done = done && !r.aborted && !r.crashed;
    r.front_s = f.time() - t0, r.front_loss = std::max(0.0, -lo), r.front_gain = hi, r.front_airspeed = fastest;
    return;
  }
  r.back_done = done && !r.crashed;
  r.back_s = f.time() - t0;
  // The altitude band holds through the hover's braking after the switch, too.
  f.Fly(sp, 4.0, [&] {
    lo = std::min(lo, f.altitude() - h0);
    hi = std::max(hi, f.altitude() - h0);
    return false;
  });
  r.back_loss = std::max(0.0, -lo), r.back_gain = hi;
}

Run FlyOne(const uav::ParameterSet& vehicle, uint64_t seed, bool vary, TransitionSchedule schedule,
           std::vector<uav::simflight::TailSitterSample>* trace) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Run r;
  uav::ParameterSet p = vehicle;
  uav::simflight::TailSitterVariation var;
  if (vary) {
    r.wind = 2.5 + 2.5 * u(rng);
    r.mass = 1 + 0.15 * u(rng), r.thrust = 1 + 0.15 * u(rng), r.aero = 1 + 0.15 * u(rng);
    p = p.With("wind_speed", r.wind).With("wind_direction", M_PI * u(rng)).With("wind_turbulence", 0.15)
            .With("wind_gust", 0.0).With("sim_seed", static_cast<double>(seed % 1000000));
    var.mass_scale = r.mass, var.thrust_scale = r.thrust, var.aero_scale = r.aero;
  } else {
    p = p.With("wind_speed", 0.0);
  }
  TailSitterFlight f(p, var, schedule);
  uav::control::TailSitterSetpoint sp;
  sp.p_N = {0, 0, -kHoverAltitude};
  f.PlaceInHover(sp.p_N, 0.0);
  f.Fly(sp, 6.0);  // settle (and weathervane)
  const Eigen::Vector3d belly = f.truth().q_NB * Eigen::Vector3d::UnitZ();
  sp.heading = std::atan2(belly.y(), belly.x());  // cruise on along the transition's course
  FlyTransition(f, true, sp, r);
  if (r.front_done) {
    f.Fly(sp, 6.0);
    FlyTransition(f, false, sp, r);
  }
  if (trace) *trace = f.samples();
  return r;
}

double Percentile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  const double at = q * (v.size() - 1);
  const std::size_t i = static_cast<std::size_t>(at);
  return i + 1 < v.size() ? v[i] + (at - i) * (v[i + 1] - v[i]) : v.back();
}

nlohmann::json Summarise(const std::vector<Run>& runs) {
  std::vector<double> fs, fl, fg, bs, bl, bg;
  int front_ok = 0, back_ok = 0, front_done = 0, back_done = 0, aborted = 0, crashed = 0;
  for (const Run& r : runs) {
    front_ok += r.FrontMeets(), back_ok += r.BackMeets(), aborted += r.aborted, crashed += r.crashed;
    if (r.front_done) ++front_done, fs.push_back(r.front_s), fl.push_back(r.front_loss), fg.push_back(r.front_gain);
    if (r.back_done) ++back_done, bs.push_back(r.back_s), bl.push_back(std::max(r.back_loss, r.back_gain)), bg.push_back(r.back_gain);
  }
  const double n = std::max<std::size_t>(1, runs.size());
  auto r2 = [](double x) { return std::round(x * 100) / 100; };
  return {{"runs", runs.size()},
          {"front", {{"completed", front_done}, {"aborted", aborted}, {"meets_target_pct", r2(100.0 * front_ok / n)},
                     {"time_s_p50", r2(Percentile(fs, 0.5))}, {"time_s_p95", r2(Percentile(fs, 0.95))},
                     {"altitude_loss_m_p95", r2(Percentile(fl, 0.95))}, {"altitude_gain_m_p95", r2(Percentile(fg, 0.95))}}},
          {"back", {{"completed", back_done}, {"meets_target_pct", r2(100.0 * back_ok / n)},
                    {"time_s_p50", r2(Percentile(bs, 0.5))}, {"time_s_p95", r2(Percentile(bs, 0.95))},
                    {"altitude_deviation_m_p95", r2(Percentile(bl, 0.95))}}},
          {"crashed", crashed}};
}

// Three stacked panels: nose pitch [deg], airspeed [m/s], altitude [m] against time; one line
// per schedule.
void Plot(const std::string& path, const std::vector<std::pair<std::string, std::vector<uav::simflight::TailSitterSample>>>& traces) {
  const int width = 1000, panel = 220;
  cv::Mat canvas(3 * panel + 40, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar colours[] = {cv::Scalar(200, 90, 20), cv::Scalar(40, 40, 210)};
  double t0 = 1e9, t1 = -1e9;
  for (const auto& [name, s] : traces)
    for (const auto& x : s) t0 = std::min(t0, x.t_s), t1 = std::max(t1, x.t_s);
  struct Channel {
    const char* title;
    double (*get)(const uav::simflight::TailSitterSample&);
  };
  const Channel channels[] = {
      {"nose pitch above the horizon [deg]", [](const uav::simflight::TailSitterSample& x) { return x.pitch_deg; }},
      {"airspeed [m/s]", [](const uav::simflight::TailSitterSample& x) { return x.airspeed_mps; }},
      {"altitude [m]", [](const uav::simflight::TailSitterSample& x) { return x.altitude_m; }}};
  for (int c = 0; c < 3; ++c) {
    const cv::Rect box(60, 30 + c * panel, width - 80, panel - 40);
    cv::rectangle(canvas, box, cv::Scalar(190, 190, 190), 1);
    double lo = 1e9, hi = -1e9;
    for (const auto& [name, s] : traces)
      for (const auto& x : s) lo = std::min(lo, channels[c].get(x)), hi = std::max(hi, channels[c].get(x));
    if (hi - lo < 1) lo -= 0.5, hi += 0.5;
    auto at = [&](double t, double v) {
      return cv::Point(box.x + static_cast<int>((t - t0) / (t1 - t0) * box.width),
                       box.y + box.height - static_cast<int>((v - lo) / (hi - lo) * box.height));
    };
    for (std::size_t k = 0; k < traces.size(); ++k) {
      std::vector<cv::Point> pts;
      for (const auto& x : traces[k].second) pts.push_back(at(x.t_s, channels[c].get(x)));
      cv::polylines(canvas, pts, false, colours[k % 2], 2, cv::LINE_AA);
    }
    char label[96];
    std::snprintf(label, sizeof label, "%s   %.1f .. %.1f", channels[c].title, lo, hi);
    cv::putText(canvas, label, {box.x + 6, box.y + 16}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  }
  char axis[128];
  std::snprintf(axis, sizeof axis, "t %.0f .. %.0f s", t0, t1);
  cv::putText(canvas, axis, {width - 180, 3 * panel + 25}, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(60, 60, 60), 1);
  for (std::size_t k = 0; k < traces.size(); ++k)
    cv::putText(canvas, traces[k].first, {70 + 420 * static_cast<int>(k), 20}, cv::FONT_HERSHEY_SIMPLEX, 0.5, colours[k % 2],
                1, cv::LINE_AA);
  std::vector<uchar> png;
  if (!cv::imencode(".png", canvas, png)) throw std::runtime_error("cannot encode the plot");
  uav::WriteFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  CLI::App cli{"uav-ulion-bench: U-Lion's transitions over many closed-loop runs (thesis 2.6.6)"};
  std::string params_path = uav::ResourcePath("vehicles/ulion.params"), json_path, plot_path;
  int runs = 200;
  bool verbose = false;
  std::string trace_path;
  uint64_t seed = 1;
  cli.add_option("--params", params_path, "tail-sitter vehicle file")->capture_default_str();
  cli.add_option("--runs", runs, "Monte-Carlo runs per schedule")->check(CLI::Range(1, 100000))->capture_default_str();
  cli.add_option("--seed", seed, "first run's seed (run i uses seed + i)")->capture_default_str();
  uav::OutputFile(cli.add_option("--json", json_path, "also write the report here"));
  cli.add_flag("--verbose", verbose, "one line per run on stderr");
  cli.add_option("--trace", trace_path, "CSV of the first run with our schedule: time, mode, altitude, airspeed, pitch, ...");
  uav::OutputFile(cli.add_option("--plot", plot_path, "PNG of a calm-air transition each way, ours against PX4's schedule"));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    // Outputs checked before the runs, not after them.
    const uav::ParameterSet vehicle = uav::ParameterSet::LoadFile(params_path, uav::VehicleParameterSchema());
    if (vehicle.Get("vehicle_type") != 1) throw std::runtime_error(params_path + ": vehicle_type is not 1 (a tail-sitter)");
    nlohmann::json report;
    report["vehicle"] = params_path;
    report["targets"] = {{"front", "<= 4 s to >= 10 m/s, altitude -1/+2 m"}, {"back", "<= 3 s, altitude +-2 m"}};
    report["conditions"] = "wind 0-5 m/s any direction, turbulence 15 %, mass, thrust and aerodynamic coefficients +-15 %";
    for (const auto& [name, schedule] : {std::pair{"ours", TransitionSchedule::kLiftLimited},
                                         std::pair{"px4_ramp", TransitionSchedule::kPx4Ramp}}) {
      std::vector<Run> all;
      for (int i = 0; i < runs; ++i) {
        all.push_back(FlyOne(vehicle, seed + i, true, schedule, nullptr));
        const Run& r = all.back();
        if (verbose)
          std::fprintf(stderr,
                       "%s run %d: wind %.1f m/s, mass x%.2f thrust x%.2f aero x%.2f | front %s %.2f s -%.2f/+%.2f m %.1f m/s | "
                       "back %s %.2f s -%.2f/+%.2f m%s\n",
                       name, i, r.wind, r.mass, r.thrust, r.aero, r.front_done ? "done" : (r.aborted ? "aborted" : "failed"),
                       r.front_s, r.front_loss, r.front_gain, r.front_airspeed, r.back_done ? "done" : "failed", r.back_s,
                       r.back_loss, r.back_gain, r.crashed ? " CRASHED" : "");
        if ((i + 1) % 50 == 0) std::fprintf(stderr, "%s: %d/%d runs\n", name, i + 1, runs);
      }
      report[name] = Summarise(all);
    }
    if (!trace_path.empty()) {
      std::vector<uav::simflight::TailSitterSample> trace;
      FlyOne(vehicle, seed, true, TransitionSchedule::kLiftLimited, &trace);
      std::string csv = "t_s,mode,north_m,east_m,altitude_m,airspeed_mps,ground_speed_mps,pitch_deg,pitch_setpoint_deg,alpha_deg,thrust_n,wing_lift_n\n";
      char line[256];
      for (const auto& s : trace) {
        std::snprintf(line, sizeof line, "%.2f,%s,%.2f,%.2f,%.2f,%.2f,%.2f,%.1f,%.1f,%.1f,%.2f,%.2f\n", s.t_s,
                      std::string(uav::Name(s.mode)).c_str(), s.p_N.x(), s.p_N.y(), s.altitude_m, s.airspeed_mps, s.ground_speed_mps,
                      s.pitch_deg, s.pitch_setpoint_deg, s.alpha_deg, s.thrust_n, s.wing_lift_n);
        csv += line;
      }
      uav::WriteFileAtomically(trace_path, csv);
    }
    // Endurance on the battery model: hover against cruise (momentum theory, thesis 2.6).
    const auto params = uav::airframe::TailSitterParams::FromParameters(vehicle);
    uav::airframe::PowerModel power;
    power.mass_kg = params.mass_kg;
    power.disk_area_m2 = M_PI / 4 * params.rotor_diameter_m * params.rotor_diameter_m;
    power.parasite_drag_area_m2 = params.fuselage_axial_m2;
    // Nominal voltage: the mean of full and empty.
    power.battery_wh = vehicle.Get("battery_capacity") * 0.5 * (vehicle.Get("battery_voltage_full") + vehicle.Get("battery_voltage_empty"));
    const uav::airframe::WingAerodynamics wing(params.wing, params.wing_coefficients);
    const auto cruise = uav::airframe::TrimCruise(wing, power, vehicle.Get("ts_cruise_speed"), params.air_density);
    report["endurance"] = {{"battery_wh", power.battery_wh},
                           {"hover_w", std::round(uav::airframe::HoverElectricPower(power, params.air_density))},
                           {"hover_min", std::round(10 * uav::airframe::HoverEnduranceMin(power, params.air_density)) / 10},
                           {"cruise_speed_mps", vehicle.Get("ts_cruise_speed")},
                           {"cruise_w", std::round(cruise.electric_w)},
                           {"cruise_min", std::round(10 * cruise.endurance_min) / 10}};
    if (!plot_path.empty()) {
      std::vector<std::pair<std::string, std::vector<uav::simflight::TailSitterSample>>> traces(2);
      traces[0].first = "ours (lift-limited pitch, 80 % thrust)";
      traces[1].first = "PX4 tail-sitter schedule (5 s ramp)";
      FlyOne(vehicle, seed, false, TransitionSchedule::kLiftLimited, &traces[0].second);
      FlyOne(vehicle, seed, false, TransitionSchedule::kPx4Ramp, &traces[1].second);
      Plot(plot_path, traces);
      report["plot"] = plot_path;
    }
    const std::string text = report.dump(2);
    std::printf("%s\n", text.c_str());
    if (!json_path.empty()) uav::WriteFileAtomically(json_path, text + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-ulion-bench: %s\n", e.what());
    return 1;
  }
  return 0;
}
