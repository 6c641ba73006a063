#include "uav/shared/geodesy.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include <GeographicLib/LocalCartesian.hpp>

namespace uav {

void ValidateGeodetic(const GeodeticPoint& g) {
  auto check = [](double v, double lo, double hi, const char* name) {
    if (!std::isfinite(v) || v < lo || v > hi) {
      throw std::invalid_argument(std::string(name) + " = " + std::to_string(v) +
                                  " is outside [" + std::to_string(lo) + ", " +
                                  std::to_string(hi) + "]");
    }
  };
  check(g.latitude_deg, -90.0, 90.0, "latitude_deg");
  check(g.longitude_deg, -180.0, 180.0, "longitude_deg");
  check(g.altitude_m, -500.0, 10000.0, "altitude_m");
}

struct LocalNedFrame::Impl {
  GeographicLib::LocalCartesian enu;  // GeographicLib's local frame is East-North-Up
};

LocalNedFrame::LocalNedFrame(const GeodeticPoint& home) : home_(home) {
  ValidateGeodetic(home);
  impl_ = std::make_unique<Impl>(Impl{GeographicLib::LocalCartesian(
      home.latitude_deg, home.longitude_deg, home.altitude_m)});
}

LocalNedFrame::~LocalNedFrame() = default;

Eigen::Vector3d LocalNedFrame::ToNed(const GeodeticPoint& g) const {
  double e, n, u;
  impl_->enu.Forward(g.latitude_deg, g.longitude_deg, g.altitude_m, e, n, u);
  return {n, e, -u};
}

GeodeticPoint LocalNedFrame::ToGeodetic(const Eigen::Vector3d& p_N) const {
  GeodeticPoint g;
  impl_->enu.Reverse(p_N.y(), p_N.x(), -p_N.z(), g.latitude_deg, g.longitude_deg, g.altitude_m);
  return g;
}

}  // namespace uav
