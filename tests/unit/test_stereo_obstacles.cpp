// Stereo obstacles (thesis 3.5) against the renderer's exact geometry: every obstacle the rig
// can see inside the working range is found, cylinders fit the true ones, featureless walls and
// open ground give none, and bad input is named.
#include <cmath>
#include <cstdio>
#include <string>
#include <tuple>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "unit/scene_test_util.hpp"
#include "uav/shared/frames.hpp"
#include "uav/vision/stereo_obstacles.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

StereoRig RigOf(const world::StereoSetup& s) { return {s.left.intrinsics, s.right.intrinsics, s.T_LR()}; }

Eigen::Isometry3d BodyPose(double n, double e, double d, double yaw_deg, double pitch_deg = 0.0, double roll_deg = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles a;
  a.psi = yaw_deg * M_PI / 180.0;
  a.theta = pitch_deg * M_PI / 180.0;
  a.phi = roll_deg * M_PI / 180.0;
  T.linear() = RotationNBFromEuler(a);
  T.translation() = Eigen::Vector3d(n, e, d);
  return T;
}

// The default detector on the pair `setup` renders of `scene` from the body pose T_NB.
StereoObstacles DetectFrom(const world::Scene& scene, const world::StereoSetup& setup, const Eigen::Isometry3d& T_NB) {
  const world::StereoRenderer renderer(scene, setup);
  const world::StereoFrame f = renderer.Render(T_NB, 1000000);
  const StereoRectifier rectifier(RigOf(setup));
  cv::Mat l, r;
  rectifier.Rectify(f.left.image, f.right.image, &l, &r);
  return StereoObstacleDetector(rectifier.geometry(), ObstacleParams()).Process(l, r, T_NB * setup.left.T_BC);
}

struct Seen {
  int pixels = 0;
  float nearest_m = 1e9f;
  int u_min = 1 << 30, u_max = -1, v_min = 1 << 30, v_max = -1;
};

// What the left camera sees of each object: pixel count, nearest depth, pixel extent.
std::map<int, Seen> SeenObjects(const world::Frame& left) {
  std::map<int, Seen> seen;
  for (int v = 0; v < left.object_id.rows; ++v)
    for (int u = 0; u < left.object_id.cols; ++u) {
      const int id = left.object_id.at<uint16_t>(v, u);
      if (id == world::kNoObject || id == world::kGroundId) continue;
      Seen& s = seen[id];
      ++s.pixels;
      s.nearest_m = std::min(s.nearest_m, left.depth.at<float>(v, u));
      s.u_min = std::min(s.u_min, u), s.u_max = std::max(s.u_max, u);
      s.v_min = std::min(s.v_min, v), s.v_max = std::max(s.v_max, v);
    }
  return seen;
}

struct ObstacleCase {
  std::string scene;
  double n, e, d, yaw_deg;
  int expect_at_least;  // obstacles inside the working range at this pose (a check on the case itself)
};
void PrintTo(const ObstacleCase& c, std::ostream* os) { *os << c.scene << " at " << c.n << "," << c.e << " yaw " << c.yaw_deg; }

class StereoObstacleAccuracy : public ::testing::TestWithParam<ObstacleCase> {};

