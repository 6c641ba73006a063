// The geotag reader on photos written as drones write them: EXIF GPS and lens tags, DJI XMP
// (attributes and elements), and the bad tags a real folder holds.
#include <cmath>
#include <filesystem>

#include <gtest/gtest.h>

#include "geotagged_jpeg.hpp"
#include "uav/vision/photo_geotag.hpp"

namespace uav::vision {
namespace {

const std::string kDir = (std::filesystem::temp_directory_path() / "uav_test_photo_geotag").string();

std::string Photo(const std::string& name, const std::map<std::string, std::string>& exif, const std::string& xmp = "") {
  std::filesystem::create_directories(kDir);
  const std::string path = kDir + "/" + name;
  test::WriteGeotaggedJpeg(path, cv::Mat(300, 400, CV_8UC3, cv::Scalar(80, 120, 90)), exif, xmp);
  return path;
}

std::map<std::string, std::string> Gps(double lat, double lon) {
  return {{"GPSLatitude", test::Dms(lat)},
          {"GPSLatitudeRef", lat < 0 ? "S" : "N"},
          {"GPSLongitude", test::Dms(lon)},
          {"GPSLongitudeRef", lon < 0 ? "W" : "E"}};
}

TEST(PhotoGeotag, ReadsGpsLensTimeAndDjiGimbal) {
  auto exif = Gps(52.238312, 4.523456);
  exif["GPSAltitude"] = "(72.5)";
  exif["Make"] = "DJI";
  exif["Model"] = "FC6310";
  exif["FocalLength"] = "(8.8)";
  exif["FocalLengthIn35mmFilm"] = "24";
  exif["DateTimeOriginal"] = "2026:11:23 10:00:01";
  const std::string path = Photo("dji.jpg", exif,
                                 test::DjiXmp({{"RelativeAltitude", "+40.20"},
                                               {"GimbalYawDegree", "+12.5"},
                                               {"GimbalPitchDegree", "-89.9"},
                                               {"GimbalRollDegree", "+0.00"},
                                               {"FlightYawDegree", "+10.0"}}));
  const PhotoGeotag tag = ReadPhotoGeotag(path);
  EXPECT_EQ(tag.width, 400);
  EXPECT_EQ(tag.height, 300);
  EXPECT_EQ(tag.camera, "DJI FC6310");
  EXPECT_NEAR(tag.position.latitude_deg, 52.238312, 1e-6);  // 0.1 m
  EXPECT_NEAR(tag.position.longitude_deg, 4.523456, 1e-6);
  EXPECT_TRUE(tag.has_altitude);
  EXPECT_NEAR(tag.position.altitude_m, 72.5, 1e-6);
  EXPECT_NEAR(*tag.height_above_takeoff_m, 40.2, 1e-9);
  EXPECT_NEAR(*tag.yaw_deg, 12.5, 1e-9);  // the gimbal's, not the airframe's
  EXPECT_NEAR(*tag.pitch_deg, -89.9, 1e-9);
  EXPECT_NEAR(*tag.roll_deg, 0.0, 1e-9);
  ASSERT_TRUE(tag.utime);
  EXPECT_EQ(*tag.utime, 1795428001LL * 1'000'000);  // 2026-11-23T10:00:01Z
  // 24 mm equivalent over the 500 px diagonal: 24 * 500 / 43.27 px.
  const CameraIntrinsics k = IntrinsicsFromGeotag(tag, path);
  EXPECT_NEAR(k.fx, 24.0 * 500.0 / std::hypot(36.0, 24.0), 1e-9);
  EXPECT_EQ(k.width, 400);
}

TEST(PhotoGeotag, SouthWestElementsAndFocalPlane) {
  auto exif = Gps(-33.5, -70.25);
  exif["FocalLength"] = "(3.6)";
  exif["FocalPlaneXResolution"] = "(83.3333)";  // px per mm
  exif["FocalPlaneResolutionUnit"] = "4";
  exif["GPSImgDirection"] = "(270.5)";
  const std::string xmp =
      "<x:xmpmeta xmlns:x=\"adobe:ns:meta/\"><rdf:RDF xmlns:rdf=\"http://www.w3.org/1999/02/22-rdf-syntax-ns#\">"
      "<rdf:Description><drone-dji:GimbalPitchDegree>-45.0</drone-dji:GimbalPitchDegree></rdf:Description>"
      "</rdf:RDF></x:xmpmeta>";
  const std::string path = Photo("sw.jpg", exif, xmp);
  const PhotoGeotag tag = ReadPhotoGeotag(path);
  EXPECT_NEAR(tag.position.latitude_deg, -33.5, 1e-6);
  EXPECT_NEAR(tag.position.longitude_deg, -70.25, 1e-6);
  EXPECT_FALSE(tag.has_altitude);
  EXPECT_NEAR(*tag.yaw_deg, 270.5, 1e-9);  // no gimbal yaw: the image direction
  EXPECT_NEAR(*tag.pitch_deg, -45.0, 1e-9);
  EXPECT_FALSE(tag.height_above_takeoff_m);
  EXPECT_NEAR(IntrinsicsFromGeotag(tag, path).fx, 3.6 * 83.3333, 1e-3);
}

TEST(PhotoGeotag, NamesWhatIsWrong) {
  auto expect_error = [](const std::string& path, const std::string& words) {
    try {
      ReadPhotoGeotag(path);
      ADD_FAILURE() << path << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  };
  expect_error(Photo("plain.jpg", {{"Model", "X"}}), "no EXIF GPSLatitude");
  auto far = Gps(10, 10);
  far["GPSLatitude"] = "(95) (0) (0)";
  expect_error(Photo("far.jpg", far), "GPSLatitude 95");
  auto high = Gps(10, 10);
  high["GPSAltitude"] = "(25000)";
  expect_error(Photo("high.jpg", high), "GPSAltitude 25000");
  expect_error(Photo("yaw.jpg", Gps(10, 10), test::DjiXmp({{"GimbalYawDegree", "north"}})), "GimbalYawDegree is not a number");
  std::ofstream(kDir + "/text.jpg") << "not a photo";
  expect_error(kDir + "/text.jpg", "not a JPEG photo");
  // No focal length at all: the camera cannot be derived; the message says what to give.
  const std::string bare = Photo("bare.jpg", Gps(10, 10));
  try {
    IntrinsicsFromGeotag(ReadPhotoGeotag(bare), bare);
    ADD_FAILURE() << "no focal length accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("--camera"), std::string::npos) << e.what();
  }
}

TEST(PhotoGeotag, NadirCameraLooksDownWithTheImageTopAlongTheYaw) {
  // Yaw 90 (east), pitch -90: optical axis down, image top (-y) east, image right (+x) south.
  const Eigen::Matrix3d R_NC = RotationNCFromGeotag(90, -90, 0);
  EXPECT_TRUE(R_NC.col(2).isApprox(Eigen::Vector3d(0, 0, 1), 1e-12)) << R_NC;
  EXPECT_TRUE((-R_NC.col(1)).isApprox(Eigen::Vector3d(0, 1, 0), 1e-12)) << R_NC;
  EXPECT_TRUE(R_NC.col(0).isApprox(Eigen::Vector3d(-1, 0, 0), 1e-12)) << R_NC;
  // Pitch -45 looking north: the axis halfway between north and down.
  const Eigen::Matrix3d oblique = RotationNCFromGeotag(0, -45, 0);
  EXPECT_TRUE(oblique.col(2).isApprox(Eigen::Vector3d(1, 0, 1).normalized(), 1e-12)) << oblique;
}

}  // namespace
}  // namespace uav::vision
