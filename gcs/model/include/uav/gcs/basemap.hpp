#pragma once
// A geo-referenced image drawn under the plan and the live map: a GeoTIFF such as the last
// survey's downloaded map or an orthophoto from another tool, in any coordinate system GDAL knows
// (our maps are WGS84; OpenDroneMap's are UTM). Loaded with GDAL (only in basemap.cpp), reduced to
// a texture-sized RGBA image, placed by its four corners in latitude and longitude.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "uav/gcs/message_log.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::gcs {

struct BasemapImage {
  std::string path;
  int source_width = 0, source_height = 0;  // [px] of the file
  int width = 0, height = 0;                // [px] of rgba
  std::vector<uint8_t> rgba;                // transparent where the file has no data
  // The image's outer corners: top-left, top-right, bottom-right, bottom-left.
  std::array<GeodeticPoint, 4> corners;
  int64_t version = 0;  // increases with every load (the UI re-uploads its texture)
};

class Basemap {
 public:
  static constexpr int kMaxSidePx = 4096;  // texture size the map draws at most
  // Loads `path`: false (and the reason in the log) for a file GDAL cannot open, without a
  // geo-transform or coordinate system, rotated, or of a band type other than 8 bits; the basemap
  // shown before stays.
  bool Load(const std::string& path, double now, MessageLog& log);
  void Clear() { image_.reset(); }
  const std::optional<BasemapImage>& image() const { return image_; }

 private:
  std::optional<BasemapImage> image_;
  int64_t loads_ = 0;
};

}  // namespace uav::gcs
