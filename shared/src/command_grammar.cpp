#include "uav/shared/command_grammar.hpp"

#include <algorithm>

#include "uav/shared/decimal.hpp"
#include "uav/shared/parameters.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace uav {
namespace {

std::vector<std::string> SplitWords(std::string_view s) {
  std::vector<std::string> words;
  std::string cur;
  for (char c : s) {
    if (std::isspace(static_cast<unsigned char>(c))) {
      if (!cur.empty()) words.push_back(std::move(cur)), cur.clear();
    } else {
      cur.push_back(c);
    }
  }
  if (!cur.empty()) words.push_back(std::move(cur));
  return words;
}

std::string Lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string FormatNumber(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

const CommandSpec* FindSpec(const std::string& name) {
  for (const auto& s : CommandSpecs())
    if (name == s.name) return &s;
  return nullptr;
}

}  // namespace

const std::vector<CommandSpec>& CommandSpecs() {
  // Altitudes are above home, positive up. 120 m is the usual legal ceiling for small UAVs
  // (EU open category, FAA part 107); 1 m keeps the rotors out of ground effect.
  static const std::vector<CommandSpec> kSpecs = {
      {CommandId::kArm, "arm", "enable the rotors (on the ground)", {}},
      {CommandId::kDisarm, "disarm", "stop the rotors (on the ground only)", {}},
      {CommandId::kTakeoff, "takeoff", "climb vertically to alt_m above home",
       {{"alt_m", 1.0, 120.0, "1 m clears ground effect, 120 m is the legal ceiling"}}},
      {CommandId::kHover, "hover", "hold the current position", {}},
      {CommandId::kLand, "land", "descend vertically and disarm on touchdown", {}},
      {CommandId::kGoto, "goto", "fly to north_m east_m from home at alt_m above home",
       {{"north_m", -1000.0, 1000.0, "stays within the 1 km radio range"},
        {"east_m", -1000.0, 1000.0, "stays within the 1 km radio range"},
        {"alt_m", 1.0, 120.0, "1 m clears ground effect, 120 m is the legal ceiling"}}},
      {CommandId::kTrack, "track", "fly stored path N (waypoints/paths/track_N.waypoints)",
       {{"N", 1.0, 99.0, "paths are numbered 1 to 99", true}}},
      {CommandId::kMission, "mission", "fly the mission uploaded from the GCS", {}},
      {CommandId::kResume, "resume",
       "fly the interrupted mission on from where it stopped (a survey from the start of the capture leg it was on)", {}},
      {CommandId::kReturn, "return", "fly home at a safe altitude and land", {}},
      // PX4's Position mode from the GCS's sticks (a gamepad or the virtual sticks).
      {CommandId::kSticks, "sticks",
       "fly by the GCS's sticks: velocity and yaw rate while the deadman is held, holding when it is released", {}},
      {CommandId::kFollow, "follow", "keep the tracked target centred from a set distance and height (hover stops)", {}},
      // System identification (thesis 2.4.5): a linear chirp (Eq. 2.14) added to one servo
      // channel while hovering; the flight log records it for uav-sysid.
      {CommandId::kChirp, "chirp", "while hovering, add a chirp (Eq. 2.14) to servo channel 1 aileron, 2 elevator, "
       "3 throttle or 4 rudder, sweeping f0_hz to f1_hz",
       {{"channel", 1.0, 4.0, "1 aileron, 2 elevator, 3 throttle, 4 rudder (thesis Table 2.3)", true},
        {"amplitude", 0.01, 0.3, "a larger perturbation leaves the linear range around hover (thesis 2.4.5)"},
        {"f0_hz", 0.05, 5.0, "start: the thesis begins with long-period swings"},
        {"f1_hz", 0.1, 10.0, "end: above 10 Hz the servos and the 50 Hz loop cannot follow"},
        {"duration_s", 5.0, 120.0, "long enough for the lowest frequency, short enough to stay in view"}}},
      // A simulator fault (a real receiver cannot be switched off from the ground): flying where
      // GPS fails is what visual odometry is for (thesis ch. 5).
      {CommandId::kGps, "gps", "simulator fault: 0 takes the GPS fix away, 1 gives it back",
       {{"on", 0.0, 1.0, "0 no fix (jammed, indoors), 1 fix", true}}},
      // QGroundControl's emergency stop, PX4's kill: the last resort when a vehicle flies away or
      // into people. The GCS asks twice before it sends it.
      {CommandId::kEmergencyStop, "emergency_stop", "stop the motors at once, in flight too: the vehicle falls", {}},
      // Parameters over the link (as QGroundControl's parameter editor): the vehicle applies the
      // value at once where that is safe and answers with the value it now uses.
      // A tail-sitter's transitions (thesis 2.6), as QGroundControl's VTOL transition buttons and
      // PX4's MAV_CMD_DO_VTOL_TRANSITION.
      {CommandId::kTransition, "transition", "tail-sitter: fw onto the wing (from hover), mc back to hover (from the wing)",
       {{"to", 0.0, 1.0, "mc: hover on the rotor, fw: cruise on the wing", true, false, "mc fw"}}},
      {CommandId::kParam, "param", "set vehicle parameter name to value (its unit, within its limits)",
       {{"name", 0.0, 0.0, "a parameter of the vehicle file (uav-onboard --list-params)", false, true},
        {"value", 0.0, 0.0, "the parameter's own limits"}}},
  };
  return kSpecs;
}

const CommandSpec& SpecOf(CommandId id) {
  for (const auto& s : CommandSpecs())
    if (s.id == id) return s;
  return CommandSpecs().front();  // unreachable: every id has a spec
}

std::string Command::Name() const { return SpecOf(id).name; }

namespace {
// The keyword of value `v` in a spec's space-separated list, or "" when there is none.
std::string Keyword(const char* keywords, double v) {
  if (!keywords || v != std::floor(v) || v < 0) return "";
  std::istringstream words(keywords);
  std::string w;
  for (int i = 0; words >> w; ++i)
    if (i == static_cast<int>(v)) return w;
  return "";
}
std::optional<double> KeywordValue(const char* keywords, const std::string& word) {
  if (!keywords) return std::nullopt;
  std::istringstream words(keywords);
  std::string w;
  for (int i = 0; words >> w; ++i)
    if (w == word) return i;
  return std::nullopt;
}
}  // namespace

std::string Command::Text() const {
  std::string t = Name();
  if (!parameter.empty()) t += " " + parameter;
  const CommandSpec& spec = SpecOf(id);
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string word = i < spec.args.size() ? Keyword(spec.args[i].keywords, args[i]) : "";
    t += " " + (word.empty() ? FormatNumber(args[i]) : word);
  }
  return t;
}

