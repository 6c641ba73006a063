// Map export (issue 7 item 5): the GeoTIFF read back with GDAL has the map's pixels, a
// transparent unmapped area and the geotransform that puts its corners where the local frame
// says; the world file and the KML agree with it.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include "uav/vision/map_export.hpp"

namespace uav::vision {
namespace {

TEST(MapExport, GeoTiffWorldFileAndKmlPlaceTheMap) {
  Mosaic map;
  map.georeferenced = true;
  map.gsd_m = 0.05;
  map.north_top_m = 40.0;  // the top edge 40 m north of home
  map.east_left_m = -20.0;
  map.bgr = cv::Mat(300, 400, CV_8UC3, cv::Scalar(10, 120, 230));
  map.mask = cv::Mat(300, 400, CV_8U, cv::Scalar(255));
  map.mask(cv::Rect(0, 0, 50, 50)).setTo(0);  // an unmapped corner
  GeodeticPoint home;
  home.latitude_deg = 52.2383;
  home.longitude_deg = 4.5234;
  home.altitude_m = 0;
  const std::string prefix = (std::filesystem::temp_directory_path() / "uav_test_export_map").string();
  const auto files = ExportMap(map, home, prefix);
  ASSERT_EQ(files.size(), 5u);

  GDALAllRegister();
  GDALDataset* ds = static_cast<GDALDataset*>(GDALOpen((prefix + ".tif").c_str(), GA_ReadOnly));
  ASSERT_NE(ds, nullptr);
  EXPECT_EQ(ds->GetRasterXSize(), 400);
  EXPECT_EQ(ds->GetRasterYSize(), 300);
  ASSERT_EQ(ds->GetRasterCount(), 4);
  double gt[6];
  ASSERT_EQ(ds->GetGeoTransform(gt), CE_None);
  // The corners against the local frame: north-west corner 40 m N, 20 m W of home; 0.05 m pixels.
  const LocalNedFrame frame(home);
  const Eigen::Vector3d nw = frame.ToNed({gt[3], gt[0], 0});
  EXPECT_NEAR(nw.x(), 40.0, 0.01);
  EXPECT_NEAR(nw.y(), -20.0, 0.01);
  const Eigen::Vector3d se = frame.ToNed({gt[3] + 300 * gt[5], gt[0] + 400 * gt[1], 0});
  EXPECT_NEAR(se.x(), 40.0 - 15.0, 0.01);
  EXPECT_NEAR(se.y(), -20.0 + 20.0, 0.01);
  EXPECT_EQ(gt[2], 0.0);
  EXPECT_EQ(gt[4], 0.0);
  EXPECT_NE(std::string(ds->GetProjectionRef()).find("WGS 84"), std::string::npos);
  uint8_t rgba[4];
  for (int b = 0; b < 4; ++b)
    ASSERT_EQ(ds->GetRasterBand(b + 1)->RasterIO(GF_Read, 200, 200, 1, 1, &rgba[b], 1, 1, GDT_Byte, 0, 0), CE_None);
  EXPECT_EQ(rgba[0], 230);  // red (BGR 10, 120, 230)
  EXPECT_EQ(rgba[1], 120);
  EXPECT_EQ(rgba[2], 10);
  EXPECT_EQ(rgba[3], 255);
  uint8_t alpha = 1;
  ASSERT_EQ(ds->GetRasterBand(4)->RasterIO(GF_Read, 10, 10, 1, 1, &alpha, 1, 1, GDT_Byte, 0, 0), CE_None);
  EXPECT_EQ(alpha, 0);  // unmapped: transparent
  GDALClose(ds);

  // World file: the centre of the upper-left pixel is half a pixel inside the corner.
  std::ifstream pgw(prefix + ".pgw");
  double a, d, b, e, lon, lat;
  pgw >> a >> d >> b >> e >> lon >> lat;
  EXPECT_NEAR(a, gt[1], 1e-12);
  EXPECT_NEAR(e, gt[5], 1e-12);
  EXPECT_NEAR(lon, gt[0] + 0.5 * gt[1], 1e-11);
  EXPECT_NEAR(lat, gt[3] + 0.5 * gt[5], 1e-11);
  // KML: the same box.
  std::stringstream kml;
  kml << std::ifstream(prefix + ".kml").rdbuf();
  const GeoBox box = MapBounds(map, home);
  char north[64];
  std::snprintf(north, sizeof north, "<north>%.9f</north>", box.north_deg);
  EXPECT_NE(kml.str().find(north), std::string::npos);
  EXPECT_NEAR(box.north_deg, gt[3], 1e-12);
  EXPECT_NEAR(box.west_deg, gt[0], 1e-12);
  for (const auto& f : files) std::filesystem::remove(f);

  Mosaic pixels = map;
  pixels.georeferenced = false;
  EXPECT_THROW(ExportMap(pixels, home, prefix), std::invalid_argument);
  EXPECT_THROW(ExportMap(Mosaic(), home, prefix), std::invalid_argument);
}

}  // namespace
}  // namespace uav::vision
