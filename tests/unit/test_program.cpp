// What every program answers the same way: its version, where its data is, its progress in a log.
#include <gtest/gtest.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "uav/shared/program.hpp"
#include "uav/shared/progress_bar.hpp"

namespace {

TEST(Program, VersionNamesTheReleaseAndTheCommit) {
  EXPECT_TRUE(std::regex_match(uav::VersionText(), std::regex(R"(\d+\.\d+\.\d+ \(commit ([0-9a-f]{12}(-modified)?|unknown)\))")))
      << uav::VersionText();
}

TEST(Program, VersionFlagPrintsProgramAndVersionAndStops) {
  CLI::App app{"test"};
  double x = 0;
  app.add_option("--x", x);
  uav::PrepareCommandLine(app);
  const char* argv[] = {"prog", "--version"};
  try {
    app.parse(2, argv);
    FAIL() << "--version did not stop the parse";
  } catch (const CLI::CallForVersion& e) {
    std::ostringstream out, err;
    EXPECT_EQ(app.exit(e, out, err), 0);
    EXPECT_NE(out.str().find(uav::VersionText()), std::string::npos) << out.str();
  }
  // The decimal-only rule still holds beside it.
  const char* bad[] = {"prog", "--x", "nan"};
  EXPECT_THROW(app.parse(3, bad), CLI::ValidationError);
}

TEST(Program, ResourceDirFollowsTheEnvironmentThenTheBuildTree) {
  ::unsetenv("UAV_RESOURCE_DIR");
  EXPECT_TRUE(std::filesystem::exists(uav::ResourcePath("vehicles/x650.params"))) << uav::ResourceDir();
  ::setenv("UAV_RESOURCE_DIR", "/opt/elsewhere", 1);
  EXPECT_EQ(uav::ResourcePath("cameras/a.camera"), "/opt/elsewhere/cameras/a.camera");
  ::unsetenv("UAV_RESOURCE_DIR");
}

// Into a file, the bar writes a plain line every 10 %, never a carriage-return redraw.
TEST(ProgressBar, IntoALogWritesAFewPlainLines) {
  const std::string path = testing::TempDir() + "progress_log.txt";
  std::fflush(stderr);
  const int saved = dup(STDERR_FILENO);
  FILE* file = std::fopen(path.c_str(), "w");
  ASSERT_NE(file, nullptr);
  dup2(fileno(file), STDERR_FILENO);
  {
    uav::ProgressBar bar(1000);
    for (std::size_t i = 0; i <= 1000; ++i) bar.Update(i, "frame");
    bar.Finish(1000);
  }
  std::fflush(stderr);
  dup2(saved, STDERR_FILENO);
  close(saved);
  std::fclose(file);
  std::ifstream in(path);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text.find('\r'), std::string::npos);
  const auto lines = std::count(text.begin(), text.end(), '\n');
  EXPECT_GE(lines, 10);
  EXPECT_LE(lines, 12) << text;
  // The last line says it is complete, once.
  EXPECT_NE(text.find("1000/1000 (100 %)"), std::string::npos) << text;
  EXPECT_EQ(text.find("1000/1000", text.find("1000/1000") + 1), std::string::npos) << text;
}

}  // namespace
