// What every program answers the same way: its version, where its data is, its progress in a log.
#include <gtest/gtest.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <algorithm>

#include "uav/shared/program.hpp"
#include "uav/shared/progress_bar.hpp"

namespace {

// "0.1.0 (commit 1a2b3c4d5e6f)", "-modified" after it for a tree with changes, or "unknown".
TEST(Program, VersionNamesTheReleaseAndTheCommit) {
  const std::string v = uav::VersionText();
  const auto space = v.find(' ');
  ASSERT_NE(space, std::string::npos) << v;
  const std::string release = v.substr(0, space), commit = v.substr(space);
  EXPECT_EQ(std::count(release.begin(), release.end(), '.'), 2) << v;
  EXPECT_EQ(release.find_first_not_of("0123456789."), std::string::npos) << v;
  ASSERT_EQ(commit.rfind(" (commit ", 0), 0u) << v;
  std::string hash = commit.substr(9, commit.size() - 10);
  if (hash.size() > 9 && hash.compare(hash.size() - 9, 9, "-modified") == 0) hash.resize(hash.size() - 9);
  EXPECT_TRUE(hash == "unknown" || (hash.size() == 12 && hash.find_first_not_of("0123456789abcdef") == std::string::npos)) << v;
  EXPECT_EQ(commit.back(), ')') << v;
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

namespace {

// An output that cannot be written is said before the work, naming the option and the path.
TEST(Program, OutputFilesAreCheckedBeforeTheWork) {
  const std::string dir = testing::TempDir();
  EXPECT_NO_THROW(uav::CheckOutputFile(dir + "/out.json", "--json"));
  EXPECT_NO_THROW(uav::CheckOutputFile("out.json", "--json"));  // the working folder
  try {
    uav::CheckOutputFile(dir + "/missing/out.json", "--json");
    FAIL() << "a missing folder was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--json: no folder " + dir + "/missing for " + dir + "/missing/out.json"),
              std::string::npos) << e.what();
  }
  EXPECT_THROW(uav::CheckOutputFile(dir, "--plot"), std::invalid_argument);  // a folder, not a file
}

}  // namespace
