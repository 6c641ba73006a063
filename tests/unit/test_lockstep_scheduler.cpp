#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "uav/runtime/lockstep_scheduler.hpp"
#include "uav/runtime/vision_worker.hpp"

namespace uav::runtime {
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

// A vision result is visible exactly its latency after its frame, never before, whatever the
// work's wall time: the control worker reads the previous result until then.
TEST(LockstepScheduler, AVisionResultIsVisibleAtCapturePlusLatency) {
  LockstepScheduler s({0, 2000, 0.0, 400000});
  std::atomic<int64_t> shared{-1};  // the newest visible result: its frame's time
  int64_t begun = -1, worked = -1;
  std::vector<std::pair<int64_t, int64_t>> seen;  // (control tick, result it saw) when it changed
  s.AddWorker("CTL", 0, 20000, [&](int64_t t) {
    if (seen.empty() || seen.back().second != shared.load()) seen.emplace_back(t, shared.load());
  });
  s.AddVisionWorker("STEREO", {100000, 0, 60000, true, 1'000'000, "pair"},
                    {[&](int64_t t) { begun = t; }, [&] { worked = begun; },
                     [&] { shared.store(worked); }});
  s.Run([](int64_t) {});
  const std::vector<std::pair<int64_t, int64_t>> expected = {{0, -1}, {60000, 0}, {160000, 100000}, {260000, 200000}, {360000, 300000}};
  EXPECT_EQ(seen, expected);
  const auto health = s.VisionHealth();
  ASSERT_EQ(health.size(), 1u);
  EXPECT_EQ(health[0].results, 4);
  EXPECT_EQ(health[0].dropped, 0);
  EXPECT_DOUBLE_EQ(health[0].latency_p50_ms, 60.0);
  EXPECT_TRUE(health[0].healthy) << health[0].reason;
}

// A worker busy longer than its frame period: the frames that come meanwhile are dropped and
// counted (every third is processed at 50 ms latency and a 20 ms period), deterministically.
TEST(LockstepScheduler, FramesThatComeWhileTheWorkerIsBusyAreDroppedAndCounted) {
  LockstepScheduler s({0, 2000, 0.0, 3'000'000});
  std::vector<int64_t> processed;
  int64_t frame = 0;
  s.AddVisionWorker("VO", {20000, 0, 50000, true, 1'000'000, "pair"},
                    {[&](int64_t t) { frame = t; }, [] {}, [&] { processed.push_back(frame); }});
  s.Run([](int64_t) {});
  ASSERT_GE(processed.size(), 3u);
  EXPECT_EQ(processed[1] - processed[0], 60000);
  const auto health = s.VisionHealth();
  EXPECT_EQ(health[0].results, 50);  // frames 0, 60, ..., 2940 ms
  EXPECT_EQ(health[0].dropped, 100);
  EXPECT_FALSE(health[0].healthy);
  EXPECT_NE(health[0].reason.find("behind: 17.0 of 50.0 Hz, 100 frames dropped"), std::string::npos) << health[0].reason;
}

// A rate lowered on purpose: the worker is offered every third frame of its camera, evenly, and
// the frames it is not asked for are not drops; its configured rate says so.
TEST(LockstepScheduler, ADecimatedWorkerIsOfferedEveryKthFrameWithoutDrops) {
  LockstepScheduler s({0, 2000, 0.0, 600000});
  std::vector<int64_t> frames;
  s.AddVisionWorker("STEREO", {20000, 0, 10000, true, 1'000'000, "pair"},
                    {[&](int64_t t) { frames.push_back(t); }, [] {}, [] {}});
  s.SetDecimation("STEREO", 3);
  EXPECT_THROW(s.SetDecimation("STEREO", 0), std::invalid_argument);
  EXPECT_THROW(s.SetDecimation("VO", 2), std::invalid_argument);
  s.Run([](int64_t) {});
  const std::vector<int64_t> expected = {0, 60000, 120000, 180000, 240000, 300000, 360000, 420000, 480000, 540000};
  EXPECT_EQ(frames, expected);
  const auto health = s.VisionHealth();
  EXPECT_EQ(health[0].dropped, 0);
  EXPECT_DOUBLE_EQ(health[0].camera_rate_hz, 50.0);
  EXPECT_NEAR(health[0].configured_rate_hz, 50.0 / 3, 1e-9);
}

// At real time a slow worker (70 ms a frame at 20 Hz) neither slows the clock nor the control
// loop: control keeps its 20 ms period while the worker drops every other frame.
TEST(LockstepScheduler, ASlowVisionWorkerDoesNotDelayControl) {
  LockstepScheduler s({0, 2000, 1.0, 1'000'000});
  std::atomic<int> control_ticks{0};
  s.AddWorker("CTL", 1, 20000, [&](int64_t) { ++control_ticks; });
  s.AddVisionWorker("STEREO", {50000, 0, 0, true, 1'000'000, "pair"},
                    {[](int64_t) {}, [] { std::this_thread::sleep_for(std::chrono::milliseconds(70)); }, [] {}});
  const auto start = std::chrono::steady_clock::now();
  s.Run([](int64_t) {});
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(control_ticks.load(), 50);
  EXPECT_LT(wall_s, 1.5) << "the clock waited for the vision worker";
  const PeriodStats control = s.Period("CTL");
  EXPECT_EQ(control.samples, 49);
  EXPECT_NEAR(control.p50_ms, 20.0, 2.0);
  const auto health = s.VisionHealth();
  EXPECT_GE(health[0].dropped, 5);
  EXPECT_GT(health[0].latency_p50_ms, 65.0);
}

// The camera's capture (rendering, decoding) is timed apart from the rest of the work: the
// sensing report gives it beside the whole work, so a simulator's rendering is not taken for
// perception.
TEST(LockstepScheduler, TheCapturesTimeIsGivenApartFromTheWholeWork) {
  LockstepScheduler s({0, 2000, 1.0, 500'000});
  s.AddVisionWorker("VO", {100000, 0, 0, true, 1'000'000, "pair"},
                    {[](int64_t) {},
                     [] {
                       TimedCapture([] {
                         std::this_thread::sleep_for(std::chrono::milliseconds(20));
                         return 0;
                       });
                       std::this_thread::sleep_for(std::chrono::milliseconds(30));
                     },
                     [] {}});
  s.Run([](int64_t) {});
  const auto health = s.VisionHealth();
  ASSERT_EQ(health.size(), 1u);
  EXPECT_GE(health[0].results, 3);
  EXPECT_GE(health[0].capture_p50_ms, 20.0);
  EXPECT_GE(health[0].compute_p50_ms, health[0].capture_p50_ms + 30.0);
}

// A worker that hangs: at a fixed latency the clock waits for it (here a second of wall time),
// then calls it stalled and carries on; control keeps running and later frames are dropped.
TEST(LockstepScheduler, AStalledWorkerIsReportedAndTheClockCarriesOn) {
  LockstepScheduler s({0, 2000, 0.0, 600000, 1'000'000});
  std::atomic<bool> release{false};
  std::atomic<int> control_ticks{0};
  std::vector<SensingWorker> during;
  s.AddWorker("CTL", 0, 20000, [&](int64_t t) {
    ++control_ticks;
    if (t == 500000) during = s.VisionHealth();
  });
  s.AddVisionWorker("TRK", {100000, 0, 40000, true, 1'000'000, "gimbal"},
                    {[](int64_t) {}, [&] { while (!release.load()) std::this_thread::sleep_for(std::chrono::milliseconds(5)); },
                     [] {}});
  std::thread releaser([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(2500));
    release.store(true);
  });
  s.Run([](int64_t) {});
  releaser.join();
  EXPECT_EQ(control_ticks.load(), 30);
  ASSERT_EQ(during.size(), 1u);
  EXPECT_FALSE(during[0].healthy);
  EXPECT_NE(during[0].reason.find("stalled"), std::string::npos) << during[0].reason;
  EXPECT_EQ(during[0].results, 0);
  EXPECT_GE(during[0].dropped, 4);
}

}  // namespace
}  // namespace uav::runtime
