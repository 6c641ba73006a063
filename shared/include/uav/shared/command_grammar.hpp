#pragma once
// The command language of the task manager (thesis 2.3.2: "hover", "track 3"): a name and
// positional numeric arguments. One grammar, used by the GCS command bar to validate while the
// operator types and by the vehicle to validate where commands enter.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace uav {

enum class CommandId { kArm, kDisarm, kTakeoff, kHover, kLand, kGoto, kTrack, kMission, kReturn, kChirp, kFollow, kGps, kParam,
                       kEmergencyStop, kResume, kSticks, kTransition };

struct ArgumentSpec {
  const char* name;   // e.g. "alt_m"
  double min;         // inclusive
  double max;         // inclusive
  const char* why;    // why the limit is where it is
  bool integer = false;  // whole numbers only (a path number)
  // A word naming a vehicle parameter (VehicleParameterSchema), not a number; the next argument
  // is its value, held to that parameter's limits instead of min/max.
  bool parameter_name = false;
  // Space-separated words the argument may be given as ("mc fw"): each stands for its position
  // (0, 1, ...), and the canonical text uses the word.
  const char* keywords = nullptr;
};

struct CommandSpec {
  CommandId id;
  const char* name;
  const char* help;
  std::vector<ArgumentSpec> args;
};

// Longest command line accepted, in characters.
constexpr std::size_t kMaxCommandLength = 256;

const std::vector<CommandSpec>& CommandSpecs();
const CommandSpec& SpecOf(CommandId id);

struct Command {
  CommandId id;
  std::vector<double> args;  // validated: finite, within the spec's limits
  std::string parameter;     // `param`: the parameter named (a declared vehicle parameter)
  std::string Name() const;
  std::string Text() const;  // canonical text, parses back to the same command
};

struct ParseResult {
  std::optional<Command> command;
  std::string error;  // names what was wrong when command is empty
  bool ok() const { return command.has_value(); }
};

// Parses and validates one command line. Never throws.
ParseResult ParseCommand(std::string_view line);

// Names of commands that start with the first word of `partial` (for completion).
std::vector<std::string> CompleteCommandName(std::string_view partial);

// "takeoff <alt_m 1..120>" style hint for the command named by the first word, or "" if none.
std::string ArgumentHint(std::string_view line);

}  // namespace uav
