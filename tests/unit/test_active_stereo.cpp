// Active stereo (thesis ch. 4) on rendered pairs of the downward rig with its laser grating over
// the featureless indoor scene, against the renderer's exact dots and the exact height: the flat
// floor at several heights and attitudes, a line across a table, a low wall and a window ledge,
// and the pairs it must refuse. Run with `ctest -R active_stereo`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/active_stereo.hpp"
#include "uav/vision/stereo_calibration.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

world::Scene Indoor() {
  return world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/indoor_active.scene.json");
}
StereoRig RigOf(const world::StereoSetup& s) { return {s.left.intrinsics, s.right.intrinsics, s.T_LR()}; }

Eigen::Isometry3d Pose(double n, double e, double height, double yaw_deg = 0, double pitch_deg = 0, double roll_deg = 0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles a;
  a.psi = yaw_deg * M_PI / 180, a.theta = pitch_deg * M_PI / 180, a.phi = roll_deg * M_PI / 180;
  T.linear() = RotationNBFromEuler(a);
  T.translation() = Eigen::Vector3d(n, e, -height);
  return T;
}

class ActiveStereoTest : public ::testing::Test {
 protected:
  ActiveStereoTest()
      : scene_(Indoor()), setup_(*scene_.stereo_camera()), renderer_(scene_, setup_), stereo_(RigOf(setup_), ActiveStereoParams{}) {}
  ActiveStereoResult Run(const Eigen::Isometry3d& T_NB, world::StereoFrame* frame = nullptr, int64_t utime = 1'000'000) {
    world::StereoFrame f = renderer_.Render(T_NB, utime);
    ActiveStereoResult r = stereo_.Process(f.left.image, f.right.image, setup_.left.T_BC, T_NB.linear());
    if (frame) *frame = std::move(f);
    return r;
  }
  // The worst distance of a triangulated point from the exact spot of the beam seen at its pixel
  // (a wrong match lands centimetres to metres away).
  double WorstPointError(const ActiveStereoResult& r, const world::StereoFrame& f, const Eigen::Isometry3d& T_NB) {
    double worst = 0;
    const Eigen::Isometry3d T_NL = T_NB * setup_.left.T_BC;
    for (const LaserPoint& p : r.points) {
      double best_px = 1e9;
      Eigen::Vector3d exact = Eigen::Vector3d::Zero();
      for (const world::LaserDot& d : f.left.laser_dots) {
        if (!d.visible) continue;
        const double px = (d.pixel - Eigen::Vector2d(p.left_px.x, p.left_px.y)).norm();
        if (px < best_px) best_px = px, exact = d.p_N;
      }
      const double e = (T_NL * p.p_C - exact).norm();
      worst = std::max(worst, e);
      wrong_ += e > 0.10;
      matched_ += 1;
    }
    return worst;
  }
  int wrong_ = 0, matched_ = 0;  // matches more than 10 cm from their beam's spot, of all
  world::Scene scene_;
  world::StereoSetup setup_;
  world::StereoRenderer renderer_;
  ActiveStereo stereo_;
};

TEST(ActiveStereoMath, LinearTriangulationRecoversAKnownPoint) {
  Eigen::Matrix<double, 3, 4> P, Pp;
  P << 500, 0, 320, 0, 0, 500, 240, 0, 0, 0, 1, 0;
  Pp = P;
  Pp(0, 3) = -500 * 0.12;
  const Eigen::Vector3d X(0.3, -0.2, 1.7);
  auto project = [](const Eigen::Matrix<double, 3, 4>& M, const Eigen::Vector3d& p) {
    const Eigen::Vector3d h = M * p.homogeneous();
    return Eigen::Vector2d(h.x() / h.z(), h.y() / h.z());
  };
  EXPECT_LT((TriangulateLinear(P, Pp, project(P, X), project(Pp, X)) - X).norm(), 1e-9);
}

