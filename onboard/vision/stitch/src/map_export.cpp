// GDAL lives in this one translation unit.
#include "uav/vision/map_export.hpp"

#include <cstdio>
#include <filesystem>
#include <future>
#include <stdexcept>

#include <gdal_priv.h>
#include <ogr_spatialref.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/text_file.hpp"

namespace uav::vision {

namespace {
constexpr const char* kWgs84Wkt =
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],PRIMEM[\"Greenwich\",0],"
    "UNIT[\"degree\",0.0174532925199433],AUTHORITY[\"EPSG\",\"4326\"]]";

// Geotransform in degrees: lon = t0 + c t1, lat = t3 + r t5 at pixel edges (GDAL convention).
struct Affine {
  double lon0, dlon, lat0, dlat;
};
Affine Transform(const Mosaic& map, const GeodeticPoint& home) {
  const LocalNedFrame frame(home);
  // Degrees per metre at the map's centre, from 1 m steps north and east.
  const double n_mid = map.north_top_m - 0.5 * map.bgr.rows * map.gsd_m;
  const double e_mid = map.east_left_m + 0.5 * map.bgr.cols * map.gsd_m;
  const GeodeticPoint c = frame.ToGeodetic({n_mid, e_mid, 0});
  const GeodeticPoint cn = frame.ToGeodetic({n_mid + 1, e_mid, 0});
  const GeodeticPoint ce = frame.ToGeodetic({n_mid, e_mid + 1, 0});
  const double deg_per_m_lat = cn.latitude_deg - c.latitude_deg;
  const double deg_per_m_lon = ce.longitude_deg - c.longitude_deg;
  Affine a;
  a.dlon = map.gsd_m * deg_per_m_lon;
  a.dlat = -map.gsd_m * deg_per_m_lat;
  a.lon0 = c.longitude_deg + (map.east_left_m - e_mid) * deg_per_m_lon;
  a.lat0 = c.latitude_deg + (map.north_top_m - n_mid) * deg_per_m_lat;
  return a;
}

void WriteGeoTiff(const cv::Mat& bgra, const Affine& a, const std::string& path) {
  GDALAllRegister();
  GDALDriver* driver = GetGDALDriverManager()->GetDriverByName("GTiff");
  if (!driver) throw std::runtime_error("GDAL has no GTiff driver");
  const std::string tmp = path + ".tmp";
  char** options = nullptr;
  // Deflate at its fastest level over horizontal differences: smaller than the default level
  // without them (1.68 against 1.86 MB on a 1-Mpx survey map) in a third of the time.
  options = CSLSetNameValue(options, "COMPRESS", "DEFLATE");
  options = CSLSetNameValue(options, "ZLEVEL", "1");
  options = CSLSetNameValue(options, "PREDICTOR", "2");
  options = CSLSetNameValue(options, "TILED", "YES");
  options = CSLSetNameValue(options, "ALPHA", "YES");
  options = CSLSetNameValue(options, "NUM_THREADS", "ALL_CPUS");  // tiles compressed in parallel
  GDALDataset* ds = driver->Create(tmp.c_str(), bgra.cols, bgra.rows, 4, GDT_Byte, options);
  CSLDestroy(options);
  if (!ds) throw std::runtime_error("cannot write '" + path + "': " + CPLGetLastErrorMsg());
  double gt[6] = {a.lon0, a.dlon, 0.0, a.lat0, 0.0, a.dlat};
  ds->SetGeoTransform(gt);
  ds->SetProjection(kWgs84Wkt);
  std::vector<cv::Mat> channels;
  cv::split(bgra, channels);
  const int order[4] = {2, 1, 0, 3};  // R G B A
  const GDALColorInterp interp[4] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
  CPLErr err = CE_None;
  for (int b = 0; b < 4 && err == CE_None; ++b) {
    GDALRasterBand* band = ds->GetRasterBand(b + 1);
    band->SetColorInterpretation(interp[b]);
    cv::Mat plane = channels[order[b]].clone();
    err = band->RasterIO(GF_Write, 0, 0, plane.cols, plane.rows, plane.data, plane.cols, plane.rows, GDT_Byte, 0, 0);
  }
  GDALClose(ds);
  if (err != CE_None) {
    std::filesystem::remove(tmp);
    throw std::runtime_error("cannot write '" + path + "': " + CPLGetLastErrorMsg());
  }
  std::filesystem::rename(tmp, path);
}

std::string Fmt(const char* f, double a) {
  char b[64];
  std::snprintf(b, sizeof b, f, a);
  return b;
}
}  // namespace

GeoBox MapBounds(const Mosaic& map, const GeodeticPoint& home) {
  const Affine a = Transform(map, home);
  GeoBox box;
  box.west_deg = a.lon0;
  box.east_deg = a.lon0 + map.bgr.cols * a.dlon;
  box.north_deg = a.lat0;
  box.south_deg = a.lat0 + map.bgr.rows * a.dlat;
  return box;
}

std::vector<std::string> ExportMap(const Mosaic& map, const GeodeticPoint& home, const std::string& prefix) {
  if (map.bgr.empty()) throw std::invalid_argument("map export: the map is empty");
  if (!map.georeferenced) throw std::invalid_argument("map export: the map has no ground reference (no poses)");
  ValidateGeodetic(home);
  const Affine a = Transform(map, home);
  cv::Mat bgra;
  cv::cvtColor(map.bgr, bgra, cv::COLOR_BGR2BGRA);
  cv::Mat alpha = map.mask.empty() ? cv::Mat(map.bgr.size(), CV_8U, cv::Scalar(255)) : map.mask;
  cv::insertChannel(alpha, bgra, 3);

  std::vector<std::string> written;
  // GDAL's drivers and OpenCV's codec table (which registers GDAL's too) are set up here, on one
  // thread: set up the first time from two threads at once, GDAL's registration crashed.
  GDALAllRegister();
  if (!cv::haveImageWriter(".png")) throw std::runtime_error("map export: this OpenCV cannot write PNG");
  // The PNG is compressed while the GeoTIFF is written.
  std::future<std::vector<uint8_t>> png_bytes = std::async(std::launch::async, [&bgra] {
    std::vector<uint8_t> png;
    if (!cv::imencode(".png", bgra, png)) png.clear();
    return png;
  });
  WriteGeoTiff(bgra, a, prefix + ".tif");
  written.push_back(prefix + ".tif");

  const std::vector<uint8_t> png = png_bytes.get();
  if (png.empty()) throw std::runtime_error("cannot encode '" + prefix + ".png'");
  WriteFileAtomically(prefix + ".png", std::string(png.begin(), png.end()));
  written.push_back(prefix + ".png");
  // World file: pixel size x, rotation, rotation, pixel size y, then the centre of the
  // upper-left pixel (ESRI convention).
  WriteFileAtomically(prefix + ".pgw", Fmt("%.12f\n", a.dlon) + "0\n0\n" + Fmt("%.12f\n", a.dlat) +
                                           Fmt("%.12f\n", a.lon0 + 0.5 * a.dlon) + Fmt("%.12f\n", a.lat0 + 0.5 * a.dlat));
  written.push_back(prefix + ".pgw");
  WriteFileAtomically(prefix + ".prj", std::string(kWgs84Wkt) + "\n");
  written.push_back(prefix + ".prj");

  const GeoBox box = MapBounds(map, home);
  const std::string name = std::filesystem::path(prefix).filename().string();
  WriteFileAtomically(prefix + ".kml",
                      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                      "<kml xmlns=\"http://www.opengis.net/kml/2.2\">\n"
                      "  <GroundOverlay>\n    <name>" + name + "</name>\n"
                      "    <Icon><href>" + name + ".png</href></Icon>\n"
                      "    <LatLonBox>\n"
                      "      <north>" + Fmt("%.9f", box.north_deg) + "</north>\n"
                      "      <south>" + Fmt("%.9f", box.south_deg) + "</south>\n"
                      "      <east>" + Fmt("%.9f", box.east_deg) + "</east>\n"
                      "      <west>" + Fmt("%.9f", box.west_deg) + "</west>\n"
                      "    </LatLonBox>\n  </GroundOverlay>\n</kml>\n");
  written.push_back(prefix + ".kml");
  return written;
}

}  // namespace uav::vision
