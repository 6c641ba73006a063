// The manual's reference pages, generated from the code that defines what they describe:
//   parameters.md   the vehicle's and a camera file's parameter schemas (units, limits, when a
//                   change applies)
//   commands.md     the command grammar (the GCS bar and the vehicle's intake)
//   reports.md      the vehicle's state and reports: topic, signal group, every signal
//   mavlink.md      the MAVLink messages (id, CRC_EXTRA, lengths), PX4's modes as the vehicle
//                   reports and accepts them, the MAVLink ids of parameters longer than 16 characters
//   gcs-script.md   the GCS script language (script.hpp's own description) and every widget name
//                   a script can click, type into or set (the panels' RegisterLastItem calls)
// uav-docs-reference --out DIR writes them; --check DIR fails naming each page that differs from
// what the code says now (the test docs.reference_current), with the command that rewrites it.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "uav/shared/command_grammar.hpp"
#include "uav/shared/mavlink_messages.hpp"
#include "uav/gcs/mavlink_commands.hpp"
#include "uav/shared/mavlink_autopilots.hpp"
#include "uav/shared/mavlink_px4.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/reports.hpp"
#include "uav/shared/vehicle_state.hpp"
#include "uav/wire/reports.hpp"

namespace {

namespace fs = std::filesystem;

constexpr const char* kGenerated =
    "<!-- Generated from the code by uav-docs-reference (tests/docs/docs_reference.cpp); do not edit: "
    "cmake --build build --target docs-reference rewrites it. -->\n\n";

std::string Cell(std::string text) {
  std::string out;
  for (char c : text) {
    if (c == '|') out += "\\|";
    else if (c == '\n') out += ' ';
    else out += c;
  }
  return out;
}

std::string Number(double v) { return uav::FormatParameterValue(v); }

const char* ApplyText(uav::ParamApply a) {
  switch (a) {
    case uav::ParamApply::kAtStart: return "at start";
    case uav::ParamApply::kOnGround: return "on the ground";
    case uav::ParamApply::kInFlight: return "in flight";
  }
  return "?";
}

void SchemaTable(std::ostream& out, const uav::ParameterSchema& schema) {
  out << "| name | default | unit | min | max | applies | description |\n|---|---|---|---|---|---|---|\n";
  for (const auto& p : schema.specs) {
    const std::string def = p.default_value ? Number(*p.default_value) : (p.optional ? "(optional)" : "(required)");
    out << "| `" << p.name << "` | " << def << " | " << Cell(p.unit) << " | " << Number(p.min) << " | " << Number(p.max)
        << " | " << ApplyText(p.apply) << " | " << Cell(p.description) << " |\n";
  }
}

std::string ParametersPage() {
  std::ostringstream out;
  out << "# Parameters\n\n" << kGenerated;
  out << "A vehicle file (`resources/vehicles/*.params`, `uav-onboard --params`) and a camera file "
         "(`resources/cameras/*.camera`) set values only: `name  value  # comment`, one a line. The program "
         "declares each parameter once, with its unit, limits and default; a file cannot widen the limits. A "
         "value outside them, a name not declared here or a duplicate is refused, naming the file and line.\n\n"
         "**Applies** says when a change over the link (the Parameters panel, the `param` command) takes "
         "effect: *at start* only from the file or `--param` when the program starts; *on the ground* while "
         "disarmed; *in flight* at once, armed or not. The vehicle refuses a change outside its window and "
         "says why.\n\n";
  out << "## Vehicle (" << uav::VehicleParameterSchema().specs.size() << " parameters)\n\n";
  SchemaTable(out, uav::VehicleParameterSchema());
  out << "\n## Camera file (" << uav::CameraParameterSchema().specs.size() << " parameters)\n\n";
  SchemaTable(out, uav::CameraParameterSchema());
  return out.str();
}

std::string CommandsPage() {
  std::ostringstream out;
  out << "# Commands\n\n" << kGenerated;
  out << "One grammar serves the GCS command bar (it validates while you type, and completes names with Tab) "
         "and the vehicle, which validates again where commands enter. A command is a name and positional "
         "decimal arguments; names are case-insensitive. A command outside these limits is refused with the "
         "argument, the limit and why. Longest line: " << uav::kMaxCommandLength << " characters.\n\n";
  out << "| command | arguments | what it does |\n|---|---|---|\n";
  for (const auto& c : uav::CommandSpecs()) {
    std::string args;
    for (const auto& a : c.args) args += std::string(args.empty() ? "" : " ") + "`" + a.name + "`";
    out << "| `" << c.name << "` | " << (args.empty() ? "none" : args) << " | " << Cell(c.help) << " |\n";
  }
  out << "\n## Arguments and their limits\n\n| command | argument | range | why |\n|---|---|---|---|\n";
  for (const auto& c : uav::CommandSpecs()) {
    for (const auto& a : c.args) {
      std::string range;
      if (a.parameter_name) range = "a vehicle parameter's name ([parameters](parameters.md))";
      else if (std::string(c.name) == "param") range = "the named parameter's limits";
      else if (a.keywords) range = std::string("`") + a.keywords + "` (or 0, 1, ...)";
      else range = Number(a.min) + " to " + Number(a.max) + (a.integer ? ", whole" : "");
      out << "| `" << c.name << "` | `" << a.name << "` | " << Cell(range) << " | " << Cell(a.why) << " |\n";
    }
  }
  return out.str();
}

template <class T>
void SignalTable(std::ostream& out, const std::vector<uav::Signal<T>>& table, std::string_view group) {
  out << "| signal | unit | frame | message field |\n|---|---|---|---|\n";
  for (const auto& s : table) {
    const std::string name = group.empty() ? std::string(s.def.name) : std::string(group) + "." + std::string(s.def.name);
    out << "| `" << name << "` | " << (s.def.unit.empty() ? "" : std::string(s.def.unit)) << " | "
        << std::string(s.def.frame) << " | " << (s.def.field.empty() ? "(derived)" : "`" + std::string(s.def.field) + "`")
        << " |\n";
  }
}

std::string ReportsPage() {
  std::ostringstream out;
  out << "# The vehicle's reports and their signals\n\n" << kGenerated;
  out << "Every message the vehicle publishes goes on the LCM channel `<VEHICLE>/<TOPIC>`. A signal is a named "
         "number with a unit read from one message: the GCS's telemetry tree, its plots, its scripts "
         "(`assert STATE.alt > 9`) and its CSV export use these names, and the vehicle's flight log has a "
         "column of each. SI units inside; the GCS shows angles in degrees. Frames: `N` north-east-down from "
         "home, `B` body forward-right-down, `WGS84` geodetic.\n\n";
  out << "## State (topic `" << uav::Topic::kState.name << "`, signals without a group)\n\n";
  SignalTable(out, uav::VehicleStateSignals(), "");
  uav::ForEachType(uav::VehicleReports{}, [&](auto* tag) {
    using T = std::remove_pointer_t<decltype(tag)>;
    const auto& table = uav::ReportSignals<T>::Table();
    out << "\n## " << uav::Report<T>::kTopic.name << "\n\nTopic `" << uav::Report<T>::kTopic.name << "`";
    if (table.empty()) {
      out << "; no signals (drawn by the GCS's panels, not plotted).\n";
      return;
    }
    out << ", signal group `" << uav::ReportSignals<T>::kGroup << "`.\n\n";
    SignalTable(out, table, uav::ReportSignals<T>::kGroup);
  });
  return out.str();
}

std::string MavlinkPage() {
  std::ostringstream out;
  out << "# MAVLink\n\n" << kGenerated
      << "What `uav-onboard --mavlink` speaks ([connecting a MAVLink GCS](../user-guide/mavlink.md)), and how "
         "`uav-gcs --mavlink` flies PX4 and ArduPilot vehicles. Each "
         "message is declared once (`shared/include/uav/shared/mavlink_messages.def`); its wire order, CRC_EXTRA "
         "and lengths follow from the declaration and are checked against npm's `mavlink-mappings` "
         "(`tests/mavlink/tables.js`).\n\n";
  out << "## Messages (" << uav::mavlink::Layouts().size() << ")\n\n"
      << "| id | name | CRC_EXTRA | payload bytes | extension fields |\n|---|---|---|---|---|\n";
  for (const auto& l : uav::mavlink::Layouts()) {
    std::string ext;
    for (const auto& f : l.fields)
      if (f.extension) ext += (ext.empty() ? "`" : ", `") + f.name + "`";
    out << "| " << l.id << " | `" << l.name << "` | " << int{l.crc_extra} << " | " << l.base_length;
    if (l.length != l.base_length) out << " (" << l.length << " with extensions)";
    out << " | " << (ext.empty() ? "-" : ext) << " |\n";
  }
  out << "\n## Flight modes\n\nThe vehicle presents itself as PX4 (HEARTBEAT.autopilot 12), so that "
         "QGroundControl allows mode changes and guided commands. The heartbeat reports the mode of the task "
         "being flown; DO_SET_MODE to a mode asks the vehicle for its command, through the same checks as ours. "
         "A mode not listed is refused (MAV_RESULT_UNSUPPORTED).\n\n"
      << "| PX4 mode | custom_mode | reported while | DO_SET_MODE asks |\n|---|---|---|---|\n";
  for (const auto& m : uav::mavlink::Px4Modes()) {
    std::string tasks;
    for (uav::Task t : m.tasks) tasks += (tasks.empty() ? "`" : ", `") + std::string(uav::Name(t)) + "`";
    char hex[16];
    std::snprintf(hex, sizeof hex, "0x%08x", static_cast<unsigned>(m.custom_mode()));
    out << "| " << m.name << " | " << hex << " | " << tasks << " | `" << m.command << "` |\n";
  }
  out << "\n## Our GCS and PX4 or ArduPilot vehicles\n\n"
         "`uav-gcs --mavlink ENDPOINT` ([flying PX4 and ArduPilot from our GCS](../user-guide/mavlink-vehicles.md)) "
         "recognises the autopilot from HEARTBEAT.autopilot and HEARTBEAT.type, shows its modes by name and as our "
         "tasks, reads its parameters in its encoding (PX4 byte-wise, ArduPilot C-cast; AUTOPILOT_VERSION's "
         "capability bits win when sent), puts ArduPilot's home at item 0 of an upload and drops it from a "
         "download, and sends each command of the command bar as below (`gcs/link/src/mavlink_commands.cpp`).\n\n"
         "### Commands\n\n| command | PX4 | ArduCopter | ArduPlane | ArduPlane VTOL |\n|---|---|---|---|---|\n";
  const uav::GeodeticPoint home{1.2966, 103.7764, 15.0};
  using uav::mavlink::Autopilot;
  for (const char* text : {"arm", "disarm", "emergency_stop", "takeoff 10", "hover", "land", "return", "goto 20 10 15",
                           "mission", "resume", "follow", "transition fw", "param NAME VALUE", "track 1"}) {
    out << "| `" << text << "` |";
    for (Autopilot a : {Autopilot::kPx4, Autopilot::kArduCopter, Autopilot::kArduPlane, Autopilot::kArduPlaneVtol}) {
      if (std::string(text) == "param NAME VALUE") {
        out << " PARAM_SET, answered by PARAM_VALUE |";
        continue;
      }
      const uav::gcs::MavlinkPlan plan =
          uav::gcs::PlanMavlinkCommand(text, a, a == Autopilot::kArduPlaneVtol, home);
      std::string cell;
      for (const auto& step : plan.steps) cell += (cell.empty() ? "" : ", then ") + step.what;
      out << " " << (plan.refusal.empty() ? cell : "refused: " + plan.refusal) << " |";
    }
    out << "\n";
  }
  out << "\nA command is done at its last step's ACCEPTED, or, for those that fly somewhere, when the vehicle "
         "gets there (the altitude, the position within 1.5 m, landed and disarmed, the mission's last item).\n";
  for (Autopilot a : {Autopilot::kPx4, Autopilot::kArduCopter, Autopilot::kArduPlane}) {
    out << "\n### " << uav::mavlink::Name(a) << (a == Autopilot::kArduPlane ? " (and ArduPlane VTOL)" : "")
        << " modes\n\n| mode | custom_mode | shown as task |\n|---|---|---|\n";
    for (const auto& m : uav::mavlink::ModesOf(a)) {
      char number[16];
      std::snprintf(number, sizeof number, a == Autopilot::kPx4 ? "0x%08x" : "%u", static_cast<unsigned>(m.custom_mode));
      out << "| " << m.name << " | " << number << " | " << (m.task ? "`" + std::string(uav::Name(*m.task)) + "`" : "-")
          << " |\n";
    }
  }
  out << "\n## Parameter ids\n\nPARAM_VALUE names a parameter in 16 characters. A longer name is sent as its "
         "first 11 characters, `_` and 4 hex digits of a hash of the whole name: the id depends on the name "
         "alone, so it does not change as parameters are added. Every other parameter keeps its name "
         "([parameters](parameters.md)).\n\n| parameter | MAVLink id |\n|---|---|\n";
  for (const auto& p : uav::VehicleParameterSchema().specs)
    if (p.name.size() > 16) out << "| `" << p.name << "` | `" << uav::mavlink::ParamIdOf(p.name) << "` |\n";
  return out.str();
}

std::string ReadFile(const fs::path& p) {
  std::ifstream in(p);
  if (!in) throw std::runtime_error("cannot read " + p.string());
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

// script.hpp's leading comment: the language as its parser documents it.
std::string ScriptLanguage(const fs::path& header) {
  std::istringstream in(ReadFile(header));
  std::string line, out;
  bool started = false;
  while (std::getline(in, line)) {
    if (line.rfind("// Operator scripts", 0) == 0) started = true;
    if (!started) continue;
    if (line.rfind("//", 0) != 0) break;
    out += line.size() > 3 ? line.substr(3) : "";
    out += '\n';
  }
  if (out.empty()) throw std::runtime_error(header.string() + ": no leading comment describing the script language");
  return out;
}

// A RegisterLastItem(ctx, EXPR) label as a pattern: string literals as written, every other part
// of the expression as <the expression> (std::to_string(n) as <n>).
std::string LabelPattern(const std::string& expr) {
  std::string out;
  std::size_t depth = 0, start = 0;
  std::vector<std::string> parts;
  bool quoted = false;
  for (std::size_t i = 0; i <= expr.size(); ++i) {
    const char c = i < expr.size() ? expr[i] : '+';
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    if (c == '(') ++depth;
    if (c == ')') --depth;
    if (c == '+' && depth == 0) {
      parts.push_back(expr.substr(start, i - start));
      start = i + 1;
    }
  }
  const std::regex literal(R"re(^\s*(?:std::string\()?"([^"]*)"\)?\s*$)re");
  const std::regex to_string(R"re(^\s*std::to_string\((.*)\)\s*$)re");
  for (const std::string& part : parts) {
    std::smatch m;
    if (std::regex_match(part, m, literal)) {
      out += m[1].str();
    } else if (std::regex_match(part, m, to_string)) {
      out += "<" + m[1].str() + ">";
    } else {
      out += "<" + std::regex_replace(std::regex_replace(part, std::regex(R"(^\s+|\s+$)"), ""), std::regex(R"(\s+)"), " ") + ">";
    }
  }
  return out;
}

std::string ScriptPage(const fs::path& source_dir) {
  std::ostringstream out;
  out << "# GCS scripts\n\n" << kGenerated;
  out << "`uav-gcs --script FILE` (headless with `--headless`) drives the real panels with real mouse and "
         "keyboard input, one step a line, and exits 0 only when every step passed. The integration tests and "
         "`uav-demo` are such scripts (`tests/integration/*.gcs`).\n\n## Steps and conditions\n\n```\n"
      << ScriptLanguage(source_dir / "gcs/model/include/uav/gcs/script.hpp") << "```\n\n";
  out << "## Widget names\n\n`click`, `set` and `type` address a widget by the name its panel registers. Parts "
         "in `<angle brackets>` are filled in at run time (a parameter's name, an item's number, a vehicle's "
         "id). `tick SIGNAL` clicks `tick:GROUP.SIGNAL`; `select ID` clicks `vehicle:ID`.\n\n";
  std::map<std::string, std::set<std::string>> by_panel;
  const std::regex call(R"re(RegisterLastItem\(ctx,\s*((?:[^;()]|\([^;()]*\))+)\);)re");
  // The number fields register themselves (number_field.hpp): NumberField(ctx, NAME, ...).
  const std::regex number_field(R"re(NumberField\(ctx,\s*((?:[^;(),]|\([^;()]*\))+),)re");
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(source_dir / "gcs/ui/src"))
    if (e.path().extension() == ".cpp") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  // A name passed through a helper (Field(ctx, ..., "survey:altitude", ...)) is a literal of the
  // names' form, "panel:what"; a name that is wholly a variable (<id>) is known only there.
  const std::regex name_literal(R"re("([a-z_]+:[a-z0-9_:]*[a-z0-9])")re");
  for (const auto& f : files) {
    const std::string text = ReadFile(f);
    auto& names = by_panel[f.stem().string()];
    for (const std::regex* r : {&call, &number_field})
      for (auto it = std::sregex_iterator(text.begin(), text.end(), *r); it != std::sregex_iterator(); ++it) {
        const std::string pattern = LabelPattern((*it)[1].str());
        if (!(pattern.front() == '<' && pattern.back() == '>' && pattern.find('<', 1) == std::string::npos)) names.insert(pattern);
      }
    for (auto it = std::sregex_iterator(text.begin(), text.end(), name_literal); it != std::sregex_iterator(); ++it)
      names.insert((*it)[1].str());
    if (names.empty()) by_panel.erase(f.stem().string());
  }
  if (by_panel.empty()) throw std::runtime_error("no RegisterLastItem calls under " + (source_dir / "gcs/ui/src").string());
  out << "| panel source | widget names |\n|---|---|\n";
  for (const auto& [panel, labels] : by_panel) {
    std::string cell;
    for (const auto& l : labels) cell += std::string(cell.empty() ? "" : ", ") + "`" + Cell(l) + "`";
    out << "| `" << panel << "` | " << cell << " |\n";
  }
  return out.str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-docs-reference: the manual's reference pages (docs/reference), generated from the code"};
  std::string out_dir, check_dir, source_dir;
  auto* out_opt = cli.add_option("--out", out_dir, "write the pages into this folder");
  cli.add_option("--check", check_dir, "compare the pages in this folder with the code; exit 1 naming each stale one")
      ->excludes(out_opt);
  cli.add_option("--source", source_dir, "the project's source tree (for the GCS panels and script.hpp)")->required();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (out_dir.empty() && check_dir.empty()) {
    std::cerr << "uav-docs-reference: give --out DIR or --check DIR\n";
    return 2;
  }
  std::map<std::string, std::string> pages;
  try {
    pages = {{"parameters.md", ParametersPage()},
             {"commands.md", CommandsPage()},
             {"reports.md", ReportsPage()},
             {"mavlink.md", MavlinkPage()},
             {"gcs-script.md", ScriptPage(source_dir)}};
  } catch (const std::exception& e) {
    std::cerr << "uav-docs-reference: " << e.what() << "\n";
    return 2;
  }
  if (!out_dir.empty()) {
    fs::create_directories(out_dir);
    for (const auto& [name, text] : pages) {
      const fs::path tmp = fs::path(out_dir) / (name + ".tmp");
      std::ofstream(tmp) << text;
      fs::rename(tmp, fs::path(out_dir) / name);
    }
    std::cout << "uav-docs-reference: wrote " << pages.size() << " pages into " << out_dir << "\n";
    return 0;
  }
  int stale = 0;
  for (const auto& [name, text] : pages) {
    const fs::path p = fs::path(check_dir) / name;
    std::string have;
    try {
      have = ReadFile(p);
    } catch (const std::exception&) {
    }
    if (have != text) {
      std::cerr << "uav-docs-reference: " << p.string() << " is stale (the code now says otherwise)\n";
      ++stale;
    }
  }
  if (stale) {
    std::cerr << "uav-docs-reference: " << stale << " stale page(s); rewrite them with: cmake --build build --target docs-reference\n";
    return 1;
  }
  std::cout << "uav-docs-reference: " << pages.size() << " pages current\n";
  return 0;
}