// Over open floor from 0.8 to 2.5 m, level and tilted by up to 8 degrees: the height within 3 cm
// (median; thesis: within 5 cm of a laser rangefinder), every point on its own beam's spot, and
// the thesis's 50 points per pair.
TEST_F(ActiveStereoTest, HeightOverFlatFloorAgainstTheExactHeight) {
  std::vector<double> errors;
  int fewest = 1 << 30;
  double worst_point = 0;
  const double heights[] = {0.8, 1.0, 1.3, 1.6, 2.0, 2.5};
  int k = 0;
  for (double h : heights)
    for (int attitude = 0; attitude < 3; ++attitude, ++k) {
      const Eigen::Isometry3d T_NB = Pose(0.5 + 0.1 * k, -1.5 + 0.05 * k, h, 37.0 * k, attitude == 1 ? 6 : -3, attitude == 2 ? 8 : 0);
      world::StereoFrame f;
      const ActiveStereoResult r = Run(T_NB, &f, 1'000'000 + k * 66'000);
      ASSERT_TRUE(r.healthy) << "at " << h << " m: " << r.reason;
      errors.push_back(std::abs(r.height_m - h));
      fewest = std::min(fewest, static_cast<int>(r.points.size()));
      worst_point = std::max(worst_point, WorstPointError(r, f, T_NB));
    }
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2];
  std::printf("flat floor 0.8-2.5 m, %zu pairs: height error median %.1f mm, worst %.1f mm; fewest points %d; %d wrong matches of %d (worst %.2f m off)\n",
              errors.size(), 1e3 * median, 1e3 * errors.back(), fewest, wrong_, matched_, worst_point);
  EXPECT_LT(median, 0.03);
  EXPECT_LT(errors.back(), 0.06);
  EXPECT_GE(fewest, 50);
  EXPECT_LT(wrong_, matched_ / 100 + 1);  // wrong matches under 1 %: the median shrugs them off
}

