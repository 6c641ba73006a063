#pragma once
// Writes a JPEG as a drone does: EXIF tags (GDAL's JPEG driver writes EXIF_* metadata items) and
// an XMP packet (an APP1 segment after the start of image, as cameras write it). For tests of
// the geotag reader and of uav-stitch on geotagged photos.
#include <fstream>
#include <iterator>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>

#include <gdal_priv.h>
#include <opencv2/core.hpp>

namespace uav::test {

inline void WriteGeotaggedJpeg(const std::string& path, const cv::Mat& bgr, const std::map<std::string, std::string>& exif,
                               const std::string& xmp = "") {
  if (bgr.empty() || bgr.type() != CV_8UC3) throw std::invalid_argument(path + ": no 8-bit BGR image to write");
  GDALAllRegister();
  std::unique_ptr<GDALDataset> mem(
      GetGDALDriverManager()->GetDriverByName("MEM")->Create("", bgr.cols, bgr.rows, 3, GDT_Byte, nullptr));
  cv::Mat channels[3];
  cv::split(bgr, channels);
  for (int b = 0; b < 3; ++b) {
    cv::Mat plane = channels[2 - b].clone();  // R, G, B
    if (mem->GetRasterBand(b + 1)->RasterIO(GF_Write, 0, 0, plane.cols, plane.rows, plane.data, plane.cols, plane.rows,
                                            GDT_Byte, 0, 0) != CE_None)
      throw std::runtime_error("cannot fill " + path);
  }
  for (const auto& [tag, value] : exif) mem->SetMetadataItem(("EXIF_" + tag).c_str(), value.c_str());
  char** options = CSLSetNameValue(nullptr, "QUALITY", "95");
  GDALDataset* jpeg =
      GetGDALDriverManager()->GetDriverByName("JPEG")->CreateCopy(path.c_str(), mem.get(), FALSE, options, nullptr, nullptr);
  CSLDestroy(options);
  if (!jpeg) throw std::runtime_error("cannot write " + path);
  GDALClose(jpeg);
  std::remove((path + ".aux.xml").c_str());
  if (xmp.empty()) return;
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  in.close();
  const std::string payload = std::string("http://ns.adobe.com/xap/1.0/") + '\0' + xmp;
  const size_t length = payload.size() + 2;
  std::string segment = "\xFF\xE1";
  segment += static_cast<char>(length >> 8);
  segment += static_cast<char>(length & 0xff);
  bytes.insert(2, segment + payload);
  std::ofstream(path, std::ios::binary) << bytes;
}

// DJI's XMP properties as attributes of one rdf:Description.
inline std::string DjiXmp(const std::map<std::string, std::string>& properties) {
  std::string attributes;
  for (const auto& [name, value] : properties) attributes += " drone-dji:" + name + "=\"" + value + "\"";
  return "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">"
         "<rdf:Description xmlns:drone-dji=\"http://www.dji.com/drone-dji/1.0/\"" +
         attributes + "/></rdf:RDF></x:xmpmeta>";
}

// Degrees as EXIF's degrees, minutes, seconds.
inline std::string Dms(double deg) {
  deg = std::abs(deg);
  const int d = static_cast<int>(deg);
  const int m = static_cast<int>((deg - d) * 60);
  const double s = (deg - d - m / 60.0) * 3600;
  char text[64];
  std::snprintf(text, sizeof text, "(%d) (%d) (%.4f)", d, m, s);
  return text;
}

}  // namespace uav::test
