// uav-stitch on a capture folder written by the onboard camera thread (CameraWorker): a 60 m
// line at 30 m over the village. Checks the outputs exist, the report (placements, alignment),
// that the world file puts the map where the vehicle flew, and a plain folder of photos.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/sim/sim_cameras.hpp"
#include "uav/world/scene.hpp"
#include "uav/app/camera_worker.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav::app {
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
  sim::SimCamera camera(scene, *scene.downward_camera(), [&] { return T_NB; });
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
  cv::imwrite(plain + "/IMG_000015b.jpg", cv::Mat(240, 320, CV_8UC3, cv::Scalar(90, 120, 60)));
  const std::string plain_command = std::string(UAV_STITCH_BIN) + " " + plain + " --out " + dir + "/pixels --report " +
                                    dir + "/plain.json > " + dir + "/plain.txt 2>&1";
  ASSERT_EQ(std::system(plain_command.c_str()), 0) << Slurp(dir + "/plain.txt");
  const nlohmann::json p = nlohmann::json::parse(Slurp(dir + "/plain.json"));
  EXPECT_EQ(p["placed"], 20);
  EXPECT_FALSE(p["georeferenced"].get<bool>());
  ASSERT_EQ(p["skipped"].size(), 2u) << p["skipped"];
  EXPECT_NE(p["skipped"][0].get<std::string>().find("IMG_000010b.jpg: missing or not an image"), std::string::npos);
  EXPECT_NE(p["skipped"][1].get<std::string>().find("320x240, the camera's is 640x480"), std::string::npos);
  const cv::Mat pixels = cv::imread(dir + "/pixels.png", cv::IMREAD_UNCHANGED);
  ASSERT_EQ(pixels.channels(), 4);
  // 20 frames 1 m apart, north up, at 30 m (the 640 px footprint is 40 m wide: 16 px per metre):
  // the strip is 19 m (304 px) longer than one frame. Chained by registration alone over roofs
  // and trees it comes out 889 x 711 px (measured): without poses the scale wanders.
  EXPECT_GT(pixels.rows, 480 + 200);
  EXPECT_LT(pixels.rows, 480 + 500);
  EXPECT_LT(pixels.cols, 800);
  EXPECT_FALSE(std::filesystem::exists(dir + "/pixels.tif"));

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
}  // namespace uav::app