// Flying at 1.5 m across the room's table, low wall, window ledge and second table: the ground
// cluster keeps the height smooth (thesis Fig. 4.8) while the obstacles show as clusters above
// it. Draws the height against the truth.
TEST_F(ActiveStereoTest, NoSpikeCrossingTablesWallsAndALedge) {
  std::vector<double> errors;
  std::vector<std::array<double, 4>> trace;  // x, truth, estimate (0: none), laser rangefinder
  int with_obstacle_cluster = 0, fewest = 1 << 30, hidden = 0;
  const double height = 1.5;
  GroundTracker ground;
  for (int i = 0; i <= 220; ++i) {
    const double x = -0.5 + 0.05 * i;  // 0.05 m per pair: 0.75 m/s at 15 Hz
    const Eigen::Isometry3d T_NB = Pose(x, 0.0, height, 0, -4, 1);  // the nose down as it flies
    const int64_t utime = 1'000'000 + i * 66'667;
    ActiveStereoResult r = Run(T_NB, nullptr, utime);
    ASSERT_TRUE(r.healthy) << "at x " << x << ": " << r.reason;
    fewest = std::min(fewest, static_cast<int>(r.points.size()));
    for (const DotCluster& c : r.clusters) with_obstacle_cluster += !c.ground && c.points >= 5 && c.down_m < height - 0.3 ? 1 : 0;
    ground.Apply(&r, T_NB.translation().z(), utime);
    // A laser rangefinder along the body's down axis, as the thesis compares with (Fig. 4.8): it
    // reads whatever is below, so it drops by the height of each table, wall and ledge.
    const auto below = scene_.Intersect(T_NB.translation(), T_NB.linear().col(2), 1e-6, 10.0);
    const double rangefinder = below ? below->t * T_NB.linear()(2, 2) : 0.0;
    trace.push_back({x, height, r.healthy ? r.height_m : 0.0, rangefinder});
    if (!r.healthy) {
      // Only where a table hides the floor from every dot, and said so.
      EXPECT_NE(r.reason.find("the floor is hidden: the dots land 0.75 m above"), std::string::npos) << x << ": " << r.reason;
      EXPECT_TRUE(std::abs(x - 2.5) < 0.3 || std::abs(x - 10.0) < 0.4) << x;
      ++hidden;
      continue;
    }
    errors.push_back(std::abs(r.height_m - height));
  }
  const double worst = *std::max_element(errors.begin(), errors.end());
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  std::printf("crossing at 1.5 m, %zu pairs with a height, %d with the floor hidden: height error median %.1f mm, worst %.1f mm; fewest points %d; obstacle clusters in %d pairs\n",
              errors.size(), hidden, 1e3 * sorted[sorted.size() / 2], 1e3 * worst, fewest, with_obstacle_cluster);
  EXPECT_LT(hidden, 30);
  EXPECT_LT(sorted[sorted.size() / 2], 0.03);
  EXPECT_LT(worst, 0.10);
  EXPECT_GE(fewest, 50);
  EXPECT_GT(with_obstacle_cluster, 40);  // the table, wall, ledge and table seen under the vehicle

  // The picture: estimated (red) against exact (black) height along the line, with the
  // obstacles' tops below for reference.
  const int W = 900, H = 300;
  cv::Mat img(H, W, CV_8UC3, cv::Scalar(255, 255, 255));
  auto at = [&](double x, double z) { return cv::Point(40 + static_cast<int>((x + 0.5) / 11.5 * (W - 60)), H - 30 - static_cast<int>(z / 1.8 * (H - 60))); };
  for (const auto& o : {std::array<double, 3>{2.2, 2.8, 0.75}, {4.925, 5.075, 0.5}, {7.925, 8.075, 0.9}, {9.6, 10.4, 0.75}})
    cv::rectangle(img, at(o[0], 0), at(o[1], o[2]), cv::Scalar(200, 200, 200), cv::FILLED);
  for (std::size_t i = 1; i < trace.size(); ++i) {
    cv::line(img, at(trace[i - 1][0], trace[i - 1][3]), at(trace[i][0], trace[i][3]), cv::Scalar(220, 150, 60), 1, cv::LINE_AA);
    cv::line(img, at(trace[i - 1][0], trace[i - 1][1]), at(trace[i][0], trace[i][1]), cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    if (trace[i][2] > 0) cv::circle(img, at(trace[i][0], trace[i][2]), 2, cv::Scalar(40, 40, 220), cv::FILLED, cv::LINE_AA);
    else cv::drawMarker(img, at(trace[i][0], trace[i][1] + 0.1), cv::Scalar(0, 140, 255), cv::MARKER_TILTED_CROSS, 6);
  }
  cv::putText(img, "height over the floor: active stereo (red) vs exact (black); orange x: floor hidden, no height",
              cv::Point(10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  cv::putText(img, "blue: a laser rangefinder pointing down (thesis Fig. 4.8); grey: table, wall, ledge, table",
              cv::Point(10, 36), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const std::string picture = ::testing::TempDir() + "active_stereo_height.png";
  cv::imwrite(picture, img);
  std::printf("picture: %s\n", picture.c_str());
}

// Outdoors over the village (the thesis flew indoors; the rig is the same): the GPS-denied
// village's downward pair (0.3 m baseline, so the 20-150 px window spans 1.0-7.7 m) with its
// grating, over grass, fields and roads in daylight. From 1.5 to 3 m up: a height in every pair,
// the same 3 cm median. Higher, daylight drowns the farther, fainter dots: too few are seen or
// matched, and the pair says so rather than giving a height from too few.
TEST(ActiveStereoVillage, HeightOverTheGroundInDaylightAgainstTheExactHeight) {
  const world::Scene scene = world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/gps_denied_village.scene.json");
  const world::StereoSetup setup = *scene.stereo_camera();
  ASSERT_TRUE(setup.laser.enabled);
  const world::StereoRenderer renderer(scene, setup);
  const ActiveStereo stereo(RigOf(setup), ActiveStereoParams{});
  std::vector<double> errors, points;
  int k = 0;
  for (double h : {1.5, 2.0, 2.5, 3.0, 3.5, 4.5, 6.0}) {
    int refused = 0;
    std::string reason;
    for (const Eigen::Vector2d& at : {Eigen::Vector2d(-20, -10), Eigen::Vector2d(-35, 12), Eigen::Vector2d(5, 30)}) {
      const Eigen::Isometry3d T_NB = Pose(at.x(), at.y(), h, 50.0 * k, k % 2 ? 4 : -3, 2);
      const world::StereoFrame f = renderer.Render(T_NB, 1'000'000 + 100'000 * k++);
      const ActiveStereoResult r = stereo.Process(f.left.image, f.right.image, setup.left.T_BC, T_NB.linear());
      if (h <= 3.0) {
        ASSERT_TRUE(r.healthy) << h << " m at " << at.transpose() << ": " << r.reason;
      }
      if (!r.healthy) {
        ++refused, reason = r.reason;
        EXPECT_FALSE(r.reason.empty());
        continue;
      }
      EXPECT_LT(std::abs(r.height_m - h), 0.10) << h << " m at " << at.transpose();
      if (h <= 3.0) {
        errors.push_back(std::abs(r.height_m - h));
        points.push_back(static_cast<double>(r.points.size()));
      }
    }
    if (refused) std::printf("village at %.1f m: %d of 3 pairs without a height (%s)\n", h, refused, reason.c_str());
  }
  std::sort(errors.begin(), errors.end());
  std::sort(points.begin(), points.end());
  std::printf("village 1.5-3 m, %zu pairs: height error median %.1f mm, worst %.1f mm; points per pair %.0f to %.0f, median %.0f\n",
              errors.size(), 1e3 * errors[errors.size() / 2], 1e3 * errors.back(), points.front(), points.back(),
              points[points.size() / 2]);
  EXPECT_LT(errors[errors.size() / 2], 0.03);
  EXPECT_GE(points[points.size() / 2], 50.0);  // the thesis's 50 in most pairs, fewer where the dots grow faint
}

TEST_F(ActiveStereoTest, RefusesPairsWithoutUsableDotsNamingWhy) {
  world::StereoFrame f;
  const Eigen::Isometry3d T_NB = Pose(0.5, -1.5, 1.2);
  ASSERT_TRUE(Run(T_NB, &f).healthy);
  const Eigen::Matrix3d R = T_NB.linear();
  auto reason = [&](const cv::Mat& l, const cv::Mat& r, const Eigen::Matrix3d& att) {
    const ActiveStereoResult res = stereo_.Process(l, r, setup_.left.T_BC, att);
    EXPECT_FALSE(res.healthy);
    EXPECT_EQ(res.height_m, 0.0);
    return res.reason;
  };
  const cv::Mat blank(f.right.image.size(), f.right.image.type(), cv::Scalar(0, 0, 0));
  EXPECT_NE(reason(f.left.image, blank, R).find("right image: no laser dots seen"), std::string::npos);
  const cv::Mat glare(f.left.image.size(), f.left.image.type(), cv::Scalar(230, 230, 230));
  EXPECT_NE(reason(glare, f.right.image, R).find("left image: too bright"), std::string::npos);
  cv::Mat half;
  cv::resize(f.right.image, half, cv::Size(), 0.5, 0.5);
  EXPECT_NE(reason(f.left.image, half, R).find("image is 320x240"), std::string::npos);
  EXPECT_NE(reason(f.left.image, cv::Mat(), R).find("empty image"), std::string::npos);
  Eigen::Matrix3d nan_att = R;
  nan_att(0, 0) = NAN;
  EXPECT_NE(reason(f.left.image, f.right.image, nan_att).find("attitude is not finite"), std::string::npos);
  // Far beyond the working range (disparity under 20 px): dots seen, none matched.
  const ActiveStereoResult far = Run(Pose(0.5, -1.5, 2.9));
  std::printf("at 2.9 m: %s\n", far.healthy ? "healthy" : far.reason.c_str());
  ActiveStereoParams bad;
  bad.max_disparity_px = 10;
  EXPECT_THROW(ActiveStereo(RigOf(setup_), bad), std::invalid_argument);
}

// The command line on recorded pairs: rendered pairs over the low wall written as two folders
// with the rig's calibration file; every height from uav-active-stereo within 1 cm of the left
// camera's exact height over the floor, the overlays written, and bad input named: folders that
// do not pair up, a missing calibration, an unreadable image (that pair only).
TEST_F(ActiveStereoTest, CommandLineOnRecordedPairsAgainstTheExactHeight) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(::testing::TempDir()) / "uav_active_stereo_cli";
  fs::remove_all(dir);
  fs::create_directories(dir / "left");
  fs::create_directories(dir / "right");
  std::vector<double> exact;
  const int pairs = 12;
  for (int i = 0; i < pairs; ++i) {
    const Eigen::Isometry3d T_NB = Pose(4.2 + 0.15 * i, 0.3, 1.4);  // level, over the floor and the 0.5 m wall
    world::StereoFrame f;
    Run(T_NB, &f, 1'000'000 + i * 66'667);
    char name[32];
    std::snprintf(name, sizeof name, "%03d.png", i);
    cv::imwrite((dir / "left" / name).string(), f.left.image);
    cv::imwrite((dir / "right" / name).string(), f.right.image);
    exact.push_back(-(T_NB * setup_.left.T_BC).translation().z());  // the left camera over the floor
  }
  StereoCalibration calibration;
  calibration.rig = RigOf(setup_);
  WriteStereoCalibration((dir / "rig.yml").string(), calibration);
  const std::string tool = UAV_ACTIVE_STEREO_BIN;
  const std::string run = tool + " " + (dir / "left").string() + " " + (dir / "right").string() + " --calib " +
                          (dir / "rig.yml").string() + " --csv " + (dir / "heights.csv").string() + " --overlay " +
                          (dir / "overlay").string() + " > " + (dir / "report.json").string() + " 2> /dev/null";
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  std::ifstream csv(dir / "heights.csv");
  std::string line;
  std::getline(csv, line);
  ASSERT_EQ(line.rfind("left,right,healthy,height_m", 0), 0u) << line;
  int rows = 0;
  double worst = 0;
  while (std::getline(csv, line)) {
    std::vector<std::string> field;
    std::stringstream ss(line);
    for (std::string x; std::getline(ss, x, ',');) field.push_back(x);
    ASSERT_GE(field.size(), 10u) << line;
    ASSERT_EQ(field[2], "1") << line;
    worst = std::max(worst, std::abs(std::stod(field[3]) - exact[rows]));
    ++rows;
  }
  EXPECT_EQ(rows, pairs);
  EXPECT_LT(worst, 0.01);
  EXPECT_EQ(cv::imread((dir / "overlay" / "000.png").string()).size(), cv::Size(640, 480));
  std::printf("uav-active-stereo on %d recorded pairs: worst height error %.1f mm\n", rows, 1e3 * worst);

  auto fails = [&](const std::string& args, int code, const std::string& names) {
    const std::string cmd = tool + " " + args + " --csv " + (dir / "none.csv").string() + " > /dev/null 2> " + (dir / "err.txt").string();
    EXPECT_EQ(WEXITSTATUS(std::system(cmd.c_str())), code) << cmd;
    std::ifstream err(dir / "err.txt");
    const std::string message((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
    EXPECT_NE(message.find(names), std::string::npos) << message;
    EXPECT_FALSE(fs::exists(dir / "none.csv"));
  };
  fails((dir / "left").string() + " " + (dir / "right").string(), 2, "--calib");
  fails((dir / "left").string() + " " + (dir / "right").string() + " --calib " + (dir / "missing.yml").string(), 1, "missing.yml");
  fs::remove(dir / "right" / "011.png");
  fails((dir / "left").string() + " " + (dir / "right").string() + " --calib " + (dir / "rig.yml").string(), 1,
        "12 images and the right 11");
  // An unreadable image spoils its own pair only.
  std::ofstream(dir / "right" / "011.png") << "not an image";
  const std::string partial = tool + " " + (dir / "left").string() + " " + (dir / "right").string() + " --calib " +
                              (dir / "rig.yml").string() + " --csv " + (dir / "partial.csv").string() + " > /dev/null 2>&1";
  ASSERT_EQ(std::system(partial.c_str()), 0);
  std::ifstream partial_csv(dir / "partial.csv");
  std::string all((std::istreambuf_iterator<char>(partial_csv)), std::istreambuf_iterator<char>());
  EXPECT_NE(all.find("011.png,0,,"), std::string::npos) << all;
  EXPECT_NE(all.find("cannot read it as an image"), std::string::npos) << all;
  if (!HasFailure()) fs::remove_all(dir);
}

}  // namespace
}  // namespace uav::vision
