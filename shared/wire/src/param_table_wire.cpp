#include "uav/wire/messages.hpp"

#include <cmath>
#include <stdexcept>

#include "uavmsg/param_table_t.hpp"

namespace uav {

ParameterTable FromMessage(const uavmsg::param_table_t& m) {
  auto fail = [](const std::string& what) { throw std::invalid_argument("param_table_t: " + what); };
  if (m.num_params < 0 || m.num_params > uavmsg::param_table_t::MAX_PARAMS ||
      m.params.size() != static_cast<std::size_t>(m.num_params))
    fail("num_params " + std::to_string(m.num_params) + " out of range");
  if (m.version < 0) fail("negative version");
  ParameterTable t;
  t.utime = m.utime;
  t.version = m.version;
  for (const uavmsg::param_entry_t& p : m.params) {
    if (p.name.empty() || p.name.size() > 64) fail("a parameter name of " + std::to_string(p.name.size()) + " characters");
    if (!std::isfinite(p.value) || !std::isfinite(p.min) || !std::isfinite(p.max) || p.min > p.max ||
        p.value < p.min || p.value > p.max)
      fail(p.name + ": value or limits not finite, or the value outside them");
    if (p.apply < uavmsg::param_entry_t::APPLY_AT_START || p.apply > uavmsg::param_entry_t::APPLY_IN_FLIGHT)
      fail(p.name + ": unknown apply " + std::to_string(p.apply));
    t.entries.push_back({p.name, p.unit, p.description, p.value, p.default_value, p.min, p.max, static_cast<ParamApply>(p.apply)});
  }
  return t;
}

uavmsg::param_table_t ToMessage(const ParameterTable& t) {
  uavmsg::param_table_t m{};
  m.utime = t.utime;
  m.version = t.version;
  for (const ParameterEntry& e : t.entries) {
    if (m.params.size() >= static_cast<std::size_t>(uavmsg::param_table_t::MAX_PARAMS)) break;
    m.params.push_back({e.name, e.unit, e.description, e.value, e.default_value, e.min, e.max, static_cast<int8_t>(e.apply)});
  }
  m.num_params = static_cast<int16_t>(m.params.size());
  return m;
}

}  // namespace uav
