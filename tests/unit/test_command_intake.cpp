#include <gtest/gtest.h>

#include "uav/runtime/command_intake.hpp"

namespace uav::runtime {
namespace {

TEST(CommandIntake, ValidCommandBecomesARequest) {
  CommandIntake in("UAV1");
  auto r = in.Receive("UAV1", "gcs", 1, "takeoff 10");
  ASSERT_TRUE(r.request);
  EXPECT_EQ(r.request->command.id, CommandId::kTakeoff);
  EXPECT_TRUE(r.replies.empty());
}

TEST(CommandIntake, InvalidCommandIsRejectedWithTheGrammarError) {
  CommandIntake in("UAV1");
  auto r = in.Receive("UAV1", "gcs", 1, "takeoff nan");
  EXPECT_FALSE(r.request);
  ASSERT_EQ(r.replies.size(), 1u);
  EXPECT_EQ(r.replies[0].result, control::AckResult::kRejected);
  EXPECT_EQ(r.replies[0].reason, "takeoff: argument alt_m is not a finite number: 'nan'");
}

TEST(CommandIntake, ResendIsAnsweredNotExecuted) {
  CommandIntake in("UAV1");
  ASSERT_TRUE(in.Receive("UAV1", "gcs", 5, "arm").request);
  in.Remember({"gcs", 5, "arm", control::AckResult::kCompleted, 100, ""});
  auto again = in.Receive("UAV1", "gcs", 5, "arm");
  EXPECT_FALSE(again.request);
  ASSERT_EQ(again.replies.size(), 1u);
  EXPECT_EQ(again.replies[0].result, control::AckResult::kCompleted);
  // Same sequence number from another GCS is a different request.
  EXPECT_TRUE(in.Receive("UAV1", "other", 5, "arm").request);
}

TEST(CommandIntake, OtherVehiclesCommandsAreIgnored) {
  CommandIntake in("UAV1");
  auto r = in.Receive("UAV2", "gcs", 1, "arm");
  EXPECT_FALSE(r.request);
  EXPECT_TRUE(r.replies.empty());
}

TEST(CommandIntake, MemoryIsBounded) {
  CommandIntake in("UAV1");
  for (int i = 0; i < 1000; ++i) in.Remember({"gcs", i, "arm", control::AckResult::kCompleted, 100, ""});
  // The oldest were forgotten: seq 0 executes again, seq 999 is still recognised.
  EXPECT_TRUE(in.Receive("UAV1", "gcs", 0, "arm").request);
  EXPECT_FALSE(in.Receive("UAV1", "gcs", 999, "arm").request);
}

}  // namespace
}  // namespace uav::runtime
