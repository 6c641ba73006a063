#include "uav/vision/photo_geotag.hpp"

#include <cmath>
#include <ctime>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <gdal_priv.h>

#include "uav/shared/frames.hpp"

namespace uav::vision {
namespace {

[[noreturn]] void Fail(const std::string& path, const std::string& what) {
  throw std::invalid_argument(path + ": " + what);
}

// GDAL writes EXIF rationals as "(52) (14) (17.88)"; integers and strings bare.
std::vector<double> Numbers(const char* text, const std::string& path, const std::string& tag) {
  std::vector<double> out;
  std::string s(text);
  for (char& c : s)
    if (c == '(' || c == ')' || c == ',') c = ' ';
  std::istringstream in(s);
  std::string word;
  while (in >> word) {
    char* end = nullptr;
    const double v = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0' || !std::isfinite(v)) Fail(path, "EXIF " + tag + " is not a number: '" + text + "'");
    out.push_back(v);
  }
  if (out.empty()) Fail(path, "EXIF " + tag + " is empty");
  return out;
}

std::optional<double> Number(GDALDataset& ds, const std::string& tag, const std::string& path) {
  const char* v = ds.GetMetadataItem(("EXIF_" + tag).c_str());
  if (!v) return std::nullopt;
  return Numbers(v, path, tag)[0];
}

// Degrees, minutes, seconds and the N/S or E/W reference.
double Angle(GDALDataset& ds, const std::string& tag, char negative, double limit, const std::string& path) {
  const char* v = ds.GetMetadataItem(("EXIF_" + tag).c_str());
  if (!v) Fail(path, "no EXIF " + tag + " (not a geotagged photo)");
  const std::vector<double> dms = Numbers(v, path, tag);
  double deg = dms[0] + (dms.size() > 1 ? dms[1] / 60.0 : 0.0) + (dms.size() > 2 ? dms[2] / 3600.0 : 0.0);
  const char* ref = ds.GetMetadataItem(("EXIF_" + tag + "Ref").c_str());
  if (ref && std::toupper(static_cast<unsigned char>(ref[0])) == negative) deg = -deg;
  if (!(std::abs(deg) <= limit)) Fail(path, "EXIF " + tag + " " + std::to_string(deg) + " deg is out of range");
  return deg;
}

// A DJI-style XMP property, written as an attribute (drone-dji:Name="+1.5") or an element
// (<drone-dji:Name>+1.5</drone-dji:Name>), whatever the namespace prefix.
std::optional<double> XmpNumber(const std::string& xmp, const std::string& name, const std::string& path) {
  for (size_t at = xmp.find(":" + name); at != std::string::npos; at = xmp.find(":" + name, at + 1)) {
    size_t p = at + 1 + name.size();
    if (p >= xmp.size()) break;
    char close;
    if (xmp.compare(p, 2, "=\"") == 0) {
      p += 2;
      close = '"';
    } else if (xmp[p] == '>') {
      p += 1;
      close = '<';
    } else {
      continue;  // a longer name sharing the prefix
    }
    const size_t end = xmp.find(close, p);
    if (end == std::string::npos) break;
    const std::string text = xmp.substr(p, end - p);
    char* stop = nullptr;
    const double v = std::strtod(text.c_str(), &stop);
    if (stop == text.c_str() || !std::isfinite(v)) Fail(path, "XMP " + name + " is not a number: '" + text + "'");
    return v;
  }
  return std::nullopt;
}

std::optional<int64_t> Time(GDALDataset& ds) {
  const char* v = ds.GetMetadataItem("EXIF_DateTimeOriginal");
  if (!v) return std::nullopt;
  std::tm t{};
  if (std::sscanf(v, "%d:%d:%d %d:%d:%d", &t.tm_year, &t.tm_mon, &t.tm_mday, &t.tm_hour, &t.tm_min, &t.tm_sec) != 6)
    return std::nullopt;  // some cameras leave it blank; the order of the files still holds
  t.tm_year -= 1900;
  t.tm_mon -= 1;
  const time_t seconds = timegm(&t);
  if (seconds == -1) return std::nullopt;
  return static_cast<int64_t>(seconds) * 1'000'000;
}

}  // namespace

PhotoGeotag ReadPhotoGeotag(const std::string& path) {
  GDALAllRegister();
  const char* const drivers[] = {"JPEG", nullptr};
  std::unique_ptr<GDALDataset> ds(
      GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, drivers, nullptr, nullptr));
  if (!ds) Fail(path, "not a JPEG photo");
  PhotoGeotag tag;
  tag.width = ds->GetRasterXSize();
  tag.height = ds->GetRasterYSize();
  const char* make = ds->GetMetadataItem("EXIF_Make");
  const char* model = ds->GetMetadataItem("EXIF_Model");
  tag.camera = std::string(make ? make : "") + (make && model ? " " : "") + (model ? model : "");
  tag.position.latitude_deg = Angle(*ds, "GPSLatitude", 'S', 90.0, path);
  tag.position.longitude_deg = Angle(*ds, "GPSLongitude", 'W', 180.0, path);
  if (const std::optional<double> alt = Number(*ds, "GPSAltitude", path)) {
    const char* ref = ds->GetMetadataItem("EXIF_GPSAltitudeRef");
    // GPSAltitudeRef 1: below sea level. GDAL shows the byte as "1" or "0x01".
    const bool below = ref && (std::string(ref) == "1" || std::string(ref) == "0x01" || std::string(ref) == "(1)");
    tag.position.altitude_m = below ? -*alt : *alt;
    tag.has_altitude = true;
    if (std::abs(tag.position.altitude_m) > 20000) Fail(path, "EXIF GPSAltitude " + std::to_string(*alt) + " m is out of range");
  }
  tag.focal_length_mm = Number(*ds, "FocalLength", path);
  tag.focal_length_35mm_mm = Number(*ds, "FocalLengthIn35mmFilm", path);
  if (const std::optional<double> res = Number(*ds, "FocalPlaneXResolution", path)) {
    const std::optional<double> unit = Number(*ds, "FocalPlaneResolutionUnit", path);
    // Unit 2: inch (the default), 3: cm, 4: mm, 5: um.
    const double mm_per_unit = !unit || *unit == 2 ? 25.4 : *unit == 3 ? 10.0 : *unit == 4 ? 1.0 : *unit == 5 ? 1e-3 : 0.0;
    if (mm_per_unit > 0 && *res > 0) tag.focal_plane_px_per_mm = *res / mm_per_unit;
  }
  for (auto* f : {&tag.focal_length_mm, &tag.focal_length_35mm_mm})
    if (*f && !(**f > 0 && **f < 5000)) Fail(path, "EXIF focal length " + std::to_string(**f) + " mm is out of range");
  tag.yaw_deg = Number(*ds, "GPSImgDirection", path);
  if (char** xmp = ds->GetMetadata("xml:XMP"); xmp && xmp[0]) {
    const std::string x(xmp[0]);
    tag.height_above_takeoff_m = XmpNumber(x, "RelativeAltitude", path);
    const std::optional<double> flight_yaw = XmpNumber(x, "FlightYawDegree", path);
    const std::optional<double> gimbal_yaw = XmpNumber(x, "GimbalYawDegree", path);
    if (gimbal_yaw) tag.yaw_deg = gimbal_yaw;
    else if (flight_yaw) tag.yaw_deg = flight_yaw;
    tag.pitch_deg = XmpNumber(x, "GimbalPitchDegree", path);
    tag.roll_deg = XmpNumber(x, "GimbalRollDegree", path);
  }
  for (const auto& [angle, name, limit] : {std::tuple{tag.yaw_deg, "yaw", 360.0}, std::tuple{tag.pitch_deg, "pitch", 180.0},
                                          std::tuple{tag.roll_deg, "roll", 180.0}})
    if (angle && std::abs(*angle) > limit) Fail(path, std::string("camera ") + name + " " + std::to_string(*angle) + " deg is out of range");
  tag.utime = Time(*ds);
  return tag;
}

