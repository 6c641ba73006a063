#pragma once
// Power lines seen in one stereo pair (thesis 3.6), as plain data: what the vehicle's STEREO
// thread produces and the GCS draws. power_lines_t is its wire form; it is decoded once, here.
#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace uav {

struct PowerLine {
  std::vector<Eigen::Vector2d> image_uv;  // the curve, normalised 0..1 in the camera image
  std::vector<Eigen::Vector3d> p_N;       // [m] 3-D polyline in local NED; empty: not ranged
  double range_m = -1.0;                  // [m] nearest point from the body origin; < 0: not ranged
  double range_sigma_m = 0.0;             // [m] its standard deviation
  bool ranged() const { return !p_N.empty(); }
};

struct PowerLines {
  int64_t utime = 0;        // [us] vehicle clock of the stereo pair
  std::string camera;       // the image the curves are in
  double nearest_m = -1.0;  // [m] nearest ranged wire; < 0: none
  std::vector<PowerLine> wires;
};

}  // namespace uav
