#include "uav/shared/program.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "uav/shared/decimal.hpp"

namespace uav {

extern const char* const kVersion;  // generated: shared/cmake/version.cmake
extern const char* const kCommit;

namespace {

std::filesystem::path ExecutablePath() {
  std::error_code ec;
  const auto p = std::filesystem::read_symlink("/proc/self/exe", ec);
  return ec ? std::filesystem::path() : p;
}

}  // namespace

const std::string& VersionText() {
  static const std::string kText = std::string(kVersion) + " (commit " + kCommit + ")";
  return kText;
}

void PrepareCommandLine(CLI::App& app) {
  app.set_version_flag("--version", [] {
    const std::string name = ExecutablePath().filename().string();
    return (name.empty() ? std::string("uav") : name) + " " + VersionText();
  });
  RequireDecimalNumbers(app);
}

void CheckOutputFile(const std::string& path, const std::string& option) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw std::invalid_argument(option + ": " + path + " is a folder, not a file");
  const fs::path folder = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(folder, ec)) throw std::invalid_argument(option + ": no folder " + folder.string() + " for " + path);
  if (access(folder.c_str(), W_OK) != 0) throw std::invalid_argument(option + ": cannot write into " + folder.string());
}

std::string ResourceDir() {
  if (const char* env = std::getenv("UAV_RESOURCE_DIR"); env && *env) return env;
  const auto exe = ExecutablePath();
  if (!exe.empty()) {
    const auto installed = exe.parent_path().parent_path() / "share" / "uav";
    std::error_code ec;
    if (std::filesystem::is_directory(installed / "vehicles", ec)) return installed.string();
  }
  return UAV_SOURCE_RESOURCE_DIR;
}

std::string ResourcePath(const std::string& relative) { return ResourceDir() + "/" + relative; }

}  // namespace uav
