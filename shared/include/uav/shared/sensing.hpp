#pragma once
// The health of the vehicle's perception workers as plain data: what the vehicle publishes
// (sensing_t, 1 Hz) and the GCS's sensing panel shows. Decoded once, here.
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/signals.hpp"

namespace uav {

// One perception worker (a thread with its camera or pair and its algorithm).
struct SensingWorker {
  std::string name;                  // "STEREO", "WIRES", "VO", "ASTEREO", "TRK", "MDEPTH", "CAM", "STITCH"
  std::string rig;                   // the camera or stereo pair it runs on
  double camera_rate_hz = 0.0;       // frames its camera gives per second (0: fed by another worker's queue)
  double configured_rate_hz = 0.0;   // frames it is offered: the camera's, or lower where the CPU cannot hold it
  double rate_hz = 0.0;              // results made visible per second, over the last 2 s
  double latency_p50_ms = 0.0;       // capture to visible, over the last 64 results
  double latency_p99_ms = 0.0;
  double compute_p50_ms = 0.0;       // wall-clock time of the work alone, its camera's capture included
  double capture_p50_ms = 0.0;       // of it, the capture: rendering in the simulator, decoding a recording
  int64_t results = 0;               // since start
  int64_t dropped = 0;               // frames the camera gave while the worker was busy
  bool healthy = true;
  std::string reason;                // why not healthy, or why the rate was lowered ("" : neither)
};

struct SensingReport {
  int64_t utime = 0;                    // [us] vehicle clock
  bool measured_latency = false;        // true: latencies are measured compute; false: the vehicle file's
  double control_period_p50_ms = 0.0;   // wall-clock period of the control loop (nominal 20 ms)
  double control_period_p99_ms = 0.0;
  double control_period_max_ms = 0.0;
  std::vector<SensingWorker> workers;
};

// Its signals (workers, unhealthy, drops and the control period): group "SENSING".
template <>
struct ReportSignals<SensingReport> {
  static constexpr std::string_view kGroup = "SENSING";
  static const std::vector<Signal<SensingReport>>& Table();
};

}  // namespace uav
