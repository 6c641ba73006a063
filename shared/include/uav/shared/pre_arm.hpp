#pragma once
// The vehicle's pre-arm checks as plain data: what it publishes (pre_arm_t, 1 Hz while on the
// ground) and the GCS's checklist shows. `arm` is refused while any check fails, naming each.
#include <cstdint>
#include <string>
#include <vector>

#include "uav/shared/signals.hpp"

namespace uav {

struct PreArmCheck {
  std::string name;    // "gps", "ins", "battery", "geofence", "sensors"
  bool passed = false;
  std::string reason;  // why it fails ("no 3-D fix: fix 0, 0 satellites"), or what it found
};

struct PreArmReport {
  int64_t utime = 0;  // [us] vehicle clock
  std::vector<PreArmCheck> checks;
  bool Ready() const {
    for (const PreArmCheck& c : checks)
      if (!c.passed) return false;
    return true;
  }
  // "gps: no 3-D fix ...; battery: ..." for the failing checks ("" when ready).
  std::string Failing() const;
};

// Its signals (how many checks fail): group "PREARM".
template <>
struct ReportSignals<PreArmReport> {
  static constexpr std::string_view kGroup = "PREARM";
  static const std::vector<Signal<PreArmReport>>& Table();
};

}  // namespace uav