TEST_P(StereoObstacleAccuracy, FindsEveryObstacleInRangeAndFitsItsCylinder) {
  const ObstacleCase& c = GetParam();
  const world::Scene& scene = test::CachedScene(c.scene);
  const world::StereoSetup& setup = *scene.stereo_camera();
  const world::StereoRenderer renderer(scene, setup);
  const Eigen::Isometry3d T_NB = BodyPose(c.n, c.e, c.d, c.yaw_deg);
  const world::StereoFrame f = renderer.Render(T_NB, 1000000);
  const StereoRectifier rectifier(RigOf(setup));
  cv::Mat l, r;
  rectifier.Rectify(f.left.image, f.right.image, &l, &r);
  const ObstacleParams params;
  const StereoObstacleDetector detector(rectifier.geometry(), params);
  const StereoObstacles found = detector.Process(l, r, T_NB * setup.left.T_BC);
  for (const ObstacleCylinder& o : found.obstacles)
    std::printf("[ found ] centre %.2f %.2f %.2f r %.2f top %.2f bottom %.2f range %.2f voxels %d\n", o.centre_W.x(),
                o.centre_W.y(), o.centre_W.z(), o.radius_m, o.top_m, o.bottom_m, o.range_m, o.voxels);

  const int blind = params.disparity.num_disparities * params.disparity.downscale;
  const int width = setup.left.intrinsics.width;
  int in_range = 0;
  for (const auto& [id, seen] : SeenObjects(f.left)) {
    const world::Obstacle* truth = nullptr;
    for (const world::Obstacle& o : scene.obstacles())
      if (o.id == id) truth = &o;
    if (truth == nullptr || truth->kind == "room") continue;
    // Inside the working range: nearer than the range gate, clear of the blind strip, and big
    // enough in the image to make a cluster of min_cluster_voxels.
    if (seen.nearest_m > 0.9 * found.gate_depth_m || seen.u_max < blind + 20 || seen.pixels < 1500) continue;
    ++in_range;
    const Eigen::Vector2d centre_true = truth->base_N.head<2>();
    const double radius_true = std::max(truth->radius, 0.5 * truth->size.head<2>().norm());
    const ObstacleCylinder* best = nullptr;
    for (const ObstacleCylinder& o : found.obstacles)
      if (best == nullptr || (o.centre_W.head<2>() - centre_true).norm() - o.radius_m <
                                 (best->centre_W.head<2>() - centre_true).norm() - best->radius_m)
        best = &o;
    ASSERT_NE(best, nullptr) << truth->kind << " " << id << " at " << seen.nearest_m << " m not found";
    const double centre_error = (best->centre_W.head<2>() - centre_true).norm();
    std::printf("[ truth ] %s %d nearest %.2f m, %d px: centre error %.3f m, radius %.3f (true %.3f)\n", truth->kind.c_str(),
                id, seen.nearest_m, seen.pixels, centre_error, best->radius_m, truth->radius);
    // Found: a cylinder centred on it, or one that contains it (two obstacles a metre apart in
    // depth at 7 m differ by under a pixel of disparity and may join into one cylinder).
    const bool centred = centre_error < radius_true + 0.3;
    const bool contained = centre_error + radius_true < best->radius_m + 0.3;
    EXPECT_TRUE(centred || contained) << truth->kind << " " << id << " at " << seen.nearest_m << " m: nearest cylinder "
                                      << centre_error << " m off, radius " << best->radius_m;
    // Round obstacles seen whole within 5 m: centre and radius within 10 cm (thesis: 10-20 cm).
    const bool round = truth->kind == "pole" || truth->kind == "pillar" || truth->kind == "person";
    const bool whole = seen.u_min > blind + 5 && seen.u_max < width - 5;  // its full width in view
    if (round && whole && seen.nearest_m < 5.0) {
      EXPECT_LT(centre_error, 0.10) << truth->kind << " " << id;
      EXPECT_NEAR(best->radius_m, truth->radius, 0.10) << truth->kind << " " << id;
    }
  }
  EXPECT_GE(in_range, c.expect_at_least);
}

INSTANTIATE_TEST_SUITE_P(Scenes, StereoObstacleAccuracy,
                         ::testing::Values(ObstacleCase{"forest", 2, 0, -1.5, 0, 2},
                                           ObstacleCase{"forest", 4, 1.5, -1.2, 0, 1},
                                           ObstacleCase{"forest", 3, -2.0, -1.2, 10, 1},
                                           ObstacleCase{"indoor_room", -1, -2, -1.5, 0, 1},
                                           ObstacleCase{"indoor_room", 0, 1.5, -1.0, 0, 1}),
                         [](const auto& info) { return "case" + std::to_string(info.index); });

