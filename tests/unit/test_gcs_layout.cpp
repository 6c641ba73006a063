// The default layout fits the displays operators use: no two panels always shown overlap, no
// window opened on demand covers the command bar (its emergency stop) or the status bar, and each
// window gets what its content needs. The screenshot test checks the same table on the real window.
#include <gtest/gtest.h>

#include "uav/gcs/layout.hpp"

namespace uav::gcs {
namespace {

class DefaultLayoutOn : public testing::TestWithParam<std::pair<float, float>> {};

TEST_P(DefaultLayoutOn, FitsWithNothingOverTheCommandBar) {
  const auto [w, h] = GetParam();
  std::string all;
  for (const std::string& p : CheckLayout(w, h)) all += p + "\n";
  EXPECT_EQ(all, "");
}

INSTANTIATE_TEST_SUITE_P(Displays, DefaultLayoutOn,
                         testing::Values(std::pair{1600.0f, 900.0f}, std::pair{1920.0f, 1080.0f}, std::pair{2560.0f, 1440.0f}));

TEST(DefaultLayout, TheCheckFindsWhatItMustRefuse) {
  // Too small a display: windows below what their content needs.
  EXPECT_FALSE(CheckLayout(1024, 600).empty());
  // Every window the GCS opens is in the table, the protected ones among them.
  for (const char* w : {"Status", "Vehicles", "Pre-arm", "Replay", "Vehicle state", "Video", "Plot", "Command", "Messages",
                        "Obstacles", "Map", "Survey", "Sensing", "Live map", "Mission", "Parameters", "Sticks", "Attitude"})
    EXPECT_NE(FindWindowPlace(w), nullptr) << w;
  EXPECT_TRUE(IsProtectedWindow("Command"));
  EXPECT_TRUE(IsProtectedWindow("Status"));
  EXPECT_FALSE(IsProtectedWindow("Plot"));
}

}  // namespace
}  // namespace uav::gcs
