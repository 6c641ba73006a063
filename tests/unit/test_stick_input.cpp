// The GCS's sticks: a gamepad's axes in mode 2 with a dead zone, 20 Hz while on, and the deadman
// released when they are switched off.
#include <gtest/gtest.h>

#include <cmath>

#include "uav/gcs/stick_input.hpp"

namespace uav::gcs {
namespace {

TEST(StickInput, GamepadMapsToMode2WithADeadZoneAndABumperDeadman) {
  GamepadState g;
  g.axes = {0.5f, -1.0f, 0.05f, -0.54f, -1.0f, -1.0f};  // yaw right, full climb, right in the dead zone
  ManualSticks s = SticksFromGamepad(g, 0.08);
  EXPECT_NEAR(s.yaw, (0.5 - 0.08) / 0.92, 1e-6);
  EXPECT_NEAR(s.up, 1.0, 1e-6);
  EXPECT_EQ(s.right, 0.0);
  EXPECT_NEAR(s.forward, 0.5, 1e-6);
  EXPECT_FALSE(s.deadman);
  g.buttons[5] = true;  // right bumper
  EXPECT_TRUE(SticksFromGamepad(g).deadman);
  g.axes[0] = std::nanf("");
  EXPECT_EQ(SticksFromGamepad(g).yaw, 0.0);  // a broken axis is centred, never NaN on the wire
}

TEST(StickInput, SendsAtTwentyHertzWhileOnAndReleasesTheDeadmanWhenSwitchedOff) {
  StickInput in;
  in.virtual_sticks().forward = 0.3;
  in.virtual_sticks().deadman = true;
  for (int i = 0; i <= 100; ++i) in.Tick("UAV1", i * 0.01);  // off: nothing
  EXPECT_TRUE(in.TakeOutgoing().empty());
  in.SetEnabled(true);
  for (int i = 0; i < 100; ++i) in.Tick("UAV1", 1.0 + i * 0.01);  // 1 s at 100 frames a second
  auto out = in.TakeOutgoing();
  EXPECT_EQ(out.size(), 20u);
  EXPECT_EQ(out.front().first, "UAV1");
  EXPECT_NEAR(out.front().second.forward, 0.3, 1e-12);
  EXPECT_TRUE(out.front().second.deadman);
  // A gamepad overrides the virtual sticks.
  GamepadState g;
  g.axes[3] = -1.0f;
  in.SetGamepad(g);
  in.Tick("UAV1", 3.0);
  out = in.TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].second.forward, 1.0, 1e-6);
  EXPECT_FALSE(out[0].second.deadman);
  in.SetGamepad(std::nullopt);
  in.SetEnabled(false);
  in.Tick("UAV1", 4.0);
  out = in.TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);  // the last word: released
  EXPECT_FALSE(out[0].second.deadman);
  EXPECT_EQ(out[0].second.forward, 0.0);
  in.Tick("UAV1", 5.0);
  EXPECT_TRUE(in.TakeOutgoing().empty());
}

}  // namespace
}  // namespace uav::gcs
