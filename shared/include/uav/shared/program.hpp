#pragma once
// What every program of the product answers the same way: --help (CLI11's), --version (the
// version and the commit it was built from) and numbers in decimal only (uav/shared/decimal.hpp);
// and where its shipped data (vehicle files, cameras, scenes) is found, in the build tree or
// installed.
#include <string>

namespace CLI {
class App;
class Option;
}

namespace uav {

// "0.2.0 (commit 1a2b3c4d5e6f)"; "(commit unknown)" when built outside a git checkout.
const std::string& VersionText();

// Adds --version ("NAME VERSION (commit ...)", NAME the program's file name) and makes every
// number-taking option decimal-only (RequireDecimalNumbers). Call after the options are declared,
// before parsing.
void PrepareCommandLine(CLI::App& app);

// Before long work: a file the program will write at the end can be written there. Throws
// std::invalid_argument naming the option and the path ("--json: no folder /x/y for
// /x/y/out.json") when its folder is missing or not writable, or the path is a folder.
void CheckOutputFile(const std::string& path, const std::string& option);
// The same check when the command line is parsed, for an option naming a file the program
// writes (or, with `suffix`, a prefix: OUT + ".tif"): a bad path is refused before any work.
// Returns `option`: OutputFile(cli.add_option("--json", path, "..."));
CLI::Option* OutputFile(CLI::Option* option, const std::string& suffix = "");

// The folder of the shipped data (vehicles/, cameras/, scenes/, areas/): $UAV_RESOURCE_DIR when
// set; else, for an installed program (PREFIX/bin/NAME), PREFIX/share/uav when it exists; else
// the source tree's resources/ this build was made from.
std::string ResourceDir();
// ResourceDir() + "/" + relative.
std::string ResourcePath(const std::string& relative);

}  // namespace uav
