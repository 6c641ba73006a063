#include "uav/shared/program.hpp"

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
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

namespace {
// "" when `path` can be written, else why not.
std::string OutputFileProblem(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec)) return path + " is a folder, not a file";
  const fs::path folder = fs::path(path).parent_path().empty() ? fs::path(".") : fs::path(path).parent_path();
  if (!fs::is_directory(folder, ec)) return "no folder " + folder.string() + " for " + path;
  if (access(folder.c_str(), W_OK) != 0) return "cannot write into " + folder.string();
  return "";
}
}  // namespace

void CheckOutputFile(const std::string& path, const std::string& option) {
  if (const std::string why = OutputFileProblem(path); !why.empty()) throw std::invalid_argument(option + ": " + why);
}

CLI::Option* OutputFile(CLI::Option* option, const std::string& suffix) {
  option->check(CLI::Validator([suffix](std::string& value) { return OutputFileProblem(value + suffix); },
                               "FILE", "writable"));
  return option;
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
