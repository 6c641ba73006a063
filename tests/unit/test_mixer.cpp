#include <gtest/gtest.h>

#include <cmath>

#include "uav/control/mixer.hpp"

namespace uav::control {
namespace {

TEST(Mixer, ThrottleAloneIsCommonToAllRotors) {
  const auto m = MixToRotors({0, 0, 0.18, 0});
  for (double v : m) EXPECT_DOUBLE_EQ(v, 0.18);
}

TEST(Mixer, ChannelsMapToEq211Torques) {
  // Aileron: left rotors (2, 3) up, right (1, 4) down.
  auto m = MixToRotors({0.1, 0, 0.2, 0});
  EXPECT_NEAR((m[1] + m[2]) - (m[0] + m[3]), 0.4, 1e-12);
  // Elevator: front (1, 2) up.
  m = MixToRotors({0, 0.1, 0.2, 0});
  EXPECT_NEAR((m[0] + m[1]) - (m[2] + m[3]), 0.4, 1e-12);
  // Rudder: 1 and 3 up.
  m = MixToRotors({0, 0, 0.2, 0.1});
  EXPECT_NEAR(m[0] - m[1] + m[2] - m[3], 0.4, 1e-12);
}

TEST(Mixer, SaturationKeepsDifferentialsAndStaysInRange) {
  const auto m = MixToRotors({0.2, 0, 0.95, 0});
  for (double v : m) EXPECT_LE(v, 1.0);
  EXPECT_NEAR((m[1] + m[2]) - (m[0] + m[3]), 0.8, 1e-12);  // roll torque kept
}

TEST(Mixer, NonFiniteInputStopsTheRotors) {
  const auto m = MixToRotors({NAN, 0, 0.2, 0});
  for (double v : m) EXPECT_EQ(v, -1.0);
}

}  // namespace
}  // namespace uav::control
