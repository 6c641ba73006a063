#include "uav/shared/parameters.hpp"

#include "uav/shared/text_file.hpp"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace uav {
namespace {

bool ParseFinite(const std::string& s, double* out) {
  char* end = nullptr;
  *out = std::strtod(s.c_str(), &end);
  return end != s.c_str() && *end == '\0' && std::isfinite(*out);
}

}  // namespace

ParameterSet ParameterSet::LoadFile(const std::string& path) {
  return Parse(ReadTextFile(path, "parameter file"), path);
}

ParameterSet ParameterSet::Parse(const std::string& text, const std::string& source_name) {
  ParameterSet set;
  set.source_ = source_name;
  std::istringstream lines(text);
  std::string line;
  int line_no = 0;
  while (std::getline(lines, line)) {
    ++line_no;
    const std::string where = source_name + ":" + std::to_string(line_no) + ": ";
    std::string description;
    if (auto hash = line.find('#'); hash != std::string::npos) {
      description = line.substr(hash + 1);
      line = line.substr(0, hash);
      const auto first = description.find_first_not_of(' ');
      description = first == std::string::npos ? "" : description.substr(first);
    }
    std::istringstream fields(line);
    std::string name, value_s, unit, min_s, max_s, extra;
    if (!(fields >> name)) continue;  // blank or comment line
    if (!(fields >> value_s >> unit >> min_s >> max_s) || (fields >> extra)) {
      throw std::runtime_error(where + "expected 'name value unit min max', got '" + line + "'");
    }
    Parameter p{0, unit, 0, 0, description};
    if (!ParseFinite(value_s, &p.value))
      throw std::runtime_error(where + name + ": value '" + value_s + "' is not a finite number");
    if (!ParseFinite(min_s, &p.min))
      throw std::runtime_error(where + name + ": min '" + min_s + "' is not a finite number");
    if (!ParseFinite(max_s, &p.max))
      throw std::runtime_error(where + name + ": max '" + max_s + "' is not a finite number");
    if (p.min > p.max) throw std::runtime_error(where + name + ": min > max");
    if (p.value < p.min || p.value > p.max)
      throw std::runtime_error(where + name + " = " + value_s + " is outside [" + min_s + ", " +
                               max_s + "] " + unit);
    if (!set.params_.emplace(name, p).second)
      throw std::runtime_error(where + name + " is defined twice");
  }
  return set;
}

double ParameterSet::Get(const std::string& name) const {
  auto it = params_.find(name);
  if (it == params_.end())
    throw std::out_of_range("parameter '" + name + "' is missing from " + source_);
  return it->second.value;
}

ParameterSet ParameterSet::With(const std::string& name, double value) const {
  auto it = params_.find(name);
  if (it == params_.end()) throw std::invalid_argument("parameter '" + name + "' does not exist in " + source_);
  const Parameter& p = it->second;
  if (!std::isfinite(value) || value < p.min || value > p.max) {
    std::ostringstream os;
    os << "parameter " << name << " = " << value << " is outside [" << p.min << ", " << p.max << "] "
       << p.unit;
    throw std::invalid_argument(os.str());
  }
  ParameterSet copy = *this;
  copy.params_[name].value = value;
  return copy;
}

ParameterSet ParameterSet::WithAssignment(const std::string& assignment) const {
  const auto eq = assignment.find('=');
  double value = 0;
  if (eq == std::string::npos || eq == 0 || !ParseFinite(assignment.substr(eq + 1), &value))
    throw std::invalid_argument("parameter override must be NAME=VALUE with a finite number, got '" +
                                assignment + "'");
  return With(assignment.substr(0, eq), value);
}

}  // namespace uav
