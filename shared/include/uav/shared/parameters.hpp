#pragma once
// Parameters are data (PX4 style). The program declares each parameter once, with its unit,
// limits, default, description and when a change may apply (a ParameterSchema); a file sets
// values only, and a variant may start from a base and list what differs:
//   include x650.params   # first, found beside this file
//   name  value   # comment
// Limits are the program's, never the file's: a file cannot widen them.
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace uav {

// When a change over the link may take effect (the vehicle refuses it otherwise, saying why).
enum class ParamApply : int8_t {
  kAtStart = 0,   // builds the vehicle (its model, sensors, cameras, threads, map): the file or --param
  kOnGround = 1,  // while disarmed (a geofence redrawn under a flying vehicle could breach it at once)
  kInFlight = 2,  // at once, armed or not (gains, speed limits, failsafe thresholds, avoidance)
};
const char* Name(ParamApply a);  // "start", "ground", "flight"

struct ParameterSpec {
  std::string name;
  std::string unit;
  std::optional<double> default_value;  // nullopt: the file must set it (unless `optional`)
  double min;
  double max;
  std::string description;
  ParamApply apply = ParamApply::kAtStart;  // when a change over the link may take effect
  bool optional = false;  // without a default: may be left out (ParameterSet::Has says)
};

struct ParameterSchema {
  std::string kind;  // "vehicle", "camera": names the file kind in errors
  std::vector<ParameterSpec> specs;
  const ParameterSpec* Find(const std::string& name) const;
};

// The vehicle's parameters (defaults: the X650 of thesis 2.3-2.5) and a camera file's.
const ParameterSchema& VehicleParameterSchema();
const ParameterSchema& CameraParameterSchema();

struct Parameter {
  double value;
  std::string unit;
  double min;
  double max;
  std::string description;
  std::string origin;  // where a value set after loading came from ("--param x=1"); "": the source
};

class ParameterSet {
 public:
  // Throws std::runtime_error naming the file and line of the first bad entry (not 'name value',
  // a name the schema does not declare, a value that is not a finite decimal number or is
  // outside the declared limits, a duplicate) or the first required parameter left out.
  // Declared parameters the file leaves out take their default.
  static ParameterSet LoadFile(const std::string& path, const ParameterSchema& schema);
  static ParameterSet Parse(const std::string& text, const std::string& source_name, const ParameterSchema& schema);
  // Every parameter at its default (a schema whose parameters all have one).
  static ParameterSet Defaults(const ParameterSchema& schema);

  // Throws std::out_of_range naming the parameter and the source when it is missing.
  double Get(const std::string& name) const;
  bool Has(const std::string& name) const { return params_.count(name) != 0; }
  // A copy with one declared parameter changed (an override from the command line or a test).
  // Throws std::invalid_argument naming the parameter when it is undeclared, not finite or
  // outside its limits.
  // `origin` says where the value came from, for messages (Describe).
  ParameterSet With(const std::string& name, double value, const std::string& origin = "as asked") const;
  // Applies "name=value" (the --param option). Same errors as With, plus malformed text.
  ParameterSet WithAssignment(const std::string& assignment) const;
  // A parameter's value and where it came from, for a refusal that names what to change:
  // "fs_battery_land 0.3 (--param fs_battery_land=0.3)", "fs_battery_return 0.25 (default.params)".
  // Names a file by its name only, never its directory: a refusal that reaches a GCS names
  // nothing on the vehicle's disk.
  std::string Describe(const std::string& name) const;
  // The source without its directory: "default.params", "defaults".
  std::string SourceName() const;
  const std::map<std::string, Parameter>& all() const { return params_; }
  const ParameterSchema* schema() const { return schema_; }
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  const ParameterSchema* schema_ = nullptr;
  std::map<std::string, Parameter> params_;
};

// A parameter's value as text: the shortest decimal that reads back as the same double ("2.5",
// "0.45", "3"), in files, commands and messages alike.
std::string FormatParameterValue(double v);

// One line per declared parameter: name, default, unit, limits, description (--list-params).
std::string DescribeSchema(const ParameterSchema& schema);

}  // namespace uav
