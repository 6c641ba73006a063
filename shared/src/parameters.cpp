#include "uav/shared/parameters.hpp"

#include <cstdio>
#include <cstdlib>

#include "uav/shared/decimal.hpp"
#include "uav/shared/text_file.hpp"

#include <algorithm>
#include <filesystem>
#include <set>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace uav {
namespace {

std::string Format(double v) { return FormatParameterValue(v); }

std::size_t EditDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diag = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// " (did you mean 'mass'?)" when a declared name is a likely misspelling of `name`.
std::string Suggestion(const ParameterSchema& schema, const std::string& name) {
  const ParameterSpec* best = nullptr;
  std::size_t best_d = 3;  // at most two edits away
  for (const auto& s : schema.specs) {
    const std::size_t d = EditDistance(name, s.name);
    if (d < best_d) best_d = d, best = &s;
  }
  return best ? " (did you mean '" + best->name + "'?)" : "";
}

Parameter FromSpec(const ParameterSpec& s, double value) { return {value, s.unit, s.min, s.max, s.description, ""}; }

}  // namespace

const ParameterSpec* ParameterSchema::Find(const std::string& name) const {
  for (const auto& s : specs)
    if (s.name == name) return &s;
  return nullptr;
}

ParameterSet ParameterSet::LoadFile(const std::string& path, const ParameterSchema& schema) {
  const std::string text = ReadTextFile(path, schema.kind + " parameter file");
  ParameterSet set = Parse(text, path, schema);
  // A file of no settings is a mistake (a truncated copy, the wrong file), not a wish for the
  // defaults: flying on them without a word is what nobody asked.
  std::istringstream lines(text);
  std::string line, name;
  bool any = false;
  while (!any && std::getline(lines, line)) any = static_cast<bool>(std::istringstream(line.substr(0, line.find('#'))) >> name);
  if (!any)
    throw std::runtime_error(path + ": the " + schema.kind + " parameter file sets nothing (it is empty or all comments); "
                             "give the parameters it should set, or the shipped file to fly on its values");
  return set;
}

ParameterSet ParameterSet::Defaults(const ParameterSchema& schema) { return Parse("", "defaults", schema); }

ParameterSet ParameterSet::Parse(const std::string& text, const std::string& source_name,
                                 const ParameterSchema& schema) {
  ParameterSet set;
  set.source_ = source_name;
  set.schema_ = &schema;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  bool any_setting = false;
  std::set<std::string> set_here;  // a file sets each name once; an included one's values it may change
  while (std::getline(lines, line)) {
    ++line_no;
    const std::string where = source_name + ":" + std::to_string(line_no) + ": ";
    if (auto hash = line.find('#'); hash != std::string::npos) line = line.substr(0, hash);
    std::istringstream fields(line);
    std::string name, value_s, extra;
    if (!(fields >> name)) continue;  // blank or comment line
    if (!(fields >> value_s) || (fields >> extra))
      throw std::runtime_error(where + "expected 'name value', got '" + line +
                               "' (units and limits are declared by the program, not the file)");
    if (name == "include") {
      // A variant lists only what differs from its base: "include x650.params" first, then the
      // differences. The base is found beside this file; includes nest (a cycle is refused).
      if (any_setting || !set.params_.empty())
        throw std::runtime_error(where + "include must come first, before any setting, and only once");
      static thread_local int depth = 0;
      if (depth >= 8) throw std::runtime_error(where + "include nested more than 8 deep (a file that includes itself?)");
      const std::string base = (std::filesystem::path(source_name).parent_path() / value_s).string();
      ++depth;
      try {
        set.params_ = LoadFile(base, schema).params_;
      } catch (...) {
        --depth;
        throw;
      }
      --depth;
      const std::string base_name = std::filesystem::path(value_s).filename().string();
      for (auto& [n, p] : set.params_)
        if (p.origin.empty()) p.origin = base_name;
      continue;
    }
    any_setting = true;
    const ParameterSpec* spec = schema.Find(name);
    if (!spec)
      throw std::runtime_error(where + "'" + name + "' is not a " + schema.kind + " parameter" +
                               Suggestion(schema, name));
    const std::optional<double> value = ParseDecimal(value_s);
    if (!value)
      throw std::runtime_error(where + name + ": value '" + value_s + "' is not a finite number");
    if (*value < spec->min || *value > spec->max)
      throw std::runtime_error(where + name + " = " + value_s + " is outside [" + Format(spec->min) + ", " +
                               Format(spec->max) + "] " + spec->unit);
    if (!set_here.insert(name).second) throw std::runtime_error(where + name + " is set twice");
    set.params_.insert_or_assign(name, FromSpec(*spec, *value));
  }
  for (const auto& s : schema.specs) {
    if (set.params_.count(s.name)) continue;
    if (s.default_value) set.params_.emplace(s.name, FromSpec(s, *s.default_value));
    else if (!s.optional)
      throw std::runtime_error(source_name + ": " + s.name + " is missing (" + s.description + ", " + s.unit + ")");
  }
  return set;
}

