#pragma once
// What a drone writes into each survey photo: EXIF (GPS position, focal length, camera model,
// time) and, where present, DJI-style XMP (gimbal and flight angles, height above take-off).
// Read with GDAL's JPEG driver (EXIF_* items, the xml:XMP domain), so uav-stitch can map a folder
// of geotagged photos from any drone without our capture files.
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Geometry>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::vision {

struct PhotoGeotag {
  int width = 0, height = 0;  // [px]
  std::string camera;         // EXIF Make and Model ("" when absent)
  GeodeticPoint position;     // EXIF GPS latitude, longitude [deg]; altitude [m] above mean sea level
  bool has_altitude = false;  // EXIF GPSAltitude present
  std::optional<double> focal_length_mm;           // EXIF FocalLength
  std::optional<double> focal_length_35mm_mm;      // EXIF FocalLengthIn35mmFilm
  std::optional<double> focal_plane_px_per_mm;     // EXIF FocalPlaneXResolution and its unit
  std::optional<double> height_above_takeoff_m;    // XMP RelativeAltitude
  // Camera angles [deg]: XMP GimbalYaw/Pitch/RollDegree (pitch -90: straight down), else XMP
  // FlightYawDegree or EXIF GPSImgDirection for the yaw; yaw clockwise from true north.
  std::optional<double> yaw_deg, pitch_deg, roll_deg;
  std::optional<int64_t> utime;  // [us] EXIF DateTimeOriginal (whole seconds), as UTC
};

// Throws std::invalid_argument naming the file and what is wrong: not an image, no GPS
// position, a malformed or out-of-range tag.
PhotoGeotag ReadPhotoGeotag(const std::string& path);

// The camera from the photo's EXIF: a pinhole without distortion, fx from the 35 mm equivalent
// focal length (over the image diagonal) or from the focal length and the focal plane
// resolution. Throws std::invalid_argument naming the file when neither is there.
CameraIntrinsics IntrinsicsFromGeotag(const PhotoGeotag& tag, const std::string& path);

// The camera's pose in NED (x right, y down, z along the optical axis) from the tag's angles:
// yaw, then pitch (-90: nadir), then roll, the image's top towards the yaw when looking down.
Eigen::Matrix3d RotationNCFromGeotag(double yaw_deg, double pitch_deg, double roll_deg);

}  // namespace uav::vision
