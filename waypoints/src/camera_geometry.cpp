#include "uav/waypoints/camera_geometry.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace uav::waypoints {
namespace {
void RequirePositive(double v, const char* name) {
  if (!std::isfinite(v) || v <= 0.0)
    throw std::invalid_argument(std::string(name) + " must be a positive number, got " +
                                std::to_string(v));
}
void RequireOverlap(double v, const char* name) {
  if (!std::isfinite(v) || v < 0.0 || v >= 1.0)
    throw std::invalid_argument(std::string(name) + " must be in [0, 1), got " + std::to_string(v));
}
}  // namespace

void ValidateCamera(const CameraSpec& c) {
  RequirePositive(c.sensor_width_mm, "sensor_width_mm");
  RequirePositive(c.sensor_height_mm, "sensor_height_mm");
  RequirePositive(c.focal_length_mm, "focal_length_mm");
  RequirePositive(c.image_width_px, "image_width_px");
  RequirePositive(c.image_height_px, "image_height_px");
}

CameraSpec CameraFromParameters(const ParameterSet& p) {
  CameraSpec c;
  c.sensor_width_mm = p.Get("sensor_width_mm");
  c.sensor_height_mm = p.Get("sensor_height_mm");
  c.focal_length_mm = p.Get("focal_length_mm");
  const double w = p.Get("image_width_px"), h = p.Get("image_height_px"), l = p.Get("landscape");
  if (w != std::floor(w) || h != std::floor(h))
    throw std::invalid_argument(p.source() + ": image_width_px and image_height_px must be whole pixels");
  if (l != 0.0 && l != 1.0) throw std::invalid_argument(p.source() + ": landscape must be 0 or 1");
  c.image_width_px = static_cast<int>(w);
  c.image_height_px = static_cast<int>(h);
  c.landscape = l == 1.0;
  ValidateCamera(c);
  return c;
}

Footprint FootprintAt(const CameraSpec& c, double altitude_m) {
  ValidateCamera(c);
  RequirePositive(altitude_m, "altitude_m");
  // Pinhole similar triangles: ground extent = altitude * sensor extent / focal length.
  const double width_m = altitude_m * c.sensor_width_mm / c.focal_length_mm;
  const double height_m = altitude_m * c.sensor_height_mm / c.focal_length_mm;
  Footprint f;
  f.gsd_cm_per_px = altitude_m * c.sensor_width_mm * 100.0 / (c.image_width_px * c.focal_length_mm);
  f.across_m = c.landscape ? width_m : height_m;
  f.along_m = c.landscape ? height_m : width_m;
  return f;
}

double AltitudeForGsd(const CameraSpec& c, double gsd_cm_per_px) {
  ValidateCamera(c);
  RequirePositive(gsd_cm_per_px, "gsd_cm_per_px");
  return gsd_cm_per_px * c.image_width_px * c.focal_length_mm / (c.sensor_width_mm * 100.0);
}

double LineSpacing(const Footprint& f, double side_overlap) {
  RequireOverlap(side_overlap, "side_overlap");
  return f.across_m * (1.0 - side_overlap);
}

double TriggerDistance(const Footprint& f, double front_overlap) {
  RequireOverlap(front_overlap, "front_overlap");
  return f.along_m * (1.0 - front_overlap);
}

}  // namespace uav::waypoints
