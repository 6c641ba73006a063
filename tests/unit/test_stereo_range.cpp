// Stereo forward clearance (thesis 3.2, 4.2) against the renderer's exact depth: the same corridor
// rule applied to the true 3-D points of every pixel, parameterised over scenes and poses.
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/stereo_range.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

world::Scene LoadScene(const std::string& name) {
  return world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/" + name + ".scene.json");
}

StereoRig RigOf(const world::StereoSetup& s) { return {s.left.intrinsics, s.right.intrinsics, s.T_LR()}; }

Eigen::Isometry3d BodyPose(double n, double e, double d, double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles a;
  a.psi = yaw;
  T.linear() = RotationNBFromEuler(a);
  T.translation() = Eigen::Vector3d(n, e, d);
  return T;
}

// Truth: the exact point of every pixel the matcher can see (right of the blind strip) in the
// left camera frame.
std::vector<Eigen::Vector3f> TruePoints(const world::Frame& left, const CameraIntrinsics& k, int blind_columns) {
  std::vector<Eigen::Vector3f> p;
  for (int v = 0; v < left.depth.rows; ++v)
    for (int u = blind_columns; u < left.depth.cols; ++u) {
      const float z = left.depth.at<float>(v, u);
      if (z <= 0) continue;
      const Eigen::Vector2d x = Unproject(k, Eigen::Vector2d(u, v));
      p.emplace_back(static_cast<float>(x.x() * z), static_cast<float>(x.y() * z), z);
    }
  return p;
}

struct RangeCase {
  std::string scene;
  double n, e, d, yaw_deg;
  double min_truth_m, max_truth_m;  // the pose was chosen to put an obstacle in this band
};
void PrintTo(const RangeCase& c, std::ostream* os) { *os << c.scene << " at " << c.n << "," << c.e; }

class StereoRangeAccuracy : public ::testing::TestWithParam<RangeCase> {};

TEST_P(StereoRangeAccuracy, NearestObstacleMatchesTruth) {
  const RangeCase& c = GetParam();
  const world::Scene scene = LoadScene(c.scene);
  ASSERT_TRUE(scene.stereo_camera());
  const world::StereoRenderer renderer(scene, *scene.stereo_camera());
  const world::StereoFrame f = renderer.Render(BodyPose(c.n, c.e, c.d, c.yaw_deg * M_PI / 180), 1000000);
  const StereoRangeParams params;
  const StereoRange range(RigOf(*scene.stereo_camera()), params);
  const StereoRangeResult measured = range.Process(f.left.image, f.right.image);
  const StereoRangeResult truth =
      StereoRange::RangeFromPoints(TruePoints(f.left, scene.stereo_camera()->left.intrinsics, range.BlindColumns()), params);
  ASSERT_TRUE(truth.obstacle);
  EXPECT_GT(truth.range_m, c.min_truth_m);
  EXPECT_LT(truth.range_m, c.max_truth_m);
  ASSERT_TRUE(measured.obstacle) << "valid fraction " << measured.valid_fraction;
  // Disparity error of ~0.25 px at half resolution: 3 % at these ranges, plus 5 cm.
  EXPECT_NEAR(measured.range_m, truth.range_m, 0.03 * truth.range_m + 0.05)
      << "truth " << truth.range_m << " m, valid fraction " << measured.valid_fraction;
  std::printf("[ stereo ] %s: truth %.3f m, measured %.3f m, valid %.2f\n", c.scene.c_str(), truth.range_m,
              measured.range_m, measured.valid_fraction);
}

INSTANTIATE_TEST_SUITE_P(Scenes, StereoRangeAccuracy,
                         ::testing::Values(RangeCase{"forest", 4, 3, -1.5, 0, 2, 6},         // pole ahead
                                           RangeCase{"forest", 6.5, 4, -0.8, 0, 2, 4},       // brick box
                                           RangeCase{"indoor_room", 0, -2, -1.5, 0, 1, 3},   // pillar
                                           RangeCase{"indoor_room", 0.5, 1.5, -0.8, 0, 1, 3}),  // box
                         [](const auto& info) { return "case" + std::to_string(info.index); });

// A featureless wall (thesis 4.4) gives the matcher nothing: it must report no obstacle rather
// than a range made from matched noise.
TEST(StereoRange, FeaturelessWallGivesNoFalseObstacle) {
  const world::Scene scene = LoadScene("indoor_room");
  world::StereoSetup setup = *scene.stereo_camera();
  setup.laser.enabled = false;
  const world::StereoRenderer renderer(scene, setup);
  const world::StereoFrame f = renderer.Render(BodyPose(-2, 0, -1.5, 0), 1000000);
  const StereoRange range(RigOf(setup), StereoRangeParams());
  const StereoRangeResult r = range.Process(f.left.image, f.right.image);
  EXPECT_FALSE(r.obstacle) << "range " << r.range_m << " m from " << r.corridor_points << " points";
  EXPECT_LT(r.valid_fraction, 0.1);
}

TEST(StereoRange, RejectsBadRigsParametersAndImages) {
  StereoRig rig;
  rig.T_LR.translation() = Eigen::Vector3d(0.12, 0, 0);
  StereoRangeParams p;
  EXPECT_NO_THROW(StereoRange(rig, p));
  StereoRig no_baseline = rig;
  no_baseline.T_LR.translation().setZero();
  EXPECT_THROW(StereoRange(no_baseline, p), std::invalid_argument);
  StereoRig nan_pose = rig;
  nan_pose.T_LR.translation().x() = NAN;
  EXPECT_THROW(StereoRange(nan_pose, p), std::invalid_argument);
  StereoRangeParams bad = p;
  bad.num_disparities = 40;
  EXPECT_THROW(StereoRange(rig, bad), std::invalid_argument);
  bad = p;
  bad.block_size = 4;
  EXPECT_THROW(StereoRange(rig, bad), std::invalid_argument);
  bad = p;
  bad.corridor_half_width_m = 0;
  EXPECT_THROW(StereoRange(rig, bad), std::invalid_argument);

  const StereoRange range(rig, p);
  const cv::Mat good(480, 640, CV_8UC3, cv::Scalar::all(100));
  EXPECT_NO_THROW(range.Process(good, good));
  EXPECT_THROW(range.Process(cv::Mat(), good), std::invalid_argument);
  EXPECT_THROW(range.Process(good, cv::Mat(240, 320, CV_8UC3)), std::invalid_argument);
  EXPECT_THROW(range.Process(good, cv::Mat(480, 640, CV_32F)), std::invalid_argument);
}

TEST(StereoRange, CorridorRuleTakesTheKthNearestPointInside) {
  StereoRangeParams p;
  p.min_points = 3;
  std::vector<Eigen::Vector3f> pts = {{0, 0, 5}, {0.5, 0.2, 4}, {0.9, -0.4, 6}, {1.5, 0, 1}, {0, 0.8, 1}, {0, 0, 30}};
  StereoRangeResult r = StereoRange::RangeFromPoints(pts, p);
  ASSERT_TRUE(r.obstacle);
  EXPECT_EQ(r.corridor_points, 3);  // (1.5, 0) is wide of it, (0, 0.8) above it, 30 m beyond range
  EXPECT_DOUBLE_EQ(r.range_m, 6.0);
  p.min_points = 4;
  EXPECT_FALSE(StereoRange::RangeFromPoints(pts, p).obstacle);
}

}  // namespace
}  // namespace uav::vision