// Nothing to see: a featureless wall (thesis 4.4, laser off) and open ground give no obstacle.
TEST(StereoObstacles, FeaturelessWallAndOpenGroundGiveNone) {
  struct View {
    std::string scene;
    Eigen::Isometry3d T_NB;
  };
  world::StereoSetup room = *test::CachedScene("indoor_room").stereo_camera();
  room.laser.enabled = false;
  for (const View& view : {View{"indoor_room", BodyPose(-2, 0, -1.5, 180)}, View{"indoor_room", BodyPose(2, 2, -1.5, 90)},
                           View{"survey_village", BodyPose(-60, -60, -1.5, 225)}}) {
    const world::Scene& scene = test::CachedScene(view.scene);
    const StereoObstacles found =
        DetectFrom(scene, view.scene == "indoor_room" ? room : *scene.stereo_camera(), view.T_NB);
    for (const ObstacleCylinder& o : found.obstacles)
      std::printf("[ found ] centre %.2f %.2f %.2f r %.2f top %.2f bottom %.2f range %.2f voxels %d\n", o.centre_W.x(),
                  o.centre_W.y(), o.centre_W.z(), o.radius_m, o.top_m, o.bottom_m, o.range_m, o.voxels);
    EXPECT_TRUE(found.obstacles.empty()) << view.scene << ": " << found.obstacles.size() << " obstacles, nearest at "
                                         << found.obstacles.front().range_m << " m";
  }
}

// A tree whose crown starts just above the camera is seen whole, trunk and crown in one cluster:
// the trunk must come out as a thin cylinder of its own (the map keeps thin cylinders and draws
// wide ones from their points, which would leave the trunk to be cleared by rays past it).
TEST(StereoObstacles, TreeSeenWholeGivesItsTrunkApartFromItsCrown) {
  const world::Scene& scene = test::CachedScene("forest");
  // The forest's tree at (12, -2): 9 m tall, crown radius 2.5 m (from 4 m up), trunk 0.15 m.
  const Eigen::Vector2d trunk_N(12, -2);
  for (const Eigen::Isometry3d& T_NB : {BodyPose(7.5, -2, -3.5, 0), BodyPose(7, -2, -4, 0), BodyPose(7.5, -1.2, -3.5, -8)}) {
    const StereoObstacles found = DetectFrom(scene, *scene.stereo_camera(), T_NB);
    const ObstacleCylinder* trunk = nullptr;
    const ObstacleCylinder* crown = nullptr;
    for (const ObstacleCylinder& o : found.obstacles) {
      std::printf("[ found ] centre %.2f %.2f %.2f r %.2f top %.2f bottom %.2f voxels %d\n", o.centre_W.x(), o.centre_W.y(),
                  o.centre_W.z(), o.radius_m, o.top_m, o.bottom_m, o.voxels);
      if ((o.centre_W.head<2>() - trunk_N).norm() > 2.5) continue;
      (o.radius_m < 0.8 ? trunk : crown) = &o;
    }
    ASSERT_NE(trunk, nullptr) << "no thin cylinder at the trunk";
    ASSERT_NE(crown, nullptr) << "no wide cylinder for the crown";
    EXPECT_LT((trunk->centre_W.head<2>() - trunk_N).norm(), 0.5);
    // The trunk reaches from under the crown down out of view; the crown stays above it.
    EXPECT_GT(trunk->bottom_m, -2.0);
    EXPECT_LE(crown->bottom_m, trunk->top_m + 0.3);
    EXPECT_GT(crown->radius_m, 1.0);
    EXPECT_TRUE(crown->on_trunk);
    EXPECT_FALSE(trunk->on_trunk);
  }
}

