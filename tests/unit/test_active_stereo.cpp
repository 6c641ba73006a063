// Active stereo (thesis ch. 4) on rendered pairs of the downward rig with its laser grating over
// the featureless indoor scene, against the renderer's exact dots and the exact height: the flat
// floor at several heights and attitudes, a line across a table, a low wall and a window ledge,
// and the pairs it must refuse. Run with `ctest -R active_stereo`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/active_stereo.hpp"
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
  std::vector<std::array<double, 3>> trace;  // x, truth, estimate (0: none)
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
    trace.push_back({x, height, r.healthy ? r.height_m : 0.0});
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
    cv::line(img, at(trace[i - 1][0], trace[i - 1][1]), at(trace[i][0], trace[i][1]), cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    if (trace[i][2] > 0) cv::circle(img, at(trace[i][0], trace[i][2]), 2, cv::Scalar(40, 40, 220), cv::FILLED, cv::LINE_AA);
    else cv::drawMarker(img, at(trace[i][0], trace[i][1] + 0.1), cv::Scalar(0, 140, 255), cv::MARKER_TILTED_CROSS, 6);
  }
  cv::putText(img, "height over the floor: active stereo (red) vs exact (black); orange x: floor hidden, no height; grey: table, wall, ledge, table",
              cv::Point(10, 18), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  const std::string picture = ::testing::TempDir() + "active_stereo_height.png";
  cv::imwrite(picture, img);
  std::printf("picture: %s\n", picture.c_str());
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

}  // namespace
}  // namespace uav::vision
