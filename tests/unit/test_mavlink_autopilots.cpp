// What the GCS must know of the autopilot behind a HEARTBEAT: which it is, its modes, how its
// parameters carry integers (PX4 byte-wise, ArduPilot C-cast), where its mission list starts.
#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "uav/shared/mavlink_autopilots.hpp"

namespace uav::mavlink {
namespace {

TEST(MavlinkAutopilots, RecognisedFromTheHeartbeat) {
  EXPECT_EQ(RecognizeAutopilot(12, 2), Autopilot::kPx4);
  EXPECT_EQ(RecognizeAutopilot(12, 1), Autopilot::kPx4);  // PX4 is PX4 whatever it flies
  EXPECT_EQ(RecognizeAutopilot(3, 2), Autopilot::kArduCopter);
  EXPECT_EQ(RecognizeAutopilot(3, 13), Autopilot::kArduCopter);  // hexarotor
  EXPECT_EQ(RecognizeAutopilot(3, 4), Autopilot::kArduCopter);   // helicopter
  EXPECT_EQ(RecognizeAutopilot(3, 1), Autopilot::kArduPlane);
  EXPECT_EQ(RecognizeAutopilot(3, 22), Autopilot::kArduPlaneVtol);  // QuadPlane (VTOL fixed-rotor)
  EXPECT_EQ(RecognizeAutopilot(3, 20), Autopilot::kArduPlaneVtol);
  EXPECT_EQ(RecognizeAutopilot(8, 2), Autopilot::kOther);
  EXPECT_EQ(Name(Autopilot::kArduPlaneVtol), "ArduPlane VTOL");
  EXPECT_TRUE(HomeIsMissionItemZero(Autopilot::kArduCopter));
  EXPECT_TRUE(HomeIsMissionItemZero(Autopilot::kArduPlane));
  EXPECT_FALSE(HomeIsMissionItemZero(Autopilot::kPx4));
}

TEST(MavlinkAutopilots, ModesByNumberAndName) {
  // PX4: AUTO (4) with sub-mode MISSION (4) in bits 24-31.
  const AutopilotMode* m = FindMode(Autopilot::kPx4, 0x04040000u);
  ASSERT_NE(m, nullptr);
  EXPECT_STREQ(m->name, "Mission");
  EXPECT_EQ(m->task, Task::kMission);
  // Outside AUTO the sub-mode bits carry nothing: POSCTL is POSCTL.
  m = FindMode(Autopilot::kPx4, 0x07030000u);
  ASSERT_NE(m, nullptr);
  EXPECT_STREQ(m->name, "Position");
  EXPECT_EQ(FindMode(Autopilot::kPx4, 0x07040000u), nullptr);  // AUTO's sub-mode 7 is not in the table
  EXPECT_STREQ(FindMode(Autopilot::kArduCopter, 3)->name, "Auto");
  EXPECT_STREQ(FindMode(Autopilot::kArduCopter, 4)->name, "Guided");
  EXPECT_STREQ(FindMode(Autopilot::kArduPlane, 19)->name, "QLoiter");
  EXPECT_STREQ(FindMode(Autopilot::kArduPlane, 10)->name, "Auto");
  EXPECT_EQ(FindMode(Autopilot::kArduCopter, 99), nullptr);
  EXPECT_EQ(ModeName(Autopilot::kArduCopter, 99), "mode 99");
  EXPECT_EQ(ModeName(Autopilot::kPx4, 0x09000000u), "mode 0x09000000");
  EXPECT_EQ(FindModeNamed(Autopilot::kArduCopter, "guided")->custom_mode, 4u);
  EXPECT_EQ(FindModeNamed(Autopilot::kPx4, "hold")->custom_mode, 0x03040000u);
  // Every mode of every table is found back by its number and by its name.
  for (Autopilot a : {Autopilot::kPx4, Autopilot::kArduCopter, Autopilot::kArduPlane})
    for (const AutopilotMode& mode : ModesOf(a)) {
      EXPECT_EQ(FindMode(a, mode.custom_mode), &mode) << mode.name;
      EXPECT_EQ(FindModeNamed(a, mode.name), &mode) << mode.name;
    }
}

TEST(MavlinkAutopilots, ParameterEncodings) {
  std::string why;
  // PX4, byte-wise: an INT32's bytes in the float, which read as a float is something else.
  const auto px4 = EncodeParamValue(1310988, kParamInt32, ParamEncoding::kBytewise, &why);
  ASSERT_TRUE(px4) << why;
  int32_t bits = 0;
  std::memcpy(&bits, &*px4, sizeof bits);
  EXPECT_EQ(bits, 1310988);
  EXPECT_NE(*px4, 1310988.f);
  EXPECT_EQ(DecodeParamValue(*px4, kParamInt32, ParamEncoding::kBytewise), 1310988.0);
  const auto negative = EncodeParamValue(-3, 2, ParamEncoding::kBytewise, &why);  // INT8
  ASSERT_TRUE(negative);
  EXPECT_EQ(DecodeParamValue(*negative, 2, ParamEncoding::kBytewise), -3.0);
  // ArduPilot, C-cast: the number itself.
  const auto apm = EncodeParamValue(1500, kParamInt32, ParamEncoding::kCCast, &why);
  ASSERT_TRUE(apm);
  EXPECT_EQ(*apm, 1500.f);
  EXPECT_EQ(DecodeParamValue(1500.f, kParamInt32, ParamEncoding::kCCast), 1500.0);
  // Reals are floats either way.
  EXPECT_EQ(*EncodeParamValue(2.5, kParamReal32, ParamEncoding::kBytewise, &why), 2.5f);
  // What an integer type or the float cannot carry is refused, saying why.
  EXPECT_FALSE(EncodeParamValue(2.5, kParamInt32, ParamEncoding::kCCast, &why));
  EXPECT_NE(why.find("whole numbers"), std::string::npos);
  EXPECT_FALSE(EncodeParamValue(300, kParamUint8, ParamEncoding::kBytewise, &why));
  EXPECT_FALSE(EncodeParamValue(1, 8, ParamEncoding::kCCast, &why));  // INT64
  EXPECT_NE(why.find("64-bit"), std::string::npos);
  EXPECT_FALSE(DecodeParamValue(1.f, 10, ParamEncoding::kCCast));  // REAL64
  EXPECT_EQ(ParamEncodingOf(Autopilot::kPx4), ParamEncoding::kBytewise);
  EXPECT_EQ(ParamEncodingOf(Autopilot::kArduPlaneVtol), ParamEncoding::kCCast);
}

}  // namespace
}  // namespace uav::mavlink