// Objects joined at range are not a crown. In dense benchmark fields two poles 2.4 m apart, or a
// thin pole with a tree behind it, came out as one cluster whose lower part is thin; its upper
// part, split off as a crown, was deeper than wide and was drawn in the map as a crown that wide,
// over free space and the goal (1/12 seeds 31 and 77 held short of it). Rendered from where those
// flights stood: every crown's disk, at its mid height, stays within 1 m of a true surface
// (before, seed 31's reached 1.3-1.5 m into free space; poles side by side, 0.85 m).
TEST(StereoObstacles, ObjectsJoinedAtRangeAreNotACrown) {
  struct View {
    int seed;
    double n, e, d, yaw_deg;
  };
  int crowns = 0;
  for (const View& v : {View{31, 54.61, 3.51, -2.68, -37}, View{31, 54.62, 3.57, -2.70, -36},
                        View{31, 54.72, 3.33, -2.62, -38}, View{77, 52.05, -5.19, -3.76, -8},
                        View{77, 51.75, -5.31, -3.78, -10}}) {
    // The benchmark's 1/12 field (uav-avoid-bench: 100 objects, 6 wires) with its level pair.
    const std::string json = R"({"name": "avoidance field", "seed": )" + std::to_string(v.seed) + R"(,
      "ground": {"layout": "uniform", "material": "grass"}, "objects": [],
      "generate": [{"type": "obstacle_field", "count": 100, "region_ne": [0, -10, 60, 10], "clear_radius_m": 3,
                    "keep_clear_ne": [60, 0], "wires": 6, "wire_height_m": [3, 8]}],
      "cameras": {"stereo": [{"name": "stereo", "rate_hz": 15, "baseline_m": 0.12}]}})";
    const world::Scene scene =
        world::Scene::Parse(json, std::string(UAV_RESOURCE_DIR) + "/scenes/avoidance_field.scene.json");
    const StereoObstacles found = DetectFrom(scene, *scene.stereo_camera(), BodyPose(v.n, v.e, v.d, v.yaw_deg));
    for (const ObstacleCylinder& o : found.obstacles) {
      if (!o.on_trunk) continue;
      ++crowns;
      double farthest = 0.0;  // from any true surface, over the crown's disk
      for (double dn = -o.radius_m; dn <= o.radius_m; dn += 0.1)
        for (double de = -o.radius_m; de <= o.radius_m; de += 0.1)
          if (std::hypot(dn, de) <= o.radius_m)
            farthest = std::max(farthest, scene.Clearance(o.centre_W + Eigen::Vector3d(dn, de, 0)));
      std::printf("[ seed %d ] crown r %.2f at (%.2f, %.2f), %.2f m from the nearest true surface at most\n", v.seed,
                  o.radius_m, o.centre_W.x(), o.centre_W.y(), farthest);
      EXPECT_LT(farthest, 1.0) << "seed " << v.seed << " from (" << v.n << ", " << v.e << "): a crown of radius "
                               << o.radius_m << " m reaching into free space";
    }
  }
  EXPECT_GT(crowns, 0) << "no crowns at all: the views no longer test the rule";
}

// A wide flat face is not a crown. A brick wall 8 m wide across the way, seen from 5-6 m as the
// vehicle banked 11-22 degrees into its turn round the wall's end: the image's tilted bottom
// edge cuts the wall's lower part away where it is near, so the wall's lowest band reads as a
// narrow trunk under a wide top. That top, fitted as a crown on a trunk (round: no deeper than
// wide), went into the map 1.2-2.9 m in radius, a patch 5 m across behind the wall
// (uav-avoid-bench --scene, the layout of tests/cli/uav_avoid_bench.sh; the poses are that
// flight's, truth). A crown's near cap stands off the line through it; a wall does not.
TEST(StereoObstacles, AWideWallIsNotACrown) {
  const world::Scene scene = world::Scene::Parse(R"({"name": "wall", "seed": 4,
      "sun": {"azimuth_deg": 200, "elevation_deg": 45, "ambient": 0.45}, "ground": {"layout": "uniform", "material": "grass"},
      "objects": [{"type": "box", "kind": "wall", "center_ned": [12, 0, -4], "size": [0.3, 8, 8], "material": "brick"}],
      "cameras": {"stereo": [{"name": "stereo", "rate_hz": 15, "baseline_m": 0.12}]}})",
                                                 std::string(UAV_RESOURCE_DIR) + "/scenes/wall.scene.json");
  struct View {
    double n, e, d, yaw_deg, pitch_deg, roll_deg;
  };
  int wide = 0;
  for (const View& v : {View{6.03, -0.11, -3.99, -11.4, 2.1, -11.4}, View{6.37, -0.16, -3.98, -18.1, 2.3, -17.5},
                        View{6.58, -0.27, -3.98, -23.3, 1.9, -20.3}, View{6.73, -0.32, -3.97, -27.3, 1.1, -21.4},
                        View{7.07, -0.49, -3.94, -37.1, -1.9, -20.3}}) {
    const StereoObstacles found =
        DetectFrom(scene, *scene.stereo_camera(), BodyPose(v.n, v.e, v.d, v.yaw_deg, v.pitch_deg, v.roll_deg));
    for (const ObstacleCylinder& o : found.obstacles) {
      if (o.radius_m <= 0.8) continue;
      ++wide;
      EXPECT_FALSE(o.on_trunk) << "from (" << v.n << ", " << v.e << ") yaw " << v.yaw_deg << " roll " << v.roll_deg
                               << ": a crown of radius " << o.radius_m << " m at (" << o.centre_W.x() << ", " << o.centre_W.y()
                               << "), " << -o.top_m << " to " << -o.bottom_m << " m up";
    }
  }
  EXPECT_GT(wide, 0) << "the wall was not seen: the views no longer test the rule";
}

