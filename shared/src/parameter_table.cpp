#include "uav/shared/parameter_table.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <set>
#include <sstream>
#include <stdexcept>

#include "uav/shared/decimal.hpp"

namespace uav {
namespace {

std::vector<std::string> Split(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == separator) out.push_back(cur), cur.clear();
    else cur.push_back(c);
  }
  out.push_back(cur);
  return out;
}

}  // namespace

const ParameterEntry* ParameterTable::Find(const std::string& name) const {
  for (const ParameterEntry& e : entries)
    if (e.name == name) return &e;
  return nullptr;
}

ParameterTable ParameterTable::Of(const ParameterSet& set, int64_t version, int64_t utime) {
  ParameterTable t;
  t.utime = utime;
  t.version = version;
  for (const auto& [name, p] : set.all()) {
    const ParameterSpec* spec = set.schema() ? set.schema()->Find(name) : nullptr;
    ParameterEntry e;
    e.name = name;
    e.unit = p.unit;
    e.description = p.description;
    e.value = p.value;
    e.default_value = spec && spec->default_value ? *spec->default_value : std::numeric_limits<double>::quiet_NaN();
    e.min = p.min;
    e.max = p.max;
    e.apply = spec ? spec->apply : ParamApply::kAtStart;
    t.entries.push_back(std::move(e));
  }
  return t;
}

const std::vector<Signal<ParameterTable>>& ReportSignals<ParameterTable>::Table() {
  using T = ParameterTable;
  static const std::vector<Signal<T>> k = {
      {{"count", "", "1", "parameters the vehicle reports", SignalFormat::kInteger},
       [](const T& t) { return static_cast<double>(t.entries.size()); }},
      {{"version", "", "1", "changes over the link since start", SignalFormat::kInteger},
       [](const T& t) { return static_cast<double>(t.version); }},
  };
  return k;
}

std::string FormatParameterFile(const ParameterTable& table, ParameterFileFormat format, const std::string& vehicle_id) {
  std::ostringstream os;
  if (format == ParameterFileFormat::kQgc) {
    // QGroundControl writes this header; a MAVLink system id is a number, so ours is 1.
    os << "# Onboard parameters for " << vehicle_id << "\n#\n# Vehicle-Id Component-Id Name Value Type\n";
    for (const ParameterEntry& e : table.entries)
      os << "1\t1\t" << e.name << "\t" << FormatParameterValue(e.value) << "\t" << e.mavlink_type << "\n";
    return os.str();
  }
  os << "# Parameters of " << vehicle_id << " (version " << table.version << "): name  value  # unit [min, max] description\n";
  for (const ParameterEntry& e : table.entries) {
    std::string line = e.name;
    line.resize(std::max<std::size_t>(line.size() + 1, 28), ' ');
    line += FormatParameterValue(e.value);
    line.resize(std::max<std::size_t>(line.size() + 1, 44), ' ');
    os << line << "# " << e.unit << " [" << FormatParameterValue(e.min) << ", " << FormatParameterValue(e.max) << "] " << e.description << "\n";
  }
  return os.str();
}

std::vector<std::pair<std::string, double>> ParseParameterFile(const std::string& text, const std::string& source) {
  std::vector<std::pair<std::string, double>> out;
  std::set<std::string> seen;
  std::istringstream in(text);
  std::string raw;
  int line_no = 0;
  while (std::getline(in, raw)) {
    ++line_no;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    const auto fail = [&](const std::string& why) {
      throw std::invalid_argument(source + ":" + std::to_string(line_no) + ": " + why);
    };
    std::string name, value;
    const std::vector<std::string> tabs = Split(raw, '\t');
    if (tabs.size() == 5 && raw.find('#') != 0) {  // QGroundControl: id, component, name, value, type
      name = tabs[2], value = tabs[3];
    } else {
      const std::string body = raw.substr(0, raw.find('#'));
      std::istringstream words(body);
      std::string extra;
      if (!(words >> name)) continue;  // blank or a comment
      if (!(words >> value)) fail("'" + name + "' has no value");
      if (words >> extra) fail("'" + name + "' is followed by '" + extra + "' (expected: name value)");
    }
    const std::optional<double> v = ParseDecimal(value);
    if (!v) fail(name + ": '" + value + "' is not a finite decimal number");
    if (!seen.insert(name).second) fail(name + " is set twice");
    out.emplace_back(name, *v);
  }
  return out;
}

}  // namespace uav
