// The Map panel's basemap: GeoTIFFs in WGS84 (as uav-stitch writes them) and in UTM (as
// OpenDroneMap writes them) placed by their corners, reduced to a texture, and the files that
// cannot be shown refused by name with the basemap shown before kept.
#include <filesystem>
#include <memory>

#include <gdal_priv.h>
#include <gtest/gtest.h>
#include <ogr_spatialref.h>

#include "uav/gcs/basemap.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::gcs {
namespace {

const std::string kDir = (std::filesystem::temp_directory_path() / "uav_test_basemap").string();

// A raster of `bands` 8-bit bands: band b holds 40 b + 10; pixels with x < 10 are no-data (0).
std::string Write(const std::string& name, int width, int height, int bands, int epsg, const double gt[6]) {
  GDALAllRegister();
  std::filesystem::create_directories(kDir);
  const std::string path = kDir + "/" + name;
  std::unique_ptr<GDALDataset> ds(
      GetGDALDriverManager()->GetDriverByName("GTiff")->Create(path.c_str(), width, height, bands, GDT_Byte, nullptr));
  if (gt) ds->SetGeoTransform(const_cast<double*>(gt));
  if (epsg) {
    OGRSpatialReference srs;
    srs.importFromEPSG(epsg);
    ds->SetSpatialRef(&srs);
  }
  std::vector<uint8_t> plane(static_cast<size_t>(width) * height);
  for (int b = 1; b <= bands; ++b) {
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) plane[y * width + x] = x < 10 ? 0 : static_cast<uint8_t>(40 * b + 10);
    ds->GetRasterBand(b)->SetNoDataValue(0);
    EXPECT_EQ(ds->GetRasterBand(b)->RasterIO(GF_Write, 0, 0, width, height, plane.data(), width, height, GDT_Byte, 0, 0), CE_None);
  }
  return path;
}

TEST(Basemap, PlacesAWgs84MapByItsCorners) {
  // 200 x 100 px at 1e-5 deg from (52.24 N, 4.52 E) at the top-left edge.
  const double gt[6] = {4.52, 1e-5, 0, 52.24, 0, -1e-5};
  MessageLog log;
  Basemap basemap;
  ASSERT_TRUE(basemap.Load(Write("wgs84.tif", 200, 100, 3, 4326, gt), 1.0, log)) << log.lines().back().text;
  const BasemapImage& image = *basemap.image();
  EXPECT_EQ(image.width, 200);
  EXPECT_EQ(image.height, 100);
  EXPECT_NEAR(image.corners[0].latitude_deg, 52.24, 1e-12);
  EXPECT_NEAR(image.corners[0].longitude_deg, 4.52, 1e-12);
  EXPECT_NEAR(image.corners[2].latitude_deg, 52.239, 1e-12);
  EXPECT_NEAR(image.corners[2].longitude_deg, 4.522, 1e-12);
  // RGB from the bands; transparent where the file has no data.
  const uint8_t* inside = &image.rgba[(50 * 200 + 100) * 4];
  EXPECT_EQ(inside[0], 50);
  EXPECT_EQ(inside[1], 90);
  EXPECT_EQ(inside[2], 130);
  EXPECT_EQ(inside[3], 255);
  EXPECT_EQ(image.rgba[(50 * 200 + 2) * 4 + 3], 0);
  EXPECT_EQ(log.lines().back().severity, Severity::kInfo);
}

TEST(Basemap, ReprojectsUtmAndReducesLargeFiles) {
  // 5000 x 100 px of 0.08 m in UTM 31N near Oostdorp: 400 m by 8 m on the ground.
  const double gt[6] = {600000.0, 0.08, 0, 5788000.0, 0, -0.08};
  MessageLog log;
  Basemap basemap;
  ASSERT_TRUE(basemap.Load(Write("utm.tif", 5000, 100, 1, 32631, gt), 1.0, log)) << log.lines().back().text;
  const BasemapImage& image = *basemap.image();
  EXPECT_EQ(image.width, Basemap::kMaxSidePx);
  EXPECT_EQ(image.height, 82);
  // The corners 400 m apart east-west, 8 m north-south (UTM's scale factor: within 0.1 %).
  const LocalNedFrame ned(image.corners[0]);
  const Eigen::Vector3d top_right = ned.ToNed(image.corners[1]), bottom_left = ned.ToNed(image.corners[3]);
  EXPECT_NEAR(top_right.head<2>().norm(), 400.0, 0.4);
  EXPECT_NEAR(bottom_left.head<2>().norm(), 8.0, 0.01);
  // UTM's grid north is turned from true north east of the central meridian (3 deg E).
  EXPECT_GT(std::abs(top_right.x()), 1.0);
  EXPECT_NEAR(image.corners[0].latitude_deg, 52.23, 0.01);
  EXPECT_NEAR(image.corners[0].longitude_deg, 4.47, 0.01);
}

TEST(Basemap, RefusesWhatItCannotPlaceAndKeepsThePreviousOne) {
  const double gt[6] = {4.52, 1e-5, 0, 52.24, 0, -1e-5};
  MessageLog log;
  Basemap basemap;
  ASSERT_TRUE(basemap.Load(Write("good.tif", 50, 50, 4, 4326, gt), 1.0, log));
  auto refused = [&](const std::string& path, const std::string& words) {
    EXPECT_FALSE(basemap.Load(path, 2.0, log)) << path;
    EXPECT_EQ(log.lines().back().severity, Severity::kError);
    EXPECT_NE(log.lines().back().text.find(words), std::string::npos) << log.lines().back().text;
    EXPECT_NE(log.lines().back().text.find(path), std::string::npos) << log.lines().back().text;
  };
  refused(kDir + "/missing.tif", "not a raster GDAL can read");
  refused(Write("plain.tif", 50, 50, 3, 0, nullptr), "no geo-transform");
  refused(Write("nocrs.tif", 50, 50, 3, 0, gt), "no coordinate system");
  refused(Write("two.tif", 50, 50, 2, 4326, gt), "2 bands");
  ASSERT_TRUE(basemap.image());
  EXPECT_EQ(basemap.image()->path, kDir + "/good.tif");
  EXPECT_EQ(basemap.image()->version, 1);
}

}  // namespace
}  // namespace uav::gcs
