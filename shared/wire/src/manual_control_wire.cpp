#include "uav/wire/messages.hpp"

namespace uav {

ManualSticks FromMessage(const uavmsg::manual_control_t& m) {
  ManualSticks s;
  s.utime = m.utime;
  s.forward = m.forward;
  s.right = m.right;
  s.up = m.up;
  s.yaw = m.yaw;
  s.deadman = m.deadman;
  ValidateSticks(s);
  return s;
}

uavmsg::manual_control_t ToMessage(const ManualSticks& s) {
  uavmsg::manual_control_t m{};
  m.utime = s.utime;
  m.forward = static_cast<float>(s.forward);
  m.right = static_cast<float>(s.right);
  m.up = static_cast<float>(s.up);
  m.yaw = static_cast<float>(s.yaw);
  m.deadman = s.deadman;
  return m;
}

}  // namespace uav
