// uav-stitch on a capture folder written by the onboard camera thread (CameraWorker): a 60 m
// line at 30 m over the village. Checks the outputs exist, the report (placements, alignment),
// that the world file puts the map where the vehicle flew, and a plain folder of photos.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "geotagged_jpeg.hpp"
#include "uav/sim/sim_cameras.hpp"
#include "uav/world/scene.hpp"
#include "uav/runtime/camera_worker.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::runtime {
namespace {

std::string Slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST(UavStitch, StitchesACaptureFolderIntoGeoreferencedFiles) {
  const world::Scene scene =
      world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
  const std::string dir = (std::filesystem::temp_directory_path() / "uav_test_stitch_cli").string();
  std::filesystem::remove_all(dir);
  GeodeticPoint home;
  home.latitude_deg = 52.2383;  // Oostdorp (thesis 6.5)
  home.longitude_deg = 4.5234;
  home.altitude_m = 40;
  Blackboard board;
  board.Update([](BlackboardData& d) { d.capture_interval_s = 0.2; });
  CameraWorker::Options options;
  options.capture_dir = dir + "/captures";
  options.home = home;
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  sim::SimCamera camera(scene, *scene.downward_camera(), [&](int64_t) { return T_NB; });
  CameraWorker worker(camera, board, options);
  for (int i = 0; i < 60; ++i) {  // north at 5 m/s, 5 Hz
    T_NB.translation() = Eigen::Vector3d(-30 + i, 10, -30);
    board.Update([&](BlackboardData& d) {
      d.estimate.p_N = T_NB.translation();
      d.estimate.euler = EulerAngles();
    });
    worker.Tick(1'000'000 + i * 200'000);
  }
  ASSERT_EQ(worker.captures(), 60);
  const std::string command = std::string(UAV_STITCH_BIN) + " " + dir + "/captures --out " + dir + "/map --report " + dir +
                              "/report.json > " + dir + "/stdout.txt 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << Slurp(dir + "/stdout.txt");
  for (const char* ext : {".tif", ".png", ".pgw", ".prj", ".kml"})
    EXPECT_TRUE(std::filesystem::exists(dir + "/map" + ext)) << ext;
  const std::string report = Slurp(dir + "/report.json");
  EXPECT_NE(report.find("\"placed\": 60"), std::string::npos) << report;
  const nlohmann::json r = nlohmann::json::parse(report);
  EXPECT_TRUE(r["alignment"]["adjusted"].get<bool>()) << r["alignment"];
  ASSERT_EQ(r["placements"].size(), 60u);
  EXPECT_EQ(r["placements"][0]["corners_lat_lon_deg"].size(), 4u);
  EXPECT_EQ(r["placements"][0]["H_map_img"].size(), 9u);
  EXPECT_LT(r["alignment"]["all_after"]["p95_px"].get<double>(), 2.0) << r["alignment"];

  // A plain folder of photos (no session.json, no poses): a map in pixels from the ones that
  // can be used; a broken file and a photo from another camera are named and left out.
  const std::string plain = dir + "/plain";
  std::filesystem::create_directories(plain);
  for (int i = 0; i < 20; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "IMG_%06d.jpg", i + 1);
    std::filesystem::copy_file(dir + "/captures/" + name, plain + "/" + name);
  }
  std::ofstream(plain + "/IMG_000010b.jpg") << "not a jpeg";
  // A truncated copy and a garbled copy: named and left out, never stitched as a grey smear.
  const std::string whole = Slurp(dir + "/captures/IMG_000005.jpg");
  std::ofstream(plain + "/IMG_000005t.jpg", std::ios::binary) << whole.substr(0, whole.size() / 2);
  std::string garbled = whole;
  for (std::size_t i = 0; i < 2000; ++i) garbled[garbled.size() / 2 + i] = static_cast<char>((i * 37 + 11) & 0xFF);
  std::ofstream(plain + "/IMG_000006g.jpg", std::ios::binary) << garbled;
  cv::imwrite(plain + "/IMG_000015b.jpg", cv::Mat(240, 320, CV_8UC3, cv::Scalar(90, 120, 60)));
  const std::string plain_command = std::string(UAV_STITCH_BIN) + " " + plain + " --out " + dir + "/pixels --report " +
                                    dir + "/plain.json > " + dir + "/plain.txt 2>&1";
  ASSERT_EQ(std::system(plain_command.c_str()), 0) << Slurp(dir + "/plain.txt");
  const nlohmann::json p = nlohmann::json::parse(Slurp(dir + "/plain.json"));
  EXPECT_EQ(p["placed"], 20);
  EXPECT_FALSE(p["georeferenced"].get<bool>());
  ASSERT_EQ(p["skipped"].size(), 4u) << p["skipped"];
  EXPECT_NE(p["skipped"][0].get<std::string>().find("IMG_000005t.jpg: corrupt JPEG (Premature end of JPEG file)"),
            std::string::npos) << p["skipped"][0];
  EXPECT_NE(p["skipped"][1].get<std::string>().find("IMG_000006g.jpg: corrupt JPEG ("), std::string::npos)
      << p["skipped"][1];
  EXPECT_NE(p["skipped"][2].get<std::string>().find("IMG_000010b.jpg: map stitcher: not an image"), std::string::npos);
  EXPECT_NE(p["skipped"][3].get<std::string>().find("320x240, the camera's is 640x480"), std::string::npos);
  const cv::Mat pixels = cv::imread(dir + "/pixels.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(pixels.channels(), 4);
  // 20 frames 1 m apart, north up, at 30 m (the 640 px footprint is 40 m wide: 16 px per metre):
  // the strip is 19 m (304 px) longer than one frame. Chained by registration alone over roofs
  // and trees it comes out 889 x 711 px (measured): without poses the scale wanders.
  EXPECT_GT(pixels.rows, 480 + 200);
  EXPECT_LT(pixels.rows, 480 + 500);
  EXPECT_LT(pixels.cols, 800);
  EXPECT_FALSE(std::filesystem::exists(dir + "/pixels.tif"));

  // The same line as a drone's geotagged photos (EXIF GPS and lens, DJI XMP with the height
  // above take-off and the gimbal): a geo-referenced map with each photo where it was taken.
  // A photo without GPS, one with a latitude of 95 deg and one from another camera are named
  // and left out.
  const std::string tagged = dir + "/geotagged";
  std::filesystem::create_directories(tagged);
  const LocalNedFrame ned(home);
  auto exif_at = [&](const Eigen::Vector3d& p_N) {
    const GeodeticPoint g = ned.ToGeodetic(p_N);
    return std::map<std::string, std::string>{{"GPSLatitude", test::Dms(g.latitude_deg)},
                                              {"GPSLatitudeRef", "N"},
                                              {"GPSLongitude", test::Dms(g.longitude_deg)},
                                              {"GPSLongitudeRef", "E"},
                                              {"GPSAltitude", "(" + std::to_string(g.altitude_m) + ")"},
                                              {"Make", "Sim"},
                                              {"Model", "Downward 640"},
                                              {"FocalLength", "(3.6)"},
                                              {"FocalPlaneXResolution", "(133.3333)"},  // 640 px over 4.8 mm
                                              {"FocalPlaneResolutionUnit", "4"}};
  };
  const std::string nadir_xmp = test::DjiXmp(
      {{"RelativeAltitude", "+30.00"}, {"GimbalYawDegree", "+0.0"}, {"GimbalPitchDegree", "-90.0"}, {"GimbalRollDegree", "0.0"}});
  for (int i = 0; i < 60; ++i) {
    char name[32];
    std::snprintf(name, sizeof name, "IMG_%06d.jpg", i);
    const cv::Mat image = cv::imread(dir + "/captures/" + name);
    test::WriteGeotaggedJpeg(tagged + "/DJI_" + std::string(name + 4), image, exif_at({-30.0 + i, 10.0, -30.0}), nadir_xmp);
  }
  const cv::Mat any = cv::imread(dir + "/captures/IMG_000030.jpg");
  test::WriteGeotaggedJpeg(tagged + "/DJI_000030a.jpg", any, {{"Model", "Downward 640"}}, nadir_xmp);
  auto far = exif_at({0, 10, -30});
  far["GPSLatitude"] = "(95) (0) (0)";
  test::WriteGeotaggedJpeg(tagged + "/DJI_000030b.jpg", any, far, nadir_xmp);
  auto other = exif_at({0, 10, -30});
  other["Model"] = "Thermal 320";
  cv::Mat small;
  cv::resize(any, small, cv::Size(320, 240));
  test::WriteGeotaggedJpeg(tagged + "/DJI_000030c.jpg", small, other, nadir_xmp);
  const std::string tagged_command = std::string(UAV_STITCH_BIN) + " " + tagged + " --out " + dir + "/tagged --report " +
                                     dir + "/tagged.json > " + dir + "/tagged.txt 2>&1";
  ASSERT_EQ(std::system(tagged_command.c_str()), 0) << Slurp(dir + "/tagged.txt");
  const nlohmann::json t = nlohmann::json::parse(Slurp(dir + "/tagged.json"));
  EXPECT_EQ(t["input"], "geotagged photos");
  EXPECT_TRUE(t["georeferenced"].get<bool>());
  EXPECT_EQ(t["placed"], 60);
  EXPECT_NEAR(t["camera"]["fx"].get<double>(), 480.0, 0.01);
  ASSERT_EQ(t["skipped"].size(), 3u) << t["skipped"];
  EXPECT_NE(t["skipped"][0].get<std::string>().find("DJI_000030a.jpg: no EXIF GPSLatitude"), std::string::npos);
  EXPECT_NE(t["skipped"][1].get<std::string>().find("DJI_000030b.jpg: EXIF GPSLatitude 95"), std::string::npos);
  EXPECT_NE(t["skipped"][2].get<std::string>().find("another camera"), std::string::npos);
  for (const std::string ext : {".tif", ".png", ".pgw", ".kml"}) EXPECT_TRUE(std::filesystem::exists(dir + "/tagged" + ext)) << ext;
  // Each photo's footprint centre against where it was taken (the NED origin is the ground under
  // the first photo, so compare in the map's own frame: offsets from the first photo).
  ASSERT_EQ(t["placements"].size(), 60u);
  double worst_m = 0;
  for (int i = 0; i < 60; ++i) {
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& c : t["placements"][i]["corners_lat_lon_deg"]) {
      const Eigen::Vector3d p = ned.ToNed({c[0].get<double>(), c[1].get<double>(), home.altitude_m});
      centre += 0.25 * p.head<2>();
    }
    worst_m = std::max(worst_m, (centre - Eigen::Vector2d(-30.0 + i, 10.0)).norm());
  }
  EXPECT_LT(worst_m, 0.5) << "worst footprint centre error";
  std::printf("[ geotag ] 60 photos placed from EXIF/XMP, worst footprint centre error %.2f m\n", worst_m);

  // The world file's upper-left pixel against the flown area: the line runs north -30 .. 29 m at
  // east 10 m; at 30 m the footprint is 40 x 30 m, so the map's north-west corner lies near
  // (29 + 15, 10 - 20) m from home.
  std::istringstream pgw(Slurp(dir + "/map.pgw"));
  double a, d, b, e, lon, lat;
  pgw >> a >> d >> b >> e >> lon >> lat;
  const LocalNedFrame frame(home);
  const Eigen::Vector3d corner = frame.ToNed({lat, lon, home.altitude_m});
  EXPECT_NEAR(corner.x(), 29 + 15, 2.0);
  EXPECT_NEAR(corner.y(), 10 - 20, 2.0);
  EXPECT_GT(a, 0);
  EXPECT_LT(e, 0);
  if (!HasFailure()) std::filesystem::remove_all(dir);
}

TEST(UavStitch, RefusesAFolderWithoutCaptures) {
  const std::string dir = (std::filesystem::temp_directory_path() / "uav_test_stitch_empty").string();
  std::filesystem::create_directories(dir);
  const std::string command = std::string(UAV_STITCH_BIN) + " " + dir + " --out " + dir + "/map > " + dir + "/out.txt 2>&1";
  EXPECT_NE(std::system(command.c_str()), 0);
  EXPECT_NE(Slurp(dir + "/out.txt").find("session.json"), std::string::npos) << Slurp(dir + "/out.txt");
  EXPECT_FALSE(std::filesystem::exists(dir + "/map.tif"));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uav::runtime