ParseResult ParseCommand(std::string_view line) {
  ParseResult r;
  if (line.size() > kMaxCommandLength) {
    r.error = "command is " + std::to_string(line.size()) + " characters long, the limit is " +
              std::to_string(kMaxCommandLength);
    return r;
  }
  for (char c : line) {
    if (static_cast<unsigned char>(c) < 0x20 && !std::isspace(static_cast<unsigned char>(c))) {
      r.error = "command contains a control character";
      return r;
    }
  }
  const auto words = SplitWords(line);
  if (words.empty()) {
    r.error = "empty command";
    return r;
  }
  const std::string name = Lower(words[0]);
  const CommandSpec* spec = FindSpec(name);
  if (!spec) {
    r.error = "unknown command '" + words[0] + "'";
    return r;
  }
  const std::size_t given = words.size() - 1;
  if (given < spec->args.size()) {
    r.error = name + ": missing argument " + spec->args[given].name + " (" + ArgumentHint(name) + ")";
    return r;
  }
  if (given > spec->args.size()) {
    r.error = name + ": unexpected extra argument '" + words[spec->args.size() + 1] + "' (" +
              ArgumentHint(name) + ")";
    return r;
  }
  Command cmd{spec->id, {}, {}};
  const ParameterSpec* parameter = nullptr;
  for (std::size_t i = 0; i < spec->args.size(); ++i) {
    const ArgumentSpec& a = spec->args[i];
    const std::string& w = words[i + 1];
    if (a.parameter_name) {
      parameter = VehicleParameterSchema().Find(w);
      if (!parameter) {
        r.error = name + ": unknown parameter '" + w + "' (uav-onboard --list-params lists them)";
        return r;
      }
      cmd.parameter = w;
      continue;
    }
    if (const std::optional<double> keyword = KeywordValue(a.keywords, Lower(w))) {
      cmd.args.push_back(*keyword);
      continue;
    }
    const std::optional<double> parsed = ParseDecimal(w);
    if (!parsed && a.keywords) {
      r.error = name + ": argument " + a.name + " must be one of '" + a.keywords + "', got '" + w + "'";
      return r;
    }
    if (!parsed) {
      // strtod would take "nan", "inf", "1e400" and "0x10": say why those are refused too.
      char* end = nullptr;
      const double v = std::strtod(w.c_str(), &end);
      const bool numeric = end != w.c_str() && *end == '\0';
      r.error = name + ": argument " + a.name +
                (!numeric ? " is not a number: '" : !std::isfinite(v) ? " is not a finite number: '"
                                                                      : " is not a decimal number (digits only, no hexadecimal): '") +
                w + "'";
      return r;
    }
    const double v = *parsed;
    if (a.integer && v != std::floor(v)) {
      r.error = name + ": argument " + a.name + " must be a whole number: '" + w + "'";
      return r;
    }
    if (parameter) {
      if (v < parameter->min || v > parameter->max) {
        r.error = name + ": " + parameter->name + " = " + w + " is outside [" + FormatNumber(parameter->min) + ", " +
                  FormatNumber(parameter->max) + "] " + parameter->unit;
        return r;
      }
    } else if (v < a.min || v > a.max) {
      r.error = name + ": argument " + a.name + " = " + w + " is outside [" + FormatNumber(a.min) +
                ", " + FormatNumber(a.max) + "]: " + a.why;
      return r;
    }
    cmd.args.push_back(v);
  }
  r.command = std::move(cmd);
  return r;
}

