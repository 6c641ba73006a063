#include <gtest/gtest.h>

#include "uav/shared/parameters.hpp"

namespace uav {
namespace {

std::string ErrorOf(const std::string& text) {
  try {
    ParameterSet::Parse(text, "t.params");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Parameters, ParsesValuesUnitsLimitsAndDescriptions) {
  const auto p = ParameterSet::Parse(
      "# comment\n\nmass 1.37 kg 0.1 50 # total mass\nl 0.325 m 0.05 5\n", "t.params");
  EXPECT_DOUBLE_EQ(p.Get("mass"), 1.37);
  EXPECT_EQ(p.all().at("mass").unit, "kg");
  EXPECT_EQ(p.all().at("mass").description, "total mass");
  EXPECT_DOUBLE_EQ(p.Get("l"), 0.325);
}

TEST(Parameters, LimitsAreInclusive) {
  EXPECT_EQ(ErrorOf("a 0.1 kg 0.1 50\nb 50 kg 0.1 50\n"), "");
  EXPECT_NE(ErrorOf("a 0.0999 kg 0.1 50").find("t.params:1: a = 0.0999 is outside [0.1, 50] kg"),
            std::string::npos);
  EXPECT_NE(ErrorOf("\nb 50.01 kg 0.1 50").find("t.params:2:"), std::string::npos);
}

TEST(Parameters, BadLinesNameThemselves) {
  EXPECT_NE(ErrorOf("a nan kg 0 1").find("value 'nan' is not a finite number"), std::string::npos);
  EXPECT_NE(ErrorOf("a 1 kg").find("expected 'name value unit min max'"), std::string::npos);
  EXPECT_NE(ErrorOf("a 1 kg 0 2 extra").find("expected"), std::string::npos);
  EXPECT_NE(ErrorOf("a 1 kg 2 0").find("min > max"), std::string::npos);
  EXPECT_NE(ErrorOf("a 1 kg 0 2\na 1 kg 0 2").find("t.params:2: a is defined twice"),
            std::string::npos);
}

TEST(Parameters, MissingParameterNamesItAndTheSource) {
  const auto p = ParameterSet::Parse("a 1 kg 0 2", "t.params");
  try {
    p.Get("b");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_STREQ(e.what(), "parameter 'b' is missing from t.params");
  }
}

TEST(Parameters, OverridesAreCheckedAgainstTheLimitsOnBothSides) {
  const auto p = ParameterSet::Parse("wind 0 m/s 0 20", "t.params");
  EXPECT_DOUBLE_EQ(p.With("wind", 20).Get("wind"), 20);
  EXPECT_DOUBLE_EQ(p.WithAssignment("wind=5").Get("wind"), 5);
  EXPECT_DOUBLE_EQ(p.Get("wind"), 0);  // the original is unchanged
  auto error = [&](const std::string& a) {
    try {
      p.WithAssignment(a);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error("wind=20.001"), "parameter wind = 20.001 is outside [0, 20] m/s");
  EXPECT_EQ(error("wind=-0.001"), "parameter wind = -0.001 is outside [0, 20] m/s");
  EXPECT_EQ(error("gust=1"), "parameter 'gust' does not exist in t.params");
  EXPECT_NE(error("wind=nan").find("NAME=VALUE"), std::string::npos);
  EXPECT_NE(error("wind").find("NAME=VALUE"), std::string::npos);
}

TEST(Parameters, ShippedVehicleFileLoads) {
  const auto p = ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params");
  EXPECT_DOUBLE_EQ(p.Get("thrust_gain"), 3.8738);        // Table 2.5
  EXPECT_DOUBLE_EQ(p.Get("thrust_time_constant"), 0.095583);
  EXPECT_DOUBLE_EQ(p.Get("induced_torque_coeff"), 0.013);
  EXPECT_DOUBLE_EQ(p.Get("mass"), 1.37);                 // Table 2.2
  EXPECT_DOUBLE_EQ(p.Get("inertia_zz"), 0.05423);
}

}  // namespace
}  // namespace uav
