#include "uav/runtime/parameter_server.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace uav::runtime {
ParameterServer::Outcome ParameterServer::Set(const std::string& name, double value, bool armed) {
  Outcome out;
  const ParameterSpec* spec = params_.schema() ? params_.schema()->Find(name) : nullptr;
  if (!spec || !params_.Has(name)) {
    out.message = "unknown parameter '" + name + "'";
    return out;
  }
  const double was = params_.Get(name);
  const std::string unit = spec->unit == "-" ? "" : " " + spec->unit;
  if (spec->apply == ParamApply::kAtStart) {
    out.message = name + " is read only at start: set it in the vehicle file or with uav-onboard --param " + name + "=" +
                  FormatParameterValue(value) + " (it is " + FormatParameterValue(was) + unit + ")";
    return out;
  }
  if (spec->apply == ParamApply::kOnGround && armed) {
    out.message = name + " changes only while disarmed (it is " + FormatParameterValue(was) + unit + ")";
    return out;
  }
  try {
    ParameterSet candidate = params_.With(name, value);  // declared, finite, within its limits
    validate_(candidate);
    out.accepted = true;
    out.changed = value != was;
    if (out.changed) {
      params_ = std::move(candidate);
      ++version_;
      out.message = name + " = " + FormatParameterValue(value) + unit + " (was " + FormatParameterValue(was) + ")";
    } else {
      out.message = name + " is already " + FormatParameterValue(value) + unit;
    }
  } catch (const std::exception& e) {
    out.message = name + " = " + FormatParameterValue(value) + " refused: " + e.what();
  }
  return out;
}

}  // namespace uav::runtime
