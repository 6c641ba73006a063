#include "uav/gcs/basemap.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <gdal_priv.h>
#include <ogr_spatialref.h>

namespace uav::gcs {

bool Basemap::Load(const std::string& path, double now, MessageLog& log) {
  auto fail = [&](const std::string& why) {
    log.Add(now, "", "basemap " + path + ": " + why, Severity::kError);
    return false;
  };
  GDALAllRegister();
  std::unique_ptr<GDALDataset> ds(GDALDataset::Open(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
  if (!ds) return fail("not a raster GDAL can read (" + std::string(CPLGetLastErrorMsg()) + ")");
  const int bands = ds->GetRasterCount();
  if (bands != 1 && bands != 3 && bands != 4) return fail(std::to_string(bands) + " bands; grey, RGB or RGBA expected");
  for (int b = 1; b <= bands; ++b)
    if (ds->GetRasterBand(b)->GetRasterDataType() != GDT_Byte) return fail("band " + std::to_string(b) + " is not 8-bit");
  if (bands == 1 && ds->GetRasterBand(1)->GetColorTable()) return fail("a palette image; expand it to RGB first");
  double gt[6];
  if (ds->GetGeoTransform(gt) != CE_None) return fail("no geo-transform (not geo-referenced)");
  const OGRSpatialReference* srs = ds->GetSpatialRef();
  if (!srs) return fail("no coordinate system");
  OGRSpatialReference wgs84;
  wgs84.importFromEPSG(4326);
  wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);  // x = longitude
  OGRSpatialReference source(*srs);
  source.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
  std::unique_ptr<OGRCoordinateTransformation> to_wgs84(OGRCreateCoordinateTransformation(&source, &wgs84));
  if (!to_wgs84) return fail("its coordinate system cannot be turned into WGS84");

  BasemapImage image;
  image.path = path;
  image.source_width = ds->GetRasterXSize();
  image.source_height = ds->GetRasterYSize();
  // Outer corners in the file's coordinates (pixel edges), then to latitude and longitude.
  const double px[4] = {0.0, static_cast<double>(image.source_width), static_cast<double>(image.source_width), 0.0};
  const double py[4] = {0.0, 0.0, static_cast<double>(image.source_height), static_cast<double>(image.source_height)};
  double x[4], y[4];
  for (int i = 0; i < 4; ++i) {
    x[i] = gt[0] + px[i] * gt[1] + py[i] * gt[2];
    y[i] = gt[3] + px[i] * gt[4] + py[i] * gt[5];
  }
  if (!to_wgs84->Transform(4, x, y)) return fail("its corners cannot be placed in WGS84");
  for (int i = 0; i < 4; ++i) {
    if (!(std::abs(y[i]) <= 90.0 && std::abs(x[i]) <= 360.0)) return fail("its corners fall outside the Earth");
    image.corners[i].latitude_deg = y[i];
    image.corners[i].longitude_deg = x[i];
  }
  // Reduced to a texture: averaged, not sampled, so a large orthophoto does not shimmer.
  const double scale = std::min(1.0, static_cast<double>(kMaxSidePx) / std::max(image.source_width, image.source_height));
  image.width = std::max(1, static_cast<int>(std::lround(image.source_width * scale)));
  image.height = std::max(1, static_cast<int>(std::lround(image.source_height * scale)));
  image.rgba.assign(static_cast<size_t>(image.width) * image.height * 4, 255);
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  extra.eResampleAlg = GRIORA_Average;
  const GSpacing pixel = 4, line = static_cast<GSpacing>(image.width) * 4;
  for (int c = 0; c < 4; ++c) {
    // R, G, B from bands 1-3 (grey: band 1 three times); A from band 4 or the file's mask.
    GDALRasterBand* band = c < 3 ? ds->GetRasterBand(bands >= 3 ? c + 1 : 1)
                                 : (bands == 4 ? ds->GetRasterBand(4) : ds->GetRasterBand(1)->GetMaskBand());
    if (band->RasterIO(GF_Read, 0, 0, image.source_width, image.source_height, image.rgba.data() + c, image.width,
                       image.height, GDT_Byte, pixel, line, &extra) != CE_None)
      return fail("cannot read its pixels (" + std::string(CPLGetLastErrorMsg()) + ")");
  }
  image.version = ++loads_;
  char text[256];
  std::snprintf(text, sizeof text, "basemap %s: %dx%d px (drawn at %dx%d), %.6f %.6f to %.6f %.6f", path.c_str(),
                image.source_width, image.source_height, image.width, image.height, image.corners[0].latitude_deg,
                image.corners[0].longitude_deg, image.corners[2].latitude_deg, image.corners[2].longitude_deg);
  log.Add(now, "", text, Severity::kInfo);
  image_ = std::move(image);
  return true;
}

}  // namespace uav::gcs
