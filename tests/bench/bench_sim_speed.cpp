// Headless simulation speed (issue 5 target: >= 200x real time with control and INS, no vision):
// the quadrotor at 500 Hz with its sensors and wind, and the IMU (with the INS), CTL and SVO
// threads in lockstep at 50 Hz, flying a
// takeoff and a square of gotos for the given simulated time, as fast as the threads go.
// Prints a JSON report: simulated seconds, wall seconds, speed-up.
// Usage: bench_sim_speed [SIM_SECONDS] [REPEATS]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/workers.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/process_memory.hpp"
#include "uav/sim/sim_vehicle.hpp"

int main(int argc, char** argv) {
  uav::KeepFreedMemory();
  const double sim_s = argc > 1 ? std::atof(argv[1]) : 600.0;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 3;
  if (!(sim_s > 0) || repeats < 1) {
    std::fprintf(stderr, "usage: bench_sim_speed [SIM_SECONDS > 0] [REPEATS >= 1]\n");
    return 2;
  }
  const auto params = uav::ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", uav::VehicleParameterSchema());
  std::vector<double> wall;
  for (int r = 0; r < repeats; ++r) {
    uav::sim::SimVehicle vehicle(params, {1.2966, 103.7764, 15.0}, 0);
    uav::runtime::Blackboard board;
    uav::runtime::ImuWorker imu(vehicle, board, uav::nav::InsParams::FromParameters(params), {1.2966, 103.7764, 15.0});
    uav::runtime::ControlWorker ctl(uav::control::TaskParams::FromParameters(params),
                                uav::control::ControllerParams::FromParameters(params),
                                uav::control::FailsafeParams::FromParameters(params), 0.02, board);
    uav::runtime::ServoWorker svo(vehicle, board, params.Get("rotor_input_idle"),
                              uav::hal::VehicleParams::FromParameters(params).attitude_mode);
    const char* plan[] = {"arm", "takeoff 10", "goto 30 0 10", "goto 30 30 10", "goto 0 30 10", "goto 0 0 10"};
    int next = 0;
    int64_t seq = 0;
    uav::runtime::LockstepScheduler s({0, 2000, 0.0, static_cast<int64_t>(sim_s * 1e6)});
    s.AddWorker("IMU", 0, 20000, [&](int64_t t) { imu.Tick(t); });
    s.AddWorker("CTL", 1, 20000, [&](int64_t t) { ctl.Tick(t); });
    s.AddWorker("SVO", 2, 20000, [&](int64_t t) {
      svo.Tick(t);
      // Next command of the square every 20 s, round and round.
      if (t % 20000000 == 0) {
        board.commands.Push({"bench", ++seq, *uav::ParseCommand(plan[next]).command});
        next = next + 1 < 6 ? next + 1 : 2;
      }
      board.task_reports.TakeAll();
      board.status.TakeAll();
    });
    const auto t0 = std::chrono::steady_clock::now();
    s.Run([&](int64_t dt) { vehicle.Step(dt); });
    wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  std::sort(wall.begin(), wall.end());
  const double median = wall[wall.size() / 2];
  std::printf("{\"simulated_s\": %.1f, \"repeats\": %d, \"wall_s_median\": %.3f, \"wall_s_min\": %.3f, "
              "\"speedup_median\": %.1f}\n", sim_s, repeats, median, wall.front(), sim_s / median);
  return 0;
}
