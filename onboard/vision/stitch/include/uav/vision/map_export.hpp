#pragma once
// Writes a stitched map where GIS tools place it (issue 7 item 5): a GeoTIFF (GDAL, WGS84
// lat/lon with an alpha band), a PNG with a world file (.pgw) and a .prj, and a KML ground
// overlay for Google Earth. The map is north-up in the local NED frame of `home`; over a survey
// area (< 2 km) lat/lon are affine in it to a few centimetres, so one geotransform holds.
// Every file is written to a temporary name and renamed.
#include <string>
#include <vector>

#include "uav/shared/geodesy.hpp"
#include "uav/vision/map_stitcher.hpp"

namespace uav::vision {

struct GeoBox {
  double north_deg = 0, south_deg = 0, east_deg = 0, west_deg = 0;  // outer pixel edges
};

// The map's outer edges in WGS84.
GeoBox MapBounds(const Mosaic& map, const GeodeticPoint& home);

// Writes PREFIX.tif, PREFIX.png, PREFIX.pgw, PREFIX.prj and PREFIX.kml; returns their paths.
// Throws std::invalid_argument for an empty map, std::runtime_error naming the file that could
// not be written.
std::vector<std::string> ExportMap(const Mosaic& map, const GeodeticPoint& home, const std::string& prefix);

}  // namespace uav::vision