TEST(StereoObstacles, RangeGateComesFromTheErrorModel) {
  const RectifiedGeometry g = RectifiedGeometry::OfRectifiedPair(640, 480, 500.0, 0.12);
  ObstacleParams p;
  p.max_depth_sigma_m = 0.2;
  p.sigma_d_px = 0.15;
  const StereoObstacleDetector detector(g, p);
  // Eq. 3.7 at half resolution: dZ = Z^2 dd / (f/2 B) = 0.2 m at Z = sqrt(0.2 * 250 * 0.12 / 0.15).
  EXPECT_NEAR(detector.GateDepth(), std::sqrt(0.2 * 250 * 0.12 / 0.15), 1e-9);
  EXPECT_NEAR(detector.error_model().DepthSigma(detector.GateDepth()), 0.2, 1e-9);
  // Eq. 3.4: lateral error p Z / f.
  EXPECT_NEAR(detector.error_model().LateralSigma(5.0), 0.5 * 5.0 / 250.0, 1e-12);
}

TEST(StereoObstacles, BadInputIsNamed) {
  const RectifiedGeometry g = RectifiedGeometry::OfRectifiedPair(320, 240, 300.0, 0.12);
  const StereoObstacleDetector detector(g, ObstacleParams());
  const cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(100));
  auto message = [&](const cv::Mat& l, const cv::Mat& r, const Eigen::Isometry3d& T) {
    try {
      detector.Process(l, r, T);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  const Eigen::Isometry3d level = StereoObstacleDetector::LevelCameraPose();
  EXPECT_NE(message(grey, cv::Mat(200, 320, CV_8UC1), level).find("200"), std::string::npos);
  EXPECT_NE(message(cv::Mat(), grey, level).find("0x0"), std::string::npos);
  EXPECT_NE(message(grey, cv::Mat(240, 320, CV_32F), level).find("8-bit"), std::string::npos);
  Eigen::Isometry3d nan_pose = level;
  nan_pose.translation().x() = NAN;
  EXPECT_NE(message(grey, grey, nan_pose).find("pose"), std::string::npos);
  EXPECT_THROW(RectifiedGeometry::OfRectifiedPair(320, 240, NAN, 0.12), std::invalid_argument);
  EXPECT_THROW(RectifiedGeometry::OfRectifiedPair(320, 240, 300, 0.0), std::invalid_argument);
  ObstacleParams bad;
  bad.disparity.num_disparities = 40;
  EXPECT_THROW(StereoObstacleDetector(g, bad), std::invalid_argument);
  bad = ObstacleParams();
  bad.max_depth_sigma_m = NAN;
  EXPECT_THROW(StereoObstacleDetector(g, bad), std::invalid_argument);
  // A blank pair is valid input with nothing in it.
  EXPECT_TRUE(detector.Process(grey, grey, level).obstacles.empty());
}

}  // namespace
}  // namespace uav::vision
