#pragma once
// The vehicle's parameters as it reports them over the link (param_table_t): each with its value
// now, default, limits, unit and when a change may take effect. The GCS's Parameters panel shows
// it; files in our vehicle-file format and in QGroundControl's .params format read and write it.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "uav/shared/parameters.hpp"
#include "uav/shared/signals.hpp"

namespace uav {

struct ParameterEntry {
  std::string name, unit, description;
  double value = 0.0, default_value = 0.0, min = 0.0, max = 0.0;  // [unit]; default NaN: none
  ParamApply apply = ParamApply::kAtStart;
  // MAV_PARAM_TYPE, what a QGroundControl .params file writes in its type column: ours are all
  // REAL32 (9); a MAVLink autopilot's come with their own (6: INT32).
  int mavlink_type = 9;
};

struct ParameterTable {
  int64_t utime = 0;    // [us] vehicle clock
  int64_t version = 0;  // changes over the link so far
  std::vector<ParameterEntry> entries;  // by name
  const ParameterEntry* Find(const std::string& name) const;
  static ParameterTable Of(const ParameterSet& set, int64_t version, int64_t utime);
};

// Its signals: group "PARAMS" (the count and the version, so a plot or the flight log shows when a
// setting changed).
template <>
struct ReportSignals<ParameterTable> {
  static constexpr std::string_view kGroup = "PARAMS";
  static const std::vector<Signal<ParameterTable>>& Table();
};

enum class ParameterFileFormat {
  kVehicle,  // ours: "name  value  # unit [min, max] description", as resources/vehicles/*.params
  kQgc,      // QGroundControl's .params: "vehicle-id<TAB>component-id<TAB>name<TAB>value<TAB>type"
};

std::string FormatParameterFile(const ParameterTable& table, ParameterFileFormat format, const std::string& vehicle_id);

// Reads either format (a line of five tab-separated fields is QGroundControl's), in file order.
// Throws std::invalid_argument naming the source, line and what is wrong (not a name and a value,
// a value that is not a finite decimal, a duplicate name).
std::vector<std::pair<std::string, double>> ParseParameterFile(const std::string& text, const std::string& source);

}  // namespace uav
