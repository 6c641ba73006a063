#pragma once
// WGS84 geodesy through GeographicLib: a local NED frame with its origin at home.
#include <memory>

#include <Eigen/Core>

namespace uav {

struct GeodeticPoint {
  double latitude_deg = 0.0;
  double longitude_deg = 0.0;
  double altitude_m = 0.0;  // above the WGS84 ellipsoid
};

// Throws std::invalid_argument naming the field when latitude is outside [-90, 90], longitude
// outside [-180, 180], altitude outside [-500, 10000] m, or any value is not finite.
void ValidateGeodetic(const GeodeticPoint& g);

// Local tangent-plane North-East-Down frame N with its origin at `home`.
class LocalNedFrame {
 public:
  explicit LocalNedFrame(const GeodeticPoint& home);
  ~LocalNedFrame();
  LocalNedFrame(const LocalNedFrame&) = delete;
  LocalNedFrame& operator=(const LocalNedFrame&) = delete;

  const GeodeticPoint& home() const { return home_; }
  Eigen::Vector3d ToNed(const GeodeticPoint& g) const;      // p_N [m]
  GeodeticPoint ToGeodetic(const Eigen::Vector3d& p_N) const;

 private:
  GeodeticPoint home_;
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav
