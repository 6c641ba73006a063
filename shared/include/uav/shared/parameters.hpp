#pragma once
// Parameters are data (PX4 style): a text file with one parameter per line,
//   name  value  unit  min  max  # description
// Every value is checked against its own limits when the file is loaded.
#include <map>
#include <string>

namespace uav {

struct Parameter {
  double value;
  std::string unit;
  double min;
  double max;
  std::string description;
};

class ParameterSet {
 public:
  // Throws std::runtime_error naming the file and line of the first bad entry (unknown syntax,
  // non-numeric or non-finite value, min > max, value outside [min, max], duplicate name).
  static ParameterSet LoadFile(const std::string& path);
  static ParameterSet Parse(const std::string& text, const std::string& source_name);

  // Throws std::out_of_range naming the parameter and the source when it is missing.
  double Get(const std::string& name) const;
  bool Has(const std::string& name) const { return params_.count(name) != 0; }
  // A copy with one existing parameter changed (an override from the command line or a test).
  // Throws std::invalid_argument naming the parameter when it is unknown, not finite or outside
  // its limits.
  ParameterSet With(const std::string& name, double value) const;
  // Applies "name=value" (the --param option). Same errors as With, plus malformed text.
  ParameterSet WithAssignment(const std::string& assignment) const;
  const std::map<std::string, Parameter>& all() const { return params_; }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::map<std::string, Parameter> params_;
};

}  // namespace uav
