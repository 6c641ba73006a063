#include <gtest/gtest.h>

#include "uav/waypoints/camera_geometry.hpp"

namespace uav::waypoints {
namespace {

// A Sony a6000-like camera: 23.5 x 15.6 mm sensor, 6000 x 4000 px, 16 mm lens.
const CameraSpec kCam{23.5, 15.6, 16.0, 6000, 4000, true};

TEST(CameraGeometry, GsdMatchesQgcFormula) {
  // GSD = H * Sw * 100 / (Iw * f) = 50 * 23.5 * 100 / (6000 * 16) = 1.22395833 cm/px.
  const Footprint f = FootprintAt(kCam, 50.0);
  EXPECT_NEAR(f.gsd_cm_per_px, 1.2239583, 1e-6);
  EXPECT_NEAR(f.across_m, 50.0 * 23.5 / 16.0, 1e-9);  // 73.4375 m
  EXPECT_NEAR(f.along_m, 50.0 * 15.6 / 16.0, 1e-9);   // 48.75 m
  EXPECT_NEAR(AltitudeForGsd(kCam, f.gsd_cm_per_px), 50.0, 1e-9);
}

TEST(CameraGeometry, SpacingAndTrigger) {
  const Footprint f = FootprintAt(kCam, 50.0);
  EXPECT_NEAR(LineSpacing(f, 0.7), 73.4375 * 0.3, 1e-9);
  EXPECT_NEAR(TriggerDistance(f, 0.8), 48.75 * 0.2, 1e-9);
  CameraSpec portrait = kCam;
  portrait.landscape = false;
  EXPECT_NEAR(FootprintAt(portrait, 50.0).across_m, 48.75, 1e-9);
}

TEST(CameraGeometry, RejectsBadInput) {
  CameraSpec bad = kCam;
  bad.focal_length_mm = 0.0;
  EXPECT_THROW(FootprintAt(bad, 50.0), std::invalid_argument);
  EXPECT_THROW(FootprintAt(kCam, -1.0), std::invalid_argument);
  const Footprint f = FootprintAt(kCam, 50.0);
  EXPECT_THROW(LineSpacing(f, 1.0), std::invalid_argument);
  EXPECT_NO_THROW(LineSpacing(f, 0.0));
  EXPECT_THROW(TriggerDistance(f, -0.01), std::invalid_argument);
}

}  // namespace
}  // namespace uav::waypoints
