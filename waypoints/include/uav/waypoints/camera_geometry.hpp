#pragma once
// Camera footprint geometry for survey planning (thesis 6.1), the same calculation as
// QGroundControl's survey camera: GSD = H*Sw*100/(Iw*f) [cm/px].
#include "uav/shared/parameters.hpp"

namespace uav::waypoints {

struct CameraSpec {
  double sensor_width_mm;
  double sensor_height_mm;
  double focal_length_mm;
  int image_width_px;
  int image_height_px;
  bool landscape = true;  // long image side across the flight direction
};

// Throws std::invalid_argument naming the field when a value is not positive and finite.
void ValidateCamera(const CameraSpec& c);

// From a camera file in the parameter format (resources/cameras/*.camera): sensor_width_mm,
// sensor_height_mm, focal_length_mm, image_width_px, image_height_px, landscape (1/0).
// Throws naming the missing or invalid parameter.
CameraSpec CameraFromParameters(const ParameterSet& p);

struct Footprint {
  double gsd_cm_per_px;  // ground sample distance along the image width
  double across_m;       // ground extent across the flight direction
  double along_m;        // ground extent along the flight direction
};

// Footprint of a nadir image taken from altitude_m above flat ground.
Footprint FootprintAt(const CameraSpec& c, double altitude_m);
// Altitude that gives the requested GSD.
double AltitudeForGsd(const CameraSpec& c, double gsd_cm_per_px);
// Distance between survey lines for the side overlap (0..1): footprint across * (1 - overlap).
double LineSpacing(const Footprint& f, double side_overlap);
// Distance between exposures for the front overlap: footprint along * (1 - overlap).
double TriggerDistance(const Footprint& f, double front_overlap);

}  // namespace uav::waypoints
