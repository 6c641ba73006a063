#include "uav/wire/messages.hpp"

#include <stdexcept>

#include "uavmsg/pre_arm_t.hpp"

namespace uav {

PreArmReport FromMessage(const uavmsg::pre_arm_t& m) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("pre_arm_t: " + what); };
  if (m.num_checks < 0 || m.num_checks > uavmsg::pre_arm_t::MAX_CHECKS ||
      m.checks.size() != static_cast<std::size_t>(m.num_checks))
    fail("num_checks " + std::to_string(m.num_checks) + " out of range");
  PreArmReport r;
  r.utime = m.utime;
  for (const uavmsg::pre_arm_check_t& c : m.checks) {
    if (c.name.empty()) fail("a check without a name");
    if (!c.passed && c.reason.empty()) fail("check " + c.name + " fails without a reason");
    r.checks.push_back({c.name, c.passed != 0, c.reason});
  }
  return r;
}

uavmsg::pre_arm_t ToMessage(const PreArmReport& r) {
  uavmsg::pre_arm_t m{};
  m.utime = r.utime;
  for (const PreArmCheck& c : r.checks) {
    if (m.checks.size() >= static_cast<std::size_t>(uavmsg::pre_arm_t::MAX_CHECKS)) break;
    m.checks.push_back({c.name, c.passed, c.reason});
  }
  m.num_checks = static_cast<int16_t>(m.checks.size());
  return m;
}

}  // namespace uav
