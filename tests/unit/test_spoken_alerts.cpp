// Spoken alerts: which messages are said (warnings and errors, once, a burst summarised), and the
// speaker that says them off the UI thread with the program it is given.
#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include "uav/gcs/speaker.hpp"
#include "uav/gcs/spoken_alerts.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::gcs {
namespace {

TEST(SpokenAlerts, WarningsOnceABurstSummarisedInfoNever) {
  MessageLog log;
  SpokenAlerts alerts;
  log.Add(0.0, "UAV1", "takeoff 10: completed", Severity::kInfo);
  log.Add(0.1, "UAV1", "failsafe return: battery 24 %", Severity::kWarning);
  EXPECT_EQ(alerts.Take(log, 0.1), std::vector<std::string>{"UAV1: failsafe return: battery 24 %"});
  EXPECT_TRUE(alerts.Take(log, 0.2).empty());  // said once
  // The same text again within 30 s is not repeated; after, it is.
  log.Add(5.0, "UAV1", "failsafe return: battery 24 %", Severity::kWarning);
  EXPECT_TRUE(alerts.Take(log, 5.0).empty());
  log.Add(40.0, "UAV1", "failsafe return: battery 24 %", Severity::kWarning);
  EXPECT_EQ(alerts.Take(log, 40.0).size(), 1u);
  // A burst: two read out, the rest counted per vehicle; the GCS's own notes name it.
  for (int i = 0; i < 5; ++i) log.Add(41.0, "UAV2", "power line " + std::to_string(i + 5) + " m away", Severity::kWarning);
  log.Add(41.0, "", "parameters not saved: disk full", Severity::kError);
  const std::vector<std::string> burst = alerts.Take(log, 41.0);
  ASSERT_EQ(burst.size(), 4u);
  EXPECT_EQ(burst[0], "UAV2: power line 5 m away");
  EXPECT_EQ(burst[1], "UAV2: power line 6 m away");
  EXPECT_EQ(burst[2], "UAV2: 3 more warnings");
  EXPECT_EQ(burst[3], "ground station: 1 more warning");
}

// The speaker runs the program it is given with the sentence as one argument (no shell), on its
// own thread; a missing program makes it unavailable and Say a no-op.
TEST(Speaker, SaysEachSentenceAsOneArgumentOffTheCallersThread) {
  const std::string dir = ::testing::TempDir() + "uav_speaker";
  std::filesystem::create_directories(dir);
  const std::string said = dir + "/said.txt", program = dir + "/say";
  std::filesystem::remove(said);
  {
    std::ofstream f(program);
    f << "#!/bin/sh\nsleep 0.2\nprintf '%s|%s\\n' \"$#\" \"$1\" >> " << said << "\n";
  }
  std::filesystem::permissions(program, std::filesystem::perms::owner_all);
  Speaker speaker(program);
  ASSERT_TRUE(speaker.available());
  const auto t0 = std::chrono::steady_clock::now();
  speaker.Say("UAV1: failsafe land; rm -rf / $(reboot)");
  speaker.Say("UAV1: obstacle avoidance: blocked");
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(100));  // never waits for speech
  for (int i = 0; i < 100 && speaker.spoken() < 2; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_EQ(speaker.spoken(), 2);
  EXPECT_EQ(ReadTextFile(said, "said"), "1|UAV1: failsafe land; rm -rf / $(reboot)\n1|UAV1: obstacle avoidance: blocked\n");
  Speaker missing("uav-no-such-speech-program");
  EXPECT_FALSE(missing.available());
  missing.Say("nothing");
  EXPECT_EQ(missing.spoken(), 0);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uav::gcs
