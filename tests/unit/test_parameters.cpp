#include <cmath>
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

#include <filesystem>

#include "uav/shared/parameter_table.hpp"
#include "uav/shared/parameters.hpp"

namespace uav {
namespace {

// A small declaration of the program's kind: the limits live here, never in the file.
const ParameterSchema& TestSchema() {
  static const ParameterSchema kSchema{"test", {
      {"mass", "kg", 1.37, 0.1, 50, "total mass"},
      {"wind", "m/s", 0, 0, 20, "steady wind"},
      {"focal", "mm", std::nullopt, 0.1, 1000, "lens focal length"},
      {"cx", "px", std::nullopt, 0, 20000, "principal point", ParamApply::kAtStart, true},
  }};
  return kSchema;
}

std::string ErrorOf(const std::string& text, const ParameterSchema& schema = TestSchema()) {
  try {
    ParameterSet::Parse(text, "t.params", schema);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Parameters, FileSetsValuesTheProgramDeclaresUnitsLimitsAndDescriptions) {
  const auto p = ParameterSet::Parse("# comment\n\nmass 2.5  # heavier\nfocal 3.8\n", "t.params", TestSchema());
  EXPECT_DOUBLE_EQ(p.Get("mass"), 2.5);
  EXPECT_EQ(p.all().at("mass").unit, "kg");
  EXPECT_EQ(p.all().at("mass").description, "total mass");
  EXPECT_DOUBLE_EQ(p.all().at("mass").max, 50);
  EXPECT_DOUBLE_EQ(p.Get("wind"), 0);  // left out: the declared default
  EXPECT_FALSE(p.Has("cx"));          // optional, no default
}

TEST(Parameters, LimitsAreTheProgramsAndInclusive) {
  EXPECT_EQ(ErrorOf("mass 0.1\nwind 20\nfocal 1\n"), "");
  EXPECT_NE(ErrorOf("mass 0.0999\nfocal 1").find("t.params:1: mass = 0.0999 is outside [0.1, 50] kg"),
            std::string::npos);
  EXPECT_NE(ErrorOf("focal 1\n\nwind 20.01").find("t.params:3: wind = 20.01 is outside [0, 20] m/s"),
            std::string::npos);
}

TEST(Parameters, AFileCannotRewriteItsLimits) {
  // The old format carried limits; a file that "widens" mass to 1000 kg is refused either way.
  EXPECT_NE(ErrorOf("mass 900 kg 0.1 1000\nfocal 1").find("t.params:1: expected 'name value'"), std::string::npos);
  EXPECT_NE(ErrorOf("mass 900\nfocal 1").find("mass = 900 is outside [0.1, 50] kg"), std::string::npos);
  const std::string vehicle = ErrorOf("mass 900\n", VehicleParameterSchema());
  EXPECT_NE(vehicle.find("t.params:1: mass = 900 is outside [0.1, 50] kg"), std::string::npos) << vehicle;
}

TEST(Parameters, UnknownNamesAreRefusedNamingTheEntry) {
  EXPECT_EQ(ErrorOf("focal 1\nmas 2"), "t.params:2: 'mas' is not a test parameter (did you mean 'mass'?)");
  EXPECT_EQ(ErrorOf("focal 1\ncolour 2"), "t.params:2: 'colour' is not a test parameter");
  EXPECT_NE(ErrorOf("fs_batery_land 0.1\n", VehicleParameterSchema()).find("did you mean 'fs_battery_land'?"),
            std::string::npos);
}

TEST(Parameters, BadLinesNameThemselves) {
  EXPECT_NE(ErrorOf("mass nan").find("t.params:1: mass: value 'nan' is not a finite number"), std::string::npos);
  EXPECT_NE(ErrorOf("mass 0x10").find("value '0x10' is not a finite number"), std::string::npos);
  EXPECT_NE(ErrorOf("mass").find("expected 'name value'"), std::string::npos);
  EXPECT_NE(ErrorOf("focal 1\nmass 1\nmass 2").find("t.params:3: mass is set twice"), std::string::npos);
  EXPECT_EQ(ErrorOf("mass 1"), "t.params: focal is missing (lens focal length, mm)");
}

TEST(Parameters, MissingParameterNamesItAndTheSource) {
  const auto p = ParameterSet::Parse("focal 1", "t.params", TestSchema());
  try {
    p.Get("cx");
    FAIL();
  } catch (const std::out_of_range& e) {
    EXPECT_STREQ(e.what(), "parameter 'cx' is missing from t.params");
  }
}

TEST(Parameters, OverridesAreCheckedAgainstTheDeclaredLimitsOnBothSides) {
  const auto p = ParameterSet::Parse("focal 1", "t.params", TestSchema());
  EXPECT_DOUBLE_EQ(p.With("wind", 20).Get("wind"), 20);
  EXPECT_DOUBLE_EQ(p.WithAssignment("wind=5").Get("wind"), 5);
  EXPECT_DOUBLE_EQ(p.WithAssignment("cx=320").Get("cx"), 320);  // an optional one may be set
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
  EXPECT_NE(error("wind=0x5").find("NAME=VALUE"), std::string::npos);
  EXPECT_NE(error("wind").find("NAME=VALUE"), std::string::npos);
}

TEST(Parameters, AFileThatSetsNothingIsRefusedNamingIt) {
  const std::string path = testing::TempDir() + "uav_empty_vehicle.params";
  for (const char* text : {"", "# only a comment\n\n"}) {
    {
      std::ofstream(path) << text;
    }
    try {
      ParameterSet::LoadFile(path, VehicleParameterSchema());
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(path + ": the vehicle parameter file sets nothing"), std::string::npos) << e.what();
    }
  }
  std::remove(path.c_str());
}

TEST(Parameters, ShippedVehicleFilesLoadAndSetEveryDeclaredParameter) {
  const auto p = ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650.params", VehicleParameterSchema());
  EXPECT_DOUBLE_EQ(p.Get("thrust_gain"), 3.8738);        // Table 2.5
  EXPECT_DOUBLE_EQ(p.Get("thrust_time_constant"), 0.095583);
  EXPECT_DOUBLE_EQ(p.Get("induced_torque_coeff"), 0.013);
  EXPECT_DOUBLE_EQ(p.Get("mass"), 1.37);                 // Table 2.2
  EXPECT_DOUBLE_EQ(p.Get("inertia_zz"), 0.05423);
  // The declared defaults are the X650 file's values.
  const auto defaults = ParameterSet::Defaults(VehicleParameterSchema());
  for (const auto& [name, param] : p.all()) EXPECT_DOUBLE_EQ(param.value, defaults.Get(name)) << name;
  const auto heavy = ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/x650_heavy_gyro.params",
                                            VehicleParameterSchema());
  EXPECT_DOUBLE_EQ(heavy.Get("mass"), 1.80);
  EXPECT_DOUBLE_EQ(heavy.Get("attitude_mode"), 2);
}

// A variant lists only what differs: "include BASE" first, found beside the file; the variant's
// own values win and are named as its own; a value set twice in one file, an include after a
// setting, a missing base and an include cycle are refused, named.
TEST(Parameters, AVariantIncludesItsBaseAndListsOnlyWhatDiffers) {
  const std::filesystem::path dir = std::filesystem::path(testing::TempDir()) / "uav_include";
  std::filesystem::create_directories(dir / "variants");
  std::ofstream(dir / "base.params") << "mass 2.0\nwind 3\nfocal 8\n";
  std::ofstream(dir / "variants" / "windy.params") << "# a windier day\ninclude ../base.params\nwind 9  # gusty\n";
  const auto windy = ParameterSet::LoadFile((dir / "variants" / "windy.params").string(), TestSchema());
  EXPECT_DOUBLE_EQ(windy.Get("mass"), 2.0);
  EXPECT_DOUBLE_EQ(windy.Get("wind"), 9.0);
  EXPECT_EQ(windy.Describe("mass"), "mass 2 (base.params)");
  EXPECT_EQ(windy.Describe("wind"), "wind 9 (windy.params)");
  auto refused = [&](const std::string& text) {
    std::ofstream(dir / "bad.params") << text;
    try {
      ParameterSet::LoadFile((dir / "bad.params").string(), TestSchema());
      return std::string("accepted");
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
  };
  EXPECT_NE(refused("include base.params\nwind 1\nwind 2\n").find("bad.params:3: wind is set twice"), std::string::npos);
  EXPECT_NE(refused("wind 1\ninclude base.params\n").find("bad.params:2: include must come first"), std::string::npos);
  EXPECT_NE(refused("include nowhere.params\n").find("nowhere.params"), std::string::npos);
  EXPECT_NE(refused("include bad.params\n").find("nested more than 8 deep"), std::string::npos);
  // The shipped variants are their base and a few lines.
  const std::string vehicles = std::string(UAV_RESOURCE_DIR) + "/vehicles/";
  const auto x650 = ParameterSet::LoadFile(vehicles + "x650.params", VehicleParameterSchema());
  for (const char* variant : {"x650_heavy_gyro.params", "x650_whole_suite.params"}) {
    const auto v = ParameterSet::LoadFile(vehicles + variant, VehicleParameterSchema());
    int differ = 0;
    for (const auto& [name, param] : v.all()) differ += param.value != x650.Get(name);
    EXPECT_GT(differ, 0) << variant;
    EXPECT_LE(differ, 8) << variant;
  }
  std::filesystem::remove_all(dir);
}

TEST(Parameters, ShippedCameraFilesLoad) {
  int n = 0;
  for (const auto& e : std::filesystem::directory_iterator(std::string(UAV_RESOURCE_DIR) + "/cameras")) {
    if (e.path().extension() != ".camera") continue;  // OpenCV calibrations beside them (rig files)
    const auto p = ParameterSet::LoadFile(e.path().string(), CameraParameterSchema());
    EXPECT_GT(p.Get("focal_length_mm"), 0) << e.path();
    ++n;
  }
  EXPECT_GE(n, 3);
}

TEST(Parameters, DescribeSchemaListsEveryDeclaration) {
  const std::string text = DescribeSchema(TestSchema());
  EXPECT_NE(text.find("mass  1.37  kg  [0.1, 50]  changes: start  total mass"), std::string::npos) << text;
  EXPECT_NE(text.find("focal  (required)  mm"), std::string::npos) << text;
}

// When each vehicle parameter may change over the link: the control thread's settings at once,
// the geofence only on the ground, what builds the vehicle (its model, sensors, threads) at start.
TEST(Parameters, EveryVehicleParameterSaysWhenItMayChange) {
  const ParameterSchema& s = VehicleParameterSchema();
  EXPECT_EQ(s.Find("ctl_pos_gain_xy")->apply, ParamApply::kInFlight);
  EXPECT_EQ(s.Find("fs_battery_return")->apply, ParamApply::kInFlight);
  EXPECT_EQ(s.Find("obs_margin")->apply, ParamApply::kInFlight);
  EXPECT_EQ(s.Find("fs_fence_radius")->apply, ParamApply::kOnGround);
  EXPECT_EQ(s.Find("avd_enable")->apply, ParamApply::kAtStart);
  EXPECT_EQ(s.Find("avd_map_res")->apply, ParamApply::kAtStart);
  EXPECT_EQ(s.Find("mass")->apply, ParamApply::kAtStart);
  EXPECT_EQ(s.Find("trk_tracker")->apply, ParamApply::kAtStart);
  EXPECT_NE(DescribeSchema(s).find("changes: flight"), std::string::npos);
}

// The table round-trips through both file formats, and a bad file names its line.
TEST(ParameterFiles, BothFormatsRoundTripAndBadLinesNameThemselves) {
  const ParameterSet set = ParameterSet::Defaults(VehicleParameterSchema()).With("ctl_speed_max_xy", 4.25);
  const ParameterTable table = ParameterTable::Of(set, 3, 1'000'000);
  ASSERT_EQ(table.entries.size(), VehicleParameterSchema().specs.size());
  const ParameterEntry* e = table.Find("ctl_speed_max_xy");
  ASSERT_NE(e, nullptr);
  EXPECT_EQ(e->value, 4.25);
  EXPECT_EQ(e->unit, "m/s");
  EXPECT_EQ(e->apply, ParamApply::kInFlight);
  for (ParameterFileFormat f : {ParameterFileFormat::kVehicle, ParameterFileFormat::kQgc}) {
    const std::string text = FormatParameterFile(table, f, "UAV1");
    const auto values = ParseParameterFile(text, "p.params");
    ASSERT_EQ(values.size(), table.entries.size());
    for (std::size_t i = 0; i < values.size(); ++i) {
      EXPECT_EQ(values[i].first, table.entries[i].name);
      EXPECT_EQ(values[i].second, table.entries[i].value) << values[i].first;  // exact: shortest round-trip digits
    }
  }
  // A MAVLink autopilot's integer parameter keeps its type in QGroundControl's file.
  ParameterTable px4;
  px4.entries.push_back(ParameterEntry{"SYS_AUTOSTART", "INT32", "", 4001, std::nan(""), -1e30, 1e30, ParamApply::kInFlight, 6});
  const std::string saved = FormatParameterFile(px4, ParameterFileFormat::kQgc, "px4-1");
  EXPECT_NE(saved.find("1\t1\tSYS_AUTOSTART\t4001\t6\n"), std::string::npos) << saved;
  // Our format is a vehicle file: the vehicle loads it as one.
  const ParameterSet again = ParameterSet::Parse(FormatParameterFile(table, ParameterFileFormat::kVehicle, "UAV1"), "saved.params",
                                                 VehicleParameterSchema());
  EXPECT_EQ(again.Get("ctl_speed_max_xy"), 4.25);
  // A QGroundControl file as QGC writes it (CRLF, header comments, type column).
  const auto qgc = ParseParameterFile("# Onboard parameters for Vehicle 1\r\n#\r\n1\t1\tctl_tilt_max\t25\t9\r\n", "qgc.params");
  ASSERT_EQ(qgc.size(), 1u);
  EXPECT_EQ(qgc[0], (std::pair<std::string, double>{"ctl_tilt_max", 25.0}));
  auto error_of = [](const std::string& text) {
    try {
      ParseParameterFile(text, "bad.params");
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of("mass 1\nmass nan\n"), "bad.params:2: mass: 'nan' is not a finite decimal number");
  EXPECT_EQ(error_of("mass 1\nmass 2\n"), "bad.params:2: mass is set twice");
  EXPECT_EQ(error_of("\nmass\n"), "bad.params:2: 'mass' has no value");
  EXPECT_EQ(error_of("mass 1 2\n"), "bad.params:1: 'mass' is followed by '2' (expected: name value)");
}

}  // namespace
}  // namespace uav