CameraIntrinsics IntrinsicsFromGeotag(const PhotoGeotag& tag, const std::string& path) {
  CameraIntrinsics k;
  k.width = tag.width;
  k.height = tag.height;
  if (tag.focal_length_35mm_mm) {
    // The 35 mm equivalent is the focal length that gives the same field of view over a
    // 36 x 24 mm frame's diagonal (43.27 mm).
    k.fx = *tag.focal_length_35mm_mm * std::hypot(tag.width, tag.height) / std::hypot(36.0, 24.0);
  } else if (tag.focal_length_mm && tag.focal_plane_px_per_mm) {
    k.fx = *tag.focal_length_mm * *tag.focal_plane_px_per_mm;
  } else {
    throw std::invalid_argument(path +
                                ": no focal length to derive the camera from (EXIF FocalLengthIn35mmFilm, or FocalLength "
                                "with FocalPlaneXResolution); give --camera FILE");
  }
  k.fy = k.fx;
  k.cx = (k.width - 1) / 2.0;
  k.cy = (k.height - 1) / 2.0;
  ValidateIntrinsics(k);
  return k;
}

Eigen::Matrix3d RotationNCFromGeotag(double yaw_deg, double pitch_deg, double roll_deg) {
  // A gimbal's angles are the camera's own yaw, pitch and roll about NED (z-y-x, Eq. 5.51), the
  // optical axis along the "body" x axis: RotationBCForward puts the camera on that axis.
  EulerAngles e;
  e.psi = yaw_deg * M_PI / 180.0;
  e.theta = pitch_deg * M_PI / 180.0;
  e.phi = roll_deg * M_PI / 180.0;
  return RotationNBFromEuler(e) * RotationBCForward();
}

}  // namespace uav::vision