double ParameterSet::Get(const std::string& name) const {
  auto it = params_.find(name);
  if (it == params_.end())
    throw std::out_of_range("parameter '" + name + "' is missing from " + source_);
  return it->second.value;
}

ParameterSet ParameterSet::With(const std::string& name, double value, const std::string& origin) const {
  const ParameterSpec* spec = schema_ ? schema_->Find(name) : nullptr;
  if (!spec)
    throw std::invalid_argument("parameter '" + name + "' does not exist in " + source_ +
                                (schema_ ? Suggestion(*schema_, name) : ""));
  if (!std::isfinite(value) || value < spec->min || value > spec->max) {
    std::ostringstream os;
    os << "parameter " << name << " = " << value << " is outside [" << spec->min << ", " << spec->max << "] "
       << spec->unit;
    throw std::invalid_argument(os.str());
  }
  ParameterSet copy = *this;
  copy.params_[name] = FromSpec(*spec, value);
  copy.params_[name].origin = origin;
  return copy;
}

std::string ParameterSet::SourceName() const {
  const auto slash = source_.find_last_of('/');
  return slash == std::string::npos ? source_ : source_.substr(slash + 1);
}

std::string ParameterSet::Describe(const std::string& name) const {
  const auto it = params_.find(name);
  if (it == params_.end()) return name + " (missing from " + SourceName() + ")";
  return name + " " + FormatParameterValue(it->second.value) + " (" +
         (it->second.origin.empty() ? SourceName() : it->second.origin) + ")";
}

ParameterSet ParameterSet::WithAssignment(const std::string& assignment) const {
  const auto eq = assignment.find('=');
  const std::optional<double> value =
      eq == std::string::npos ? std::nullopt : ParseDecimal(std::string_view(assignment).substr(eq + 1));
  if (eq == std::string::npos || eq == 0 || !value)
    throw std::invalid_argument("parameter override must be NAME=VALUE with a finite decimal number, got '" +
                                assignment + "'");
  return With(assignment.substr(0, eq), *value, "--param " + assignment);
}

std::string FormatParameterValue(double v) {
  char buf[40];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

const char* Name(ParamApply a) {
  switch (a) {
    case ParamApply::kAtStart: return "start";
    case ParamApply::kOnGround: return "ground";
    case ParamApply::kInFlight: return "flight";
  }
  return "?";
}

std::string DescribeSchema(const ParameterSchema& schema) {
  std::ostringstream os;
  for (const auto& s : schema.specs) {
    os << s.name << "  " << (s.default_value ? Format(*s.default_value) : std::string(s.optional ? "(optional)" : "(required)"))
       << "  " << s.unit << "  [" << Format(s.min) << ", " << Format(s.max) << "]  changes: " << Name(s.apply) << "  "
       << s.description << "\n";
  }
  return os.str();
}

}  // namespace uav
