#include "uav/shared/pre_arm.hpp"

namespace uav {

std::string PreArmReport::Failing() const {
  std::string out;
  for (const PreArmCheck& c : checks)
    if (!c.passed) out += (out.empty() ? "" : "; ") + c.name + ": " + c.reason;
  return out;
}

const std::vector<Signal<PreArmReport>>& ReportSignals<PreArmReport>::Table() {
  using R = PreArmReport;
  static const std::vector<Signal<R>> k = {
      {{"failing", "", "1", "checks failing, 0 ready to arm", SignalFormat::kInteger}, [](const R& r) {
         double n = 0;
         for (const PreArmCheck& c : r.checks) n += !c.passed;
         return n;
       }},
  };
  return k;
}

}  // namespace uav
