// The land detector: on the ground at rest, flying, falling with the motors stopped, crashed;
// each crash said with its cause, and over only once the vehicle stands upright and still.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "uav/control/land_detector.hpp"

namespace uav::control {
namespace {

constexpr double kG = 9.80665;
constexpr double kDt = 0.02;

class LandDetectorTest : public ::testing::Test {
 protected:
  // `seconds` of samples at 50 Hz with this specific force, body rates and attitude.
  GroundState Run(double seconds, const Eigen::Vector3d& f_B, bool motors_on,
                  const Eigen::Matrix3d& R_NB = Eigen::Matrix3d::Identity(), const Eigen::Vector3d& w_B = Eigen::Vector3d::Zero()) {
    GroundState s = d_.state();
    for (int i = 0; i < static_cast<int>(std::lround(seconds / kDt)); ++i) {
      t_ += kDt;
      s = d_.Update({t_, f_B, w_B, R_NB, motors_on});
    }
    return s;
  }
  static Eigen::Vector3d Standing() { return Eigen::Vector3d(0, 0, -kG); }  // the legs push up
  LandDetector d_;
  double t_ = 0.0;
};

TEST_F(LandDetectorTest, StandingStillIsOnTheGroundAtRestAndUpright) {
  // Powered on standing: at rest from the first sample.
  EXPECT_EQ(Run(0.2, Standing(), false), GroundState::kOnGround);
  EXPECT_TRUE(d_.at_rest());
  EXPECT_NEAR(d_.rest_tilt_rad(), 0.0, 1e-9);
  // Moved (carried), then put down: at rest once still for its rest time.
  Run(0.1, Standing(), false, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0));
  EXPECT_FALSE(d_.at_rest());
  Run(0.2, Standing(), false);
  EXPECT_FALSE(d_.at_rest());
  Run(0.4, Standing(), false);
  EXPECT_TRUE(d_.at_rest());
  EXPECT_NEAR(d_.rest_tilt_rad(), 0.0, 1e-9);
  EXPECT_TRUE(d_.upright_at_rest());
  // Rocked (a hand on it): not at rest.
  Run(0.1, Standing(), false, Eigen::Matrix3d::Identity(), Eigen::Vector3d(0.5, 0, 0));
  EXPECT_FALSE(d_.at_rest());
}

TEST_F(LandDetectorTest, ALandingIsOnTheGroundNotACrash) {
  EXPECT_EQ(Run(5.0, Standing(), true), GroundState::kFlying);
  // Touchdown at 0.7 m/s, stopped within one 20 ms sample: 35 m/s^2 over gravity.
  EXPECT_EQ(Run(0.02, Eigen::Vector3d(0, 0, -kG - 35), true), GroundState::kFlying);
  EXPECT_EQ(Run(0.6, Standing(), true), GroundState::kFlying);  // still armed, rotors idling
  EXPECT_EQ(Run(0.6, Standing(), false), GroundState::kOnGround);
  EXPECT_TRUE(d_.crash_reason().empty());
  // Stopped at a landing's touchdown: on the ground at once, whatever the IMU reads then.
  LandDetector landing;
  for (int i = 0; i < 100; ++i) landing.Update({i * kDt, Standing(), Eigen::Vector3d(0.3, 0, 0), Eigen::Matrix3d::Identity(), true, true});
  EXPECT_EQ(landing.Update({2.0, Standing(), Eigen::Vector3d(0.3, 0, 0), Eigen::Matrix3d::Identity(), false, false}), GroundState::kOnGround);
}

TEST_F(LandDetectorTest, MotorsStoppedInTheAirFallAndCrash) {
  Run(3.0, Standing(), true);
  // The rotors spin down for a tenth of a second, then free fall (the accelerometer reads ~0).
  EXPECT_EQ(Run(0.06, Eigen::Vector3d(0, 0, -0.7 * kG), false), GroundState::kFlying);
  EXPECT_EQ(Run(1.2, Eigen::Vector3d(0, 0, -0.1), false), GroundState::kFalling);
  // The ground: an impact, then lying still.
  EXPECT_EQ(Run(0.02, Eigen::Vector3d(0, 0, -600), false), GroundState::kCrashed);
  EXPECT_NE(d_.crash_reason().find("fell with its motors stopped (impact of 61.2 g)"), std::string::npos) << d_.crash_reason();
  // It stays crashed lying on its side (gravity along y_B), whatever time passes.
  EXPECT_EQ(Run(3.0, Eigen::Vector3d(0, -kG, 0), false), GroundState::kCrashed);
  EXPECT_NEAR(d_.rest_tilt_rad() * 180 / M_PI, 90.0, 1e-6);
  EXPECT_FALSE(d_.upright_at_rest());
  // Stood upright and still: the crash may be declared over.
  Run(0.6, Standing(), false);
  EXPECT_TRUE(d_.upright_at_rest());
  d_.Recover();
  EXPECT_EQ(d_.state(), GroundState::kOnGround);
  EXPECT_TRUE(d_.crash_reason().empty());
}

TEST_F(LandDetectorTest, AFallThatComesToRestWithoutAHardImpactIsACrashToo) {
  Run(1.0, Standing(), true);
  Run(0.5, Eigen::Vector3d(0, 0, -0.2), false);
  ASSERT_EQ(d_.state(), GroundState::kFalling);
  EXPECT_EQ(Run(0.6, Standing(), false), GroundState::kCrashed);  // into a net: at rest
}

TEST_F(LandDetectorTest, TippedPastTheLimitInFlightIsACrashAfterHalfASecond) {
  Run(1.0, Standing(), true);
  const Eigen::Matrix3d rolled = Eigen::AngleAxisd(75 * M_PI / 180, Eigen::Vector3d::UnitX()).toRotationMatrix();
  EXPECT_EQ(Run(0.4, Standing(), true, rolled), GroundState::kFlying);
  EXPECT_EQ(Run(0.2, Standing(), true, rolled), GroundState::kCrashed);
  EXPECT_NE(d_.crash_reason().find("tipped 75 deg (limit 60)"), std::string::npos) << d_.crash_reason();
  // Banked within the limit for long: flying.
  LandDetector banked;
  for (int i = 0; i < 200; ++i)
    banked.Update({i * kDt, Standing(), Eigen::Vector3d::Zero(),
                   Eigen::AngleAxisd(40 * M_PI / 180, Eigen::Vector3d::UnitY()).toRotationMatrix(), true});
  EXPECT_EQ(banked.state(), GroundState::kFlying);
}

TEST_F(LandDetectorTest, AnImpactInFlightIsACrash) {
  Run(1.0, Standing(), true);
  EXPECT_EQ(Run(0.02, Eigen::Vector3d(120, 0, -kG), true), GroundState::kCrashed);
  EXPECT_NE(d_.crash_reason().find("impact of 12.3 g in flight"), std::string::npos) << d_.crash_reason();
}

TEST_F(LandDetectorTest, ATailSitterStandsOnItsTailAndItsTiltInFlightIsNotACrash) {
  LandDetectorParams p;
  p.up_B = Eigen::Vector3d(1, 0, 0);
  p.check_tilt_in_flight = false;
  LandDetector ts(p);
  const Eigen::Vector3d on_tail(kG, 0, 0);  // nose up: the ground pushes along +x_B
  const Eigen::Matrix3d nose_up = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  double t = 0;
  for (int i = 0; i < 50; ++i) ts.Update({t += kDt, on_tail, Eigen::Vector3d::Zero(), nose_up, false});
  EXPECT_TRUE(ts.upright_at_rest());
  EXPECT_NEAR(ts.rest_tilt_rad(), 0.0, 1e-9);
  // On the wing (level, 90 degrees from its standing attitude) for a minute: flying.
  for (int i = 0; i < 3000; ++i) ts.Update({t += kDt, Eigen::Vector3d(0, 0, -kG), Eigen::Vector3d::Zero(), Eigen::Matrix3d::Identity(), true});
  EXPECT_EQ(ts.state(), GroundState::kFlying);
}

TEST_F(LandDetectorTest, NonFiniteSamplesAreSkipped) {
  Run(1.0, Standing(), false);
  EXPECT_EQ(Run(0.1, Eigen::Vector3d(NAN, 0, 0), false), GroundState::kOnGround);
  EXPECT_TRUE(d_.at_rest());
}

}  // namespace
}  // namespace uav::control