std::vector<std::string> CompleteCommandName(std::string_view partial) {
  const auto words = SplitWords(partial);
  const std::string prefix = words.empty() ? std::string() : Lower(words[0]);
  std::vector<std::string> out;
  for (const auto& s : CommandSpecs())
    if (std::string_view(s.name).substr(0, prefix.size()) == prefix) out.emplace_back(s.name);
  return out;
}

std::string ArgumentHint(std::string_view line) {
  const auto words = SplitWords(line);
  if (words.empty()) return "";
  const CommandSpec* spec = FindSpec(Lower(words[0]));
  if (!spec) return "";
  std::string h = spec->name;
  const ParameterSpec* parameter = nullptr;
  for (std::size_t i = 0; i < spec->args.size(); ++i) {
    const ArgumentSpec& a = spec->args[i];
    if (a.parameter_name) {
      parameter = words.size() > i + 1 ? VehicleParameterSchema().Find(words[i + 1]) : nullptr;
      h += std::string(" <") + (parameter ? parameter->name : std::string(a.name)) + ">";
    } else if (parameter) {
      h += " <" + FormatNumber(parameter->min) + ".." + FormatNumber(parameter->max) + " " + parameter->unit + ">";
    } else if (a.keywords) {
      std::string choices = a.keywords;
      std::replace(choices.begin(), choices.end(), ' ', '|');
      h += " <" + choices + ">";
    } else if (spec->args.size() > i && i > 0 && spec->args[i - 1].parameter_name) {
      h += std::string(" <") + a.name + ">";
    } else {
      h += std::string(" <") + a.name + " " + FormatNumber(a.min) + ".." + FormatNumber(a.max) + ">";
    }
  }
  return h;
}

}  // namespace uav
