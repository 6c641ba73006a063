#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <vector>

#include "uav/app/lockstep_scheduler.hpp"

namespace uav::app {
namespace {

TEST(LockstepScheduler, StagesRunInOrderAtTheirPeriods) {
  LockstepScheduler s({0, 1000, 0.0, 100000});
  std::mutex m;
  std::vector<std::string> trace;
  auto rec = [&](const char* n) {
    return [&, n](int64_t t) {
      std::lock_guard<std::mutex> l(m);
      trace.push_back(std::string(n) + "@" + std::to_string(t));
    };
  };
  s.AddWorker("C", 2, 20000, rec("C"));
  s.AddWorker("A", 0, 20000, rec("A"));
  s.AddWorker("B", 1, 40000, rec("B"));
  int physics_steps = 0;
  s.Run([&](int64_t dt) { ++physics_steps; });
  EXPECT_EQ(physics_steps, 100);
  EXPECT_EQ(s.now(), 100000);
  const std::vector<std::string> expected = {"A@0",     "B@0",     "C@0",     "A@20000", "C@20000",
                                             "A@40000", "B@40000", "C@40000", "A@60000", "C@60000",
                                             "A@80000", "B@80000", "C@80000"};
  EXPECT_EQ(trace, expected);
}

// Two users of one camera on alternate frames: the second starts one frame later.
TEST(LockstepScheduler, APhaseDelaysAWorkerWithinItsPeriod) {
  LockstepScheduler s({0, 1000, 0.0, 80000});
  std::vector<int64_t> lit, dark;
  s.AddWorker("LIT", 2, 40000, [&](int64_t t) { lit.push_back(t); });
  s.AddWorker("DARK", 2, 40000, [&](int64_t t) { dark.push_back(t); }, 20000);
  s.Run([](int64_t) {});
  EXPECT_EQ(lit, (std::vector<int64_t>{0, 40000}));
  EXPECT_EQ(dark, (std::vector<int64_t>{20000, 60000}));
  EXPECT_THROW(s.AddWorker("W", 0, 40000, [](int64_t) {}, 40000), std::invalid_argument);
  EXPECT_THROW(s.AddWorker("W", 0, 40000, [](int64_t) {}, 500), std::invalid_argument);
}

TEST(LockstepScheduler, PacesToWallClockTimesSpeed) {
  LockstepScheduler s({0, 2000, 4.0, 400000});  // 0.4 s simulated at 4x: 0.1 s wall
  s.AddWorker("W", 0, 20000, [](int64_t) {});
  const auto t0 = std::chrono::steady_clock::now();
  s.Run([](int64_t) {});
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  EXPECT_GE(wall, 0.099);
}

TEST(LockstepScheduler, RejectsPeriodsThatAreNotStepMultiples) {
  LockstepScheduler s({0, 2000, 0.0, 0});
  EXPECT_THROW(s.AddWorker("W", 0, 3000, [](int64_t) {}), std::invalid_argument);
  EXPECT_THROW(s.AddWorker("W", 0, 0, [](int64_t) {}), std::invalid_argument);
}

TEST(LockstepScheduler, StopFromAWorkerEndsTheRun) {
  LockstepScheduler s({0, 2000, 0.0, 0});
  s.AddWorker("W", 0, 20000, [&](int64_t t) {
    if (t >= 200000) s.Stop();
  });
  s.Run([](int64_t) {});
  EXPECT_EQ(s.now(), 202000);
}

}  // namespace
}  // namespace uav::app
