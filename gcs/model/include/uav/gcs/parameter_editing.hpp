#pragma once
// The Parameters panel's checks, before anything is sent: a typed value against the vehicle's
// table (its limits, and whether it may change now), and a parameter file against the table (what
// a load would send, and what it cannot). The vehicle checks again and has the last word.
#include <string>
#include <utility>
#include <vector>

#include "uav/shared/parameter_table.hpp"

namespace uav::gcs {

// "" when `text` is a value that may be sent for `name` now (set in *value); otherwise why not:
// an unknown name, not a finite decimal, outside the limits, read only at start, only disarmed.
std::string CheckParameterValue(const ParameterTable& table, const std::string& name, const std::string& text, bool armed,
                                double* value);

struct ParameterLoad {
  std::vector<std::pair<std::string, double>> to_send;  // differ from the vehicle's and may change now
  int unchanged = 0;
  std::vector<std::string> problems;  // per parameter not sent: why
};
ParameterLoad PlanParameterLoad(const ParameterTable& table, const std::vector<std::pair<std::string, double>>& file,
                                bool armed);

}  // namespace uav::gcs
