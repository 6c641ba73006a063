#pragma once
// Parameters over the link (QGroundControl's parameter editor, PX4's `param set` and
// parameter_update): the vehicle's parameters as they are now. A change is applied only when its
// ParamApply allows it (at once, only disarmed, or never: read at start), when it is declared,
// finite and within its limits, and when the whole set still makes a valid vehicle (the
// validator builds every setting the change reaches). Every change is counted (the version).
#include <cstdint>
#include <functional>
#include <string>

#include "uav/shared/parameters.hpp"

namespace uav::runtime {

class ParameterServer {
 public:
  // Throws (std::invalid_argument, std::runtime_error) naming what a candidate set breaks.
  using Validator = std::function<void(const ParameterSet&)>;
  ParameterServer(ParameterSet params, Validator validate) : params_(std::move(params)), validate_(std::move(validate)) {}

  struct Outcome {
    bool accepted = false;
    bool changed = false;
    std::string message;  // accepted: "ctl_speed_max_xy = 4 m/s (was 5)"; refused: why
  };
  Outcome Set(const std::string& name, double value, bool armed);

  const ParameterSet& params() const { return params_; }
  int64_t version() const { return version_; }

 private:
  ParameterSet params_;
  Validator validate_;
  int64_t version_ = 0;
};

}  // namespace uav::runtime
