// The GCS's alarm on a state no vehicle can be in: a height far below home, a roll or pitch past
// the vehicle's limits, a jump of the estimate, a ground speed far past the vehicle's. Said once
// as an error (so spoken) when it starts, once when it is over.
#include <gtest/gtest.h>

#include <cmath>

#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/spoken_alerts.hpp"
#include "uav/gcs/state_alarms.hpp"

namespace uav::gcs {
namespace {

VehicleState At(double t_s, const Eigen::Vector3d& p_N, double roll_deg = 0, double speed = 0) {
  VehicleState s;
  s.utime = static_cast<int64_t>(t_s * 1e6);
  s.p_N = p_N;
  s.euler.phi = roll_deg * M_PI / 180;
  s.v_B = Eigen::Vector3d(speed, 0, 0);
  return s;
}

TEST(StateAlarms, EachAbsurdStateIsNamedWithItsNumbers) {
  StateLimits x650;
  x650.tilt_max_rad = 1.5 * 0.45;  // ctl_tilt_max
  x650.speed_max_m_s = 9.0;
  const VehicleState fine = At(1.0, {5, 0, -10}, 20, 3);
  EXPECT_TRUE(AbsurdState(nullptr, fine, x650).empty());
  auto only = [&](const VehicleState* prev, const VehicleState& s, const std::string& key) {
    const auto a = AbsurdState(prev, s, x650);
    EXPECT_EQ(a.size(), 1u) << key;
    return a.empty() ? std::string() : a[0].key + ": " + a[0].text;
  };
  EXPECT_EQ(only(nullptr, At(1, {0, 0, 14.5}), "height"), "height: height -14.5 m: far below home (the estimate has gone wrong, or a crash)");
  EXPECT_EQ(only(nullptr, At(1, {0, 0, -10}, 90), "tilt"), "tilt: roll 90 deg: past the vehicle's limits (39 deg)");
  const VehicleState before = At(1.00, {0, 0, -8});
  EXPECT_EQ(only(&before, At(1.02, {180, 0, -8}), "jump"), "jump: the position estimate jumped 180 m in 0.02 s");
  EXPECT_EQ(only(nullptr, At(1, {0, 0, -8}, 0, 20), "speed"), "speed: ground speed 20.0 m/s: over three times what the vehicle flies");
  // A fast but possible step (3 m in 0.5 s) is no jump; a tail-sitter's 90 degrees is no tilt.
  const VehicleState later = At(1.5, {3, 0, -8});
  EXPECT_TRUE(AbsurdState(&before, later, x650).empty());
  StateLimits wing = x650;
  wing.check_tilt = false;
  EXPECT_TRUE(AbsurdState(nullptr, At(1, {0, 0, -10}, 90), wing).empty());
}

TEST(StateAlarms, LimitsComeFromTheVehiclesParameters) {
  ParameterTable t;
  t.entries = {{"ctl_speed_max_xy", "m/s", "", 3.0}, {"ctl_tilt_max", "rad", "", 0.45}, {"ts_cruise_speed", "m/s", "", 12.0}};  // by name
  const StateLimits quad = StateLimits::From(&t, VehicleType::kQuadrotor);
  EXPECT_NEAR(quad.tilt_max_rad, 0.675, 1e-12);
  EXPECT_NEAR(quad.speed_max_m_s, 9.0, 1e-12);
  EXPECT_TRUE(quad.check_tilt);
  const StateLimits ts = StateLimits::From(&t, VehicleType::kTailSitter);
  EXPECT_NEAR(ts.speed_max_m_s, 36.0, 1e-12);
  EXPECT_FALSE(ts.check_tilt);
}

// In the model: said once as an error, spoken, and once more when it is over.
TEST(StateAlarms, TheModelSaysEachOnceAndItIsSpoken) {
  GcsModel m("gcs", 1);
  m.OnState("UAV1", 1, At(1.00, {0, 0, -8}), 1.00);
  const std::size_t before = m.log().lines().size();
  for (int i = 1; i <= 50; ++i) m.OnState("UAV1", 1 + i, At(1.00 + 0.02 * i, {0, 0, 14.5}), 1.00 + 0.02 * i);
  int alarms = 0;
  for (std::size_t i = before; i < m.log().lines().size(); ++i)
    alarms += m.log().lines()[i].text.rfind("ALARM: height -14.5 m", 0) == 0 && m.log().lines()[i].severity == Severity::kError;
  EXPECT_EQ(alarms, 1);
  SpokenAlerts spoken;
  const auto sentences = spoken.Take(m.log(), 2.0);
  EXPECT_NE(std::find_if(sentences.begin(), sentences.end(), [](const std::string& s) { return s.find("ALARM: height") != std::string::npos; }),
            sentences.end());
  m.OnState("UAV1", 100, At(3.0, {0, 0, -1}), 3.0);
  EXPECT_EQ(m.log().lines().back().text.rfind("alarm over: height -14.5 m", 0), 0u) << m.log().lines().back().text;
  EXPECT_EQ(m.log().lines().back().severity, Severity::kInfo);
}

}  // namespace
}  // namespace uav::gcs
