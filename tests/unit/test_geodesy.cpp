#include <gtest/gtest.h>

#include <cmath>

#include "uav/shared/geodesy.hpp"

namespace uav {
namespace {

TEST(Geodesy, NedRoundTripAndAxes) {
  LocalNedFrame f({1.2966, 103.7764, 15.0});
  const Eigen::Vector3d p(100.0, -50.0, -20.0);
  const GeodeticPoint g = f.ToGeodetic(p);
  EXPECT_GT(g.latitude_deg, 1.2966);    // north is +x
  EXPECT_LT(g.longitude_deg, 103.7764); // west for negative east
  EXPECT_NEAR(g.altitude_m, 35.0, 1e-3);  // up is -z
  EXPECT_LT((f.ToNed(g) - p).norm(), 1e-6);
  // 100 m north near the equator is about 100/111320 deg of latitude.
  EXPECT_NEAR(g.latitude_deg - 1.2966, 100.0 / 110574.0, 2e-6);
}

TEST(Geodesy, ValidatesHome) {
  EXPECT_THROW(LocalNedFrame({91.0, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(LocalNedFrame({0.0, -180.1, 0.0}), std::invalid_argument);
  EXPECT_THROW(LocalNedFrame({NAN, 0.0, 0.0}), std::invalid_argument);
  EXPECT_THROW(LocalNedFrame({0.0, 0.0, 20000.0}), std::invalid_argument);
  EXPECT_NO_THROW(LocalNedFrame({90.0, 180.0, 10000.0}));
  try {
    ValidateGeodetic({0.0, 200.0, 0.0});
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("longitude_deg"), std::string::npos);
  }
}

}  // namespace
}  // namespace uav
