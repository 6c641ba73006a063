#include "uav/wire/messages.hpp"

#include <cmath>
#include <stdexcept>

#include "uavmsg/power_lines_t.hpp"

namespace uav {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("power_lines_t: " + what);
}
}  // namespace

PowerLines FromMessage(const uavmsg::power_lines_t& m) {
  Require(m.num_wires >= 0 && m.num_wires <= uavmsg::power_lines_t::MAX_WIRES,
          "num_wires " + std::to_string(m.num_wires) + " outside 0.." + std::to_string(uavmsg::power_lines_t::MAX_WIRES));
  Require(static_cast<int>(m.wires.size()) == m.num_wires, "num_wires does not match the wires sent");
  Require(std::isfinite(m.nearest_m), "nearest_m is not finite");
  PowerLines p;
  p.utime = m.utime;
  p.camera = m.camera;
  p.nearest_m = m.nearest_m < 0 ? -1.0 : m.nearest_m;
  for (int i = 0; i < m.num_wires; ++i) {
    const uavmsg::power_line_t& w = m.wires[i];
    const std::string where = "wire " + std::to_string(i) + ": ";
    Require(w.num_image_points >= 0 && static_cast<int>(w.image_x.size()) == w.num_image_points &&
                static_cast<int>(w.image_y.size()) == w.num_image_points,
            where + "image point arrays do not match num_image_points");
    Require(w.num_points >= 0 && static_cast<int>(w.north_m.size()) == w.num_points &&
                static_cast<int>(w.east_m.size()) == w.num_points && static_cast<int>(w.down_m.size()) == w.num_points,
            where + "NED arrays do not match num_points");
    PowerLine line;
    for (int k = 0; k < w.num_image_points; ++k) {
      Require(std::isfinite(w.image_x[k]) && std::isfinite(w.image_y[k]) && std::abs(w.image_x[k] - 0.5f) <= 1.0f &&
                  std::abs(w.image_y[k] - 0.5f) <= 1.0f,
              where + "image point " + std::to_string(k) + " is not finite or far outside the image");
      line.image_uv.emplace_back(w.image_x[k], w.image_y[k]);
    }
    for (int k = 0; k < w.num_points; ++k) {
      Require(std::isfinite(w.north_m[k]) && std::isfinite(w.east_m[k]) && std::isfinite(w.down_m[k]),
              where + "point " + std::to_string(k) + " is not finite");
      line.p_N.emplace_back(w.north_m[k], w.east_m[k], w.down_m[k]);
    }
    Require(std::isfinite(w.range_m) && std::isfinite(w.range_sigma_m) && w.range_sigma_m >= 0,
            where + "range or its sigma is not finite");
    Require((w.range_m >= 0) == (w.num_points > 0), where + "a range needs points and points need a range");
    line.range_m = w.range_m >= 0 ? w.range_m : -1.0;
    line.range_sigma_m = w.range_sigma_m;
    p.wires.push_back(std::move(line));
  }
  return p;
}

uavmsg::power_lines_t ToMessage(const PowerLines& p) {
  uavmsg::power_lines_t m;
  m.utime = p.utime;
  m.camera = p.camera;
  m.nearest_m = static_cast<float>(p.nearest_m);
  for (const PowerLine& line : p.wires) {
    if (static_cast<int>(m.wires.size()) >= uavmsg::power_lines_t::MAX_WIRES) break;
    uavmsg::power_line_t w;
    for (const auto& uv : line.image_uv) {
      w.image_x.push_back(static_cast<float>(uv.x()));
      w.image_y.push_back(static_cast<float>(uv.y()));
    }
    w.num_image_points = static_cast<int16_t>(w.image_x.size());
    for (const auto& q : line.p_N) {
      w.north_m.push_back(static_cast<float>(q.x()));
      w.east_m.push_back(static_cast<float>(q.y()));
      w.down_m.push_back(static_cast<float>(q.z()));
    }
    w.num_points = static_cast<int16_t>(w.north_m.size());
    w.range_m = static_cast<float>(line.range_m);
    w.range_sigma_m = static_cast<float>(line.range_sigma_m);
    m.wires.push_back(std::move(w));
  }
  m.num_wires = static_cast<int16_t>(m.wires.size());
  return m;
}

}  // namespace uav
