// Simulated world and cameras (issue 4): rendered truth against analytic geometry, reprojection,
// chessboard detection and stereo calibration, laser dots, determinism, scene files.
#include <cmath>
#include <filesystem>
#include <map>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/world/renderer.hpp"

namespace uav::world {
namespace {

std::string ScenePath(const std::string& name) {
  return std::string(UAV_RESOURCE_DIR) + "/scenes/" + name + ".scene.json";
}

CameraSetup IdealCamera(const std::string& name = "test") {
  CameraSetup c;
  c.name = name;
  c.intrinsics.width = 640;
  c.intrinsics.height = 480;
  c.intrinsics.fx = c.intrinsics.fy = 500.0;
  c.intrinsics.cx = 319.5;
  c.intrinsics.cy = 239.5;
  c.noise_sigma = 0.0;
  return c;
}

// Camera at p_N looking along the body x axis of yaw/pitch (forward camera, Eq. 5.48).
Eigen::Isometry3d ForwardCameraPose(const Eigen::Vector3d& p_N, double yaw, double pitch = 0.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles e;
  e.psi = yaw;
  e.theta = pitch;
  T.linear() = RotationNBFromEuler(e) * RotationBCForward();
  T.translation() = p_N;
  return T;
}

// What Scene::Parse says about a scene text: its error, or "accepted".
std::string ParseError(const std::string& text) {
  try {
    Scene::Parse(text, "bad.scene.json");
  } catch (const std::exception& e) {
    return std::string(e.what());
  }
  return std::string("accepted");
}

Eigen::Vector3d PixelRay(const CameraIntrinsics& k, int u, int v) {
  return Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
}

// ---- Depth against analytic geometry ---------------------------------------------------------

TEST(WorldDepth, TiltedGroundPlaneMatchesAnalyticDepth) {
  Scene scene(1);
  GroundSpec g;
  g.material = "gravel";
  scene.SetGround(g);
  const CameraSetup cam = IdealCamera();
  const Renderer r(scene, cam);
  // 5 m above the ground, pitched 35 deg down, looking north-east.
  const Eigen::Isometry3d T_NC = ForwardCameraPose(Eigen::Vector3d(3, -2, -5), 0.7, -35 * M_PI / 180);
  const Frame f = r.Render(T_NC, 0);
  const Eigen::Vector3d n_C = T_NC.linear().transpose() * Eigen::Vector3d(0, 0, -1);  // ground normal (up) in C
  const double height = 5.0;
  int checked = 0;
  double worst = 0;
  for (int v = 0; v < 480; v += 7)
    for (int u = 0; u < 640; u += 7) {
      const Eigen::Vector3d ray = PixelRay(cam.intrinsics, u, v);
      const double denom = -n_C.dot(ray);  // how fast the ray descends per unit of depth
      if (denom <= 1e-6) {
        EXPECT_EQ(f.depth.at<float>(v, u), 0.0f) << "sky at " << u << "," << v;
        continue;
      }
      const double expected = height / denom;
      worst = std::max(worst, std::abs(f.depth.at<float>(v, u) - expected) / expected);
      EXPECT_EQ(f.object_id.at<uint16_t>(v, u), kGroundId);
      ++checked;
    }
  EXPECT_GT(checked, 3000);
  EXPECT_LT(worst, 2e-6);  // float storage
}

TEST(WorldDepth, BoxFaceAndCylinderMatchAnalyticDepth) {
  Scene scene(2);
  const double D = 6.0, r = 0.5;
  const int box = scene.AddBox("box", Eigen::Vector3d(D + 1.0, -3.0, -1.0), Eigen::Vector3d(2, 2, 2), 0.0, "brick");
  const int cyl = scene.AddCylinder("pole", Eigen::Vector3d(D, 1.5, 0), r, 3.0, "concrete");
  const CameraSetup cam = IdealCamera();
  const Renderer renderer(scene, cam);
  const Eigen::Isometry3d T_NC = ForwardCameraPose(Eigen::Vector3d(0, 0, -1), 0.0);
  const Frame f = renderer.Render(T_NC, 0);
  int box_pixels = 0, cyl_pixels = 0;
  double worst_box = 0, worst_cyl = 0;
  for (int v = 0; v < 480; ++v)
    for (int u = 0; u < 640; ++u) {
      const Eigen::Vector3d ray = PixelRay(cam.intrinsics, u, v);  // C: x east, y down, z north
      const int id = f.object_id.at<uint16_t>(v, u);
      const double z = f.depth.at<float>(v, u);
      // Box front face at north = D; it spans east -4..-2, height 0..2 (camera at 1 m).
      const double east = ray.x() * D, up = 1.0 - ray.y() * D;
      const bool on_face = east > -4 + 1e-6 && east < -2 - 1e-6 && up > 1e-6 && up < 2 - 1e-6;
      if (on_face) {
        EXPECT_EQ(id, box);
        worst_box = std::max(worst_box, std::abs(z - D));
        ++box_pixels;
      }
      // Cylinder axis at north D, east 1.5: (t x - 1.5)^2 + (t - D)^2 = r^2, lowest t.
      const double a = 1 + ray.x() * ray.x(), b = -2 * (1.5 * ray.x() + D), c = 1.5 * 1.5 + D * D - r * r;
      const double disc = b * b - 4 * a * c;
      if (disc > 1e-6) {
        const double t = (-b - std::sqrt(disc)) / (2 * a);
        const double height = 1.0 - ray.y() * t;
        if (height > 0.01 && height < 2.99) {
          EXPECT_EQ(id, cyl) << u << "," << v;
          worst_cyl = std::max(worst_cyl, std::abs(z - t));
          ++cyl_pixels;
        }
      }
    }
  EXPECT_GT(box_pixels, 10000);
  EXPECT_GT(cyl_pixels, 5000);
  EXPECT_LT(worst_box, 1e-5);
  EXPECT_LT(worst_cyl, 1e-5);
}

// ---- Moving objects (tracking targets) -------------------------------------------------------

// A red ball rolls along a path: it is rendered, and its ground-truth box found, where the path
// puts it at each time; a looping path comes back round, a back-and-forth one reverses; a car
// turns to face its leg.
TEST(WorldMovingObjects, ObjectsAreRenderedWhereTheirPathPutsThem) {
  Scene scene(3);
  scene.SetGround(GroundSpec{});
  const int ball = scene.AddSphere("ball", Eigen::Vector3d(8, -2, -0.3), 0.3, "red");
  ObjectPath path;
  path.waypoints_NE = {{8, -2}, {8, 2}, {10, 2}};
  path.speed_mps = 2.0;
  path.start_s = 1.0;
  path.loop = false;
  scene.SetPath(ball, path);
  EXPECT_EQ(scene.MovingObjects(), std::vector<int>{ball});
  // Footprint centres: before the start, where declared; 1 s in, 2 m along the first leg; 2.5 s
  // in, 1 m along the second; after the end (6 m) it comes back, heading south.
  EXPECT_LT((scene.PlacementAt(ball, 0.5).base_N - Eigen::Vector3d(8, -2, 0)).norm(), 1e-12);
  EXPECT_LT((scene.PlacementAt(ball, 2.0).base_N - Eigen::Vector3d(8, 0, 0)).norm(), 1e-12);
  EXPECT_LT((scene.PlacementAt(ball, 3.5).base_N - Eigen::Vector3d(9, 2, 0)).norm(), 1e-12);
  EXPECT_LT((scene.PlacementAt(ball, 4.5).base_N - Eigen::Vector3d(9, 2, 0)).norm(), 1e-12);
  EXPECT_NEAR(std::cos(scene.PlacementAt(ball, 4.5).heading_rad), -1.0, 1e-12);
  EXPECT_LT((scene.PlacementAt(ball, 2.0).velocity_NE - Eigen::Vector2d(0, 2)).norm(), 1e-12);

  const CameraSetup cam = IdealCamera();
  const Renderer renderer(scene, cam);
  const Eigen::Isometry3d T_NC = ForwardCameraPose(Eigen::Vector3d(0, 0, -0.3), 0.0);
  for (const double t_s : {0.0, 2.0, 3.5}) {
    const Frame f = renderer.Render(T_NC, static_cast<int64_t>(t_s * 1e6));
    const Eigen::Vector3d centre_N = scene.PlacementAt(ball, t_s).base_N - Eigen::Vector3d(0, 0, 0.3);
    const Eigen::Vector2d px = Project(cam.intrinsics, T_NC.inverse() * centre_N);
    const cv::Rect box = ObjectBox(f, ball);
    ASSERT_FALSE(box.empty()) << t_s;
    EXPECT_NEAR(box.x + 0.5 * (box.width - 1), px.x(), 0.6) << t_s;
    EXPECT_NEAR(box.y + 0.5 * (box.height - 1), px.y(), 0.6) << t_s;
    // Red: R well above G and B at the box centre.
    const cv::Vec3b c = f.image.at<cv::Vec3b>(static_cast<int>(px.y()), static_cast<int>(px.x()));
    EXPECT_GT(c[2], 2 * c[1]) << t_s;
    // The ray through the centre hits it at that time, not where it was declared.
    const auto hit = scene.Intersect(T_NC.translation(), centre_N - T_NC.translation(), 1e-6, 1e9, t_s);
    ASSERT_TRUE(hit);
    EXPECT_EQ(hit->object_id, ball);
  }

  // A 4 x 2 m car driving east turns to face north on its second leg: seen from above, its long
  // side lies along north.
  Scene town(4);
  const int car = town.AddBox("car", Eigen::Vector3d(0, 0, -0.75), Eigen::Vector3d(2, 4, 1.5), 0.0, "blue");
  ObjectPath drive;
  drive.waypoints_NE = {{0, 0}, {0, 10}, {10, 10}};
  drive.speed_mps = 5.0;
  town.SetPath(car, drive);
  EXPECT_NEAR(town.PlacementAt(car, 3.0).heading_rad, 0.0, 1e-12);  // 15 m along: on the north leg
  Eigen::Isometry3d T_down = Eigen::Isometry3d::Identity();
  T_down.linear() = RotationBCDownward();
  T_down.translation() = Eigen::Vector3d(5, 10, -40);
  const Frame above = Renderer(town, IdealCamera()).Render(T_down, 3'000'000);
  const cv::Rect seen = ObjectBox(above, car);
  ASSERT_FALSE(seen.empty());
  EXPECT_GT(seen.height, 1.6 * seen.width);  // image up is north: long along the image's y
}

TEST(WorldMovingObjects, BadPathsAreRejected) {
  Scene scene(1);
  const int pole = scene.AddCylinder("pole", Eigen::Vector3d(0, 0, 0), 0.1, 2, "concrete");
  ObjectPath one;
  one.waypoints_NE = {{0, 0}};
  EXPECT_THROW(scene.SetPath(pole, one), std::invalid_argument);
  ObjectPath same;
  same.waypoints_NE = {{0, 0}, {0, 0}};
  EXPECT_THROW(scene.SetPath(pole, same), std::invalid_argument);
  ObjectPath nan_speed;
  nan_speed.waypoints_NE = {{0, 0}, {1, 0}};
  nan_speed.speed_mps = std::nan("");
  EXPECT_THROW(scene.SetPath(pole, nan_speed), std::invalid_argument);
  EXPECT_THROW(scene.SetPath(999, nan_speed), std::invalid_argument);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "person", "at_ne": [0, 0], "path": {"waypoints_ne": [[0, 0]], "speed_mps": 1}}]})")
                .find("$.objects[0].path.waypoints_ne"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "tree", "at_ne": [0, 0], "height_m": 5, "crown_radius_m": 1,
      "path": {"waypoints_ne": [[0, 0], [1, 1]], "speed_mps": 1}}]})").find("$.objects[0].path: only"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "person", "at_ne": [0, 0], "path": {"waypoints_ne": [[0, 0], [1, 1]], "speed_mps": 0}}]})")
                .find("$.objects[0].path.speed_mps"), std::string::npos);
  EXPECT_EQ(ParseError(R"({"objects": [{"type": "person", "at_ne": [0, 0], "clothing": "red",
      "path": {"waypoints_ne": [[0, 0], [1, 1]], "speed_mps": 1.2}}]})"), "accepted");
}

// ---- Reprojection ----------------------------------------------------------------------------

TEST(WorldProjection, KnownPointsReprojectWithinHalfAPixel) {
  Scene scene(3);
  scene.SetSky(false);
  CameraSetup cam = IdealCamera();
  cam.intrinsics.distortion = {-0.12, 0.03, 0.001, -0.0005, 0.0};  // a real lens: barrel + tangential
  cam.supersample = 4;
  cam.auto_exposure = false;
  const Eigen::Isometry3d T_NC = ForwardCameraPose(Eigen::Vector3d(0, 0, -2), 0.3, 0.1);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 4; ++j) {
      const Eigen::Vector3d p_C((i - 2) * 0.55, (j - 1.5) * 0.5, 3.0 + 0.2 * i);
      points.push_back(T_NC * p_C);
      scene.AddSphere("marker", points.back(), 0.03, "plain");
    }
  SunLight sun;
  sun.ambient = 1.0;
  scene.SetSun(sun);
  const Renderer r(scene, cam);
  const Frame f = r.Render(T_NC, 0);
  cv::Mat grey, mask, labels, stats, centroids;
  cv::cvtColor(f.image, grey, cv::COLOR_BGR2GRAY);
  mask = grey > 20;
  const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids);
  ASSERT_EQ(n - 1, static_cast<int>(points.size()));
  double worst = 0;
  for (const auto& p_N : points) {
    const Eigen::Vector2d expected = Project(cam.intrinsics, T_NC.inverse() * p_N);
    // Intensity-weighted centroid of the blob under the expected pixel.
    const int label = labels.at<int>(static_cast<int>(std::lround(expected.y())), static_cast<int>(std::lround(expected.x())));
    ASSERT_GT(label, 0);
    double sw = 0, su = 0, sv = 0;
    for (int v = 0; v < grey.rows; ++v)
      for (int u = 0; u < grey.cols; ++u)
        if (labels.at<int>(v, u) == label) {
          sw += grey.at<uint8_t>(v, u);
          su += u * grey.at<uint8_t>(v, u);
          sv += v * grey.at<uint8_t>(v, u);
        }
    worst = std::max(worst, (Eigen::Vector2d(su / sw, sv / sw) - expected).norm());
  }
  EXPECT_LT(worst, 0.5);
  RecordProperty("worst_reprojection_px", std::to_string(worst));
  std::printf("worst reprojection error %.3f px\n", worst);
}

TEST(WorldProjection, UnprojectInvertsProject) {
  CameraIntrinsics k = IdealCamera().intrinsics;
  k.distortion = {-0.2, 0.05, 0.002, -0.001, 0.01};
  for (int v = 0; v < 480; v += 40)
    for (int u = 0; u < 640; u += 40) {
      const Eigen::Vector2d x = Unproject(k, Eigen::Vector2d(u, v));
      const Eigen::Vector2d back = Project(k, Eigen::Vector3d(x.x(), x.y(), 1.0));
      EXPECT_LT((back - Eigen::Vector2d(u, v)).norm(), 1e-8);
    }
}

// ---- Chessboard and stereo calibration -------------------------------------------------------

// Stereo calibration from rendered boards: test_stereo_calibration.cpp.

// ---- Laser dots --------------------------------------------------------------------------------

TEST(WorldLaser, DotsLandOnTheWallWhereTheGeometrySaysAndAppearWhereProjected) {
  Scene scene(5);
  scene.SetSky(false);
  scene.AddRoom(Eigen::Vector3d(0, 0, -1.5), Eigen::Vector3d(10, 8, 3), "plain");
  CameraSetup cam = IdealCamera("stereo");
  cam.noise_sigma = 1.5;
  LaserEmitter laser;
  laser.enabled = true;
  laser.rows = laser.cols = 15;
  laser.pitch_rad = 1.5 * M_PI / 180;
  Eigen::Isometry3d T_B_rig = Eigen::Isometry3d::Identity();
  T_B_rig.linear() = RotationBCForward();
  T_B_rig.translation() = Eigen::Vector3d(0.15, 0, 0);
  const StereoSetup setup = MakeStereoSetup(cam, T_B_rig, 0.12, laser);
  const StereoRenderer renderer(scene, setup);
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(-1, 0.3, -1.5);
  const StereoFrame f = renderer.Render(T_NB, 0);
  ASSERT_EQ(f.left.laser_dots.size(), 225u);
  // Every beam hits the far wall (north = 5): p = o + t d with t = (5 - o_n) / d_n.
  const Eigen::Isometry3d T_NE = T_NB * setup.T_BE;
  for (const LaserDot& dot : f.left.laser_dots) {
    ASSERT_TRUE(dot.hit);
    const Eigen::Vector3d d = T_NE.linear() * laser.BeamDirection(dot.beam);
    const Eigen::Vector3d expected = T_NE.translation() + (5.0 - T_NE.translation().x()) / d.x() * d;
    EXPECT_LT((dot.p_N - expected).norm(), 1e-9);
    EXPECT_TRUE(dot.visible);
  }
  // Detected spots (green excess) match the projected dots in both images.
  for (const Frame* frame : {&f.left, &f.right}) {
    std::vector<cv::Mat> ch;
    cv::split(frame->image, ch);
    cv::Mat excess;
    cv::Mat br;
    cv::addWeighted(ch[0], 0.5, ch[2], 0.5, 0, br);
    cv::subtract(ch[1], br, excess);
    cv::Mat mask = excess > 30, labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(mask, labels, stats, centroids);
    EXPECT_EQ(n - 1, 225);
    double worst = 0;
    for (const LaserDot& dot : frame->laser_dots) {
      double sw = 0, su = 0, sv = 0;
      const int cu = static_cast<int>(std::lround(dot.pixel.x())), cv_ = static_cast<int>(std::lround(dot.pixel.y()));
      for (int v = cv_ - 3; v <= cv_ + 3; ++v)
        for (int u = cu - 3; u <= cu + 3; ++u) {
          const double w = std::max(0, excess.at<uint8_t>(v, u) - 10);
          sw += w;
          su += u * w;
          sv += v * w;
        }
      ASSERT_GT(sw, 0);
      worst = std::max(worst, (Eigen::Vector2d(su / sw, sv / sw) - dot.pixel).norm());
    }
    EXPECT_LT(worst, 0.5);
    std::printf("%s: %d spots, worst centroid error %.3f px\n", frame->camera.c_str(), n - 1, worst);
  }
}

TEST(WorldLaser, AnOccludedDotIsNotVisible) {
  Scene scene(6);
  scene.SetSky(false);
  scene.AddRoom(Eigen::Vector3d(0, 0, -1.5), Eigen::Vector3d(10, 8, 3), "plain");
  // A pillar between the right camera and the wall; beams pass beside it.
  const CameraSetup cam = IdealCamera("stereo");
  LaserEmitter laser;
  laser.enabled = true;
  Eigen::Isometry3d T_B_rig = Eigen::Isometry3d::Identity();
  T_B_rig.linear() = RotationBCForward();
  const StereoSetup setup = MakeStereoSetup(cam, T_B_rig, 0.12, laser);
  scene.AddCylinder("pillar", Eigen::Vector3d(0.6, 0.2, 0), 0.05, 3.0, "plain");
  const StereoRenderer renderer(scene, setup);
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(0, 0, -1.5);
  const StereoFrame f = renderer.Render(T_NB, 0);
  int hidden_left = 0, hidden_right = 0;
  for (size_t i = 0; i < f.left.laser_dots.size(); ++i) {
    hidden_left += !f.left.laser_dots[i].visible;
    hidden_right += !f.right.laser_dots[i].visible;
  }
  EXPECT_GT(hidden_right, 0);      // the right camera sees the pillar in front of some spots
  EXPECT_NE(hidden_left, hidden_right);
}

// ---- Power lines -------------------------------------------------------------------------------

TEST(WorldPowerLine, CatenaryHangsItsSagAndIsWhereTheRayHitsIt) {
  Scene scene(7);
  const Eigen::Vector3d a(0, 0, -10), b(50, 0, -10);
  scene.AddCable(a, b, 1.5, 0.01);
  const Cable& c = scene.cables()[0];
  EXPECT_LT((c.PointAt(0) - a).norm(), 1e-9);
  EXPECT_LT((c.PointAt(1) - b).norm(), 1e-9);
  EXPECT_NEAR(c.PointAt(0.5).z() - a.z(), 1.5, 1e-9);  // NED: sag is down
  // Catenary, not parabola: z(s) - z_chord = a (cosh(L/2a) - cosh((x - L/2)/a)).
  const double x = 0.25 * 50 - 25;
  EXPECT_NEAR(c.PointAt(0.25).z() - a.z(),
              c.catenary_a * (std::cosh(25 / c.catenary_a) - std::cosh(x / c.catenary_a)), 1e-9);
  // A ray straight up from the ground at s = 0.3 hits the bottom of the cable.
  const Eigen::Vector3d under = c.PointAt(0.3);
  const auto hit = scene.Intersect(Eigen::Vector3d(under.x(), under.y(), 0), Eigen::Vector3d(0, 0, -1));
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->p_N.z(), under.z() + 0.01, 2e-3);  // 64 straight pieces: chord error < 2 mm
  // The clearance to it: 2 m below mid-span is 2 m less the radius; beside it, to the side.
  const Eigen::Vector3d mid = c.PointAt(0.5);
  EXPECT_NEAR(c.Distance(mid + Eigen::Vector3d(0, 0, 2)), 2 - 0.01, 2e-3);
  EXPECT_NEAR(scene.Clearance(mid + Eigen::Vector3d(0, 3, 0)), 3 - 0.01, 2e-3);
  EXPECT_EQ(c.Distance(mid), 0.0);
}

// ---- Determinism, clouds, scene files -----------------------------------------------------------

TEST(WorldDeterminism, SameSceneAndSeedGiveBitIdenticalImagesOnAnyThreadCount) {
  const Scene a = Scene::LoadFile(ScenePath("survey_village"));
  const Scene b = Scene::LoadFile(ScenePath("survey_village"));
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(20, 35, -30);
  const Frame fa = Renderer(a, *a.downward_camera()).Render(T_NB * a.downward_camera()->T_BC, 1234567);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const Frame fb = Renderer(b, *b.downward_camera()).Render(T_NB * b.downward_camera()->T_BC, 1234567);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::norm(fa.image, fb.image, cv::NORM_INF), 0.0);
  EXPECT_EQ(cv::norm(fa.depth, fb.depth, cv::NORM_INF), 0.0);
  // A different time changes the noise (and the clouds), so the test above can fail.
  const Frame fc = Renderer(a, *a.downward_camera()).Render(T_NB * a.downward_camera()->T_BC, 1434567);
  EXPECT_GT(cv::norm(fa.image, fc.image, cv::NORM_L1), 0.0);
}

TEST(WorldClouds, CloudShadowsDarkenPatchesByTheirDarkness) {
  // The same ground with and without clouds: their ratio is the cloud's light factor.
  auto make = [](bool with_clouds) {
    Scene scene(8);
    GroundSpec g;
    g.material = "plain";
    scene.SetGround(g);
    CloudShadows clouds;
    clouds.enabled = with_clouds;
    clouds.coverage = 0.5;
    clouds.darkness = 0.5;
    clouds.scale_m = 40;
    scene.SetClouds(clouds);
    SunLight sun;
    sun.to_sun_N = Eigen::Vector3d(0, 0, -1);  // overhead
    sun.ambient = 0.2;
    scene.SetSun(sun);
    return scene;
  };
  const Scene cloudy = make(true), clear = make(false);
  CameraSetup cam = IdealCamera();
  cam.auto_exposure = false;
  Eigen::Isometry3d T_NC = Eigen::Isometry3d::Identity();
  T_NC.linear() = RotationBCDownward();
  T_NC.translation() = Eigen::Vector3d(0, 0, -200);
  cv::Mat a, b, ratio;
  cv::cvtColor(Renderer(cloudy, cam).Render(T_NC, 0).image, a, cv::COLOR_BGR2GRAY);
  cv::cvtColor(Renderer(clear, cam).Render(T_NC, 0).image, b, cv::COLOR_BGR2GRAY);
  a.convertTo(a, CV_32F);
  b.convertTo(b, CV_32F);
  cv::divide(a, b, ratio);
  double darkest = 0, brightest = 0;
  cv::minMaxLoc(ratio, &darkest, &brightest);
  // Full shadow keeps ambient + (1 - ambient) * (1 - darkness) = 0.2 + 0.8 * 0.5 = 0.6 of the light.
  EXPECT_NEAR(darkest, 0.6, 0.02);
  EXPECT_NEAR(brightest, 1.0, 0.02);
  const double shadowed = cv::countNonZero(ratio < 0.8) / static_cast<double>(ratio.total());
  EXPECT_GT(shadowed, 0.2);
  EXPECT_LT(shadowed, 0.8);
  // Clouds drift with the wind: 20 s later the pattern has moved.
  cv::Mat later;
  cv::cvtColor(Renderer(cloudy, cam).Render(T_NC, 20000000).image, later, cv::COLOR_BGR2GRAY);
  later.convertTo(later, CV_32F);
  EXPECT_GT(cv::norm(later, a, cv::NORM_L1) / a.total(), 1.0);
}

TEST(WorldScene, NamedScenesLoadAndRender) {
  for (const char* name : {"survey_village", "forest", "power_lines", "indoor_room", "calibration"}) {
    SCOPED_TRACE(name);
    const Scene scene = Scene::LoadFile(ScenePath(name));
    ASSERT_TRUE(scene.stereo_camera());
    const StereoRenderer r(scene, *scene.stereo_camera());
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.translation() = Eigen::Vector3d(-2, 0, -1.5);
    const StereoFrame f = r.Render(T_NB, 0);
    cv::Scalar mean, dev;
    cv::meanStdDev(f.left.image, mean, dev);
    EXPECT_GT(dev[0] + dev[1] + dev[2], 3.0) << "a blank image";
    EXPECT_GT(cv::countNonZero(f.disparity > 0), 1000);
  }
  const Scene forest = Scene::LoadFile(ScenePath("forest"));
  std::map<std::string, int> kinds;
  for (const auto& o : forest.obstacles()) ++kinds[o.kind];
  EXPECT_GE(kinds["tree"], 150);
  EXPECT_GE(kinds["person"], 4);
  const Scene lines = Scene::LoadFile(ScenePath("power_lines"));
  EXPECT_EQ(lines.cables().size(), 9u);  // 3 spans x 3 wires
}

TEST(WorldScene, BadScenesAreRejectedNamingTheEntry) {
  EXPECT_NE(ParseError("{").find("not valid JSON"), std::string::npos);
  EXPECT_NE(ParseError(R"({"seed": 1, "objects": [{"type": "box", "center_ned": [0, 0, -1], "size": [1, 1, 1],
      "material": "cheese"}]})").find("$.objects[0].material: unknown material 'cheese'"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "tree", "at_ne": [0, 0], "height_m": 5}]})")
                .find("$.objects[0]: missing 'crown_radius_m'"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "cylinder", "base_ned": [0, 0, 0], "radius_m": -1, "height_m": 2}]})")
                .find("$.objects[0].radius_m: must be in"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "ufo"}]})").find("unknown object type 'ufo'"), std::string::npos);
  EXPECT_NE(ParseError(R"({"ground": {"layout": "fields", "parcel_m": 10, "road_width_m": 12}})")
                .find("$.ground.road_width_m"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "box", "center_ned": [0, 0, NaN], "size": [1, 1, 1]}]})")
                .find("not valid JSON"), std::string::npos);
  EXPECT_NE(ParseError(R"({"cameras": {"downward": {"file": "/nonexistent.camera"}}})")
                .find("$.cameras.downward.file"), std::string::npos);
  EXPECT_NE(ParseError(R"({"objects": [{"type": "power_line", "poles_ne": [[0, 0], [3, 0]], "pole_height_m": 8,
      "sag_m": 2}]})").find("sag_m"), std::string::npos);
  // A field nobody reads is refused (a misspelling, a field of another kind of object), and a
  // number too large for a double is named with the file, not as a bare JSON error.
  EXPECT_NE(ParseError(R"({"objects": [{"type": "box", "center_ned": [0, 0, -1], "size": [1, 1, 1], "colour": "red"}]})")
                .find("bad.scene.json: $.objects[0]: unknown field 'colour' (fields here: "), std::string::npos)
      << ParseError(R"({"objects": [{"type": "box", "center_ned": [0, 0, -1], "size": [1, 1, 1], "colour": "red"}]})");
  EXPECT_NE(ParseError(R"({"seed": 1, "wind": 3})").find("$: unknown field 'wind'"), std::string::npos);
  EXPECT_NE(ParseError(R"({"seed": 1, "objects": [{"type": "box", "center_ned": [0, 0, 1e999], "size": [1, 1, 1]}]})")
                .find("bad.scene.json: not a valid scene: "), std::string::npos);
}

// A scene copied to another folder: its relative camera file is looked for beside it, then in
// the shipped cameras folder; when neither holds it the error says where it looked and what to do.
TEST(WorldScene, ACopiedSceneSaysWhereItsCameraFileIsMissing) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "uav_test_scene_copy";
  fs::remove_all(dir);
  fs::create_directories(dir);
  fs::copy_file(std::string(UAV_RESOURCE_DIR) + "/scenes/tracking.scene.json", dir / "tracking.scene.json");
  std::string error;
  try {
    Scene::LoadFile((dir / "tracking.scene.json").string());
  } catch (const std::exception& e) {
    error = e.what();
  }
  EXPECT_NE(error.find("is in neither " + (dir / "sim_downward_640x480.camera").string()), std::string::npos) << error;
  EXPECT_NE(error.find("copy it beside the scene, or give its absolute path"), std::string::npos) << error;
  for (const char* f : {"sim_downward_640x480.camera", "sim_stereo_640x480.camera"})
    fs::copy_file(std::string(UAV_RESOURCE_DIR) + "/cameras/" + f, dir / f);
  EXPECT_NO_THROW(Scene::LoadFile((dir / "tracking.scene.json").string()));
  fs::remove_all(dir);
}

// The stereo rig's mount angles: pitched down 90 degrees its optical axis is the body's down axis;
// rolled, the baseline turns about that axis; the camera frames stay parallel (a plain stereo
// pair for the matcher). Preview defaults: the stereo camera streams only without a downward one.
TEST(WorldScene, StereoMountAnglesAndPreviewDefaults) {
  const std::string cams = std::string(UAV_RESOURCE_DIR) + "/cameras/";
  const std::string stereo_file = "\"file\": \"" + cams + "sim_stereo_640x480.camera\"";
  const std::string down_file = "\"file\": \"" + cams + "sim_downward_640x480.camera\"";
  const Scene down = Scene::Parse(R"({"cameras": {"stereo": {"mount_pitch_deg": -90, )" + stereo_file + "}}}", "down.scene.json");
  const Eigen::Matrix3d R_BC = down.stereo_camera()->left.T_BC.linear();
  EXPECT_TRUE((R_BC.col(2) - Eigen::Vector3d(0, 0, 1)).norm() < 1e-9) << R_BC;  // optical axis: body down
  EXPECT_NEAR(down.stereo_camera()->left.preview_rate_hz, 5.0, 1e-12);
  const Scene rolled = Scene::Parse(
      R"({"cameras": {"downward": {)" + down_file + R"(}, "stereo": {"mount_roll_deg": 45, )" + stereo_file + "}}}", "r.scene.json");
  const world::StereoSetup& s = *rolled.stereo_camera();
  const Eigen::Vector3d baseline_B = s.right.T_BC.translation() - s.left.T_BC.translation();
  EXPECT_NEAR(baseline_B.y(), 0.12 * std::cos(M_PI / 4), 1e-9);   // body right ...
  EXPECT_NEAR(baseline_B.z(), 0.12 * std::sin(M_PI / 4), 1e-9);   // ... and down
  EXPECT_TRUE(s.T_LR().linear().isIdentity(1e-12));
  EXPECT_NEAR(s.T_LR().translation().x(), 0.12, 1e-12);
  EXPECT_EQ(s.left.preview_rate_hz, 0.0);
  try {
    Scene::Parse(R"({"cameras": {"stereo": {"mount_roll_deg": 120, )" + stereo_file + "}}}", "bad.scene.json");
    ADD_FAILURE() << "accepted a 120 degree roll";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("$.cameras.stereo.mount_roll_deg"), std::string::npos) << e.what();
  }
}

TEST(WorldScene, CameraIntrinsicsAreValidated) {
  CameraIntrinsics k;
  k.fx = -1;
  EXPECT_THROW(ValidateIntrinsics(k), std::invalid_argument);
  k = CameraIntrinsics();
  k.cx = 700;
  EXPECT_THROW(ValidateIntrinsics(k), std::invalid_argument);
  k = CameraIntrinsics();
  k.distortion[0] = std::nan("");
  EXPECT_THROW(ValidateIntrinsics(k), std::invalid_argument);
  EXPECT_NO_THROW(ValidateIntrinsics(CameraIntrinsics()));
  Scene scene(1);
  EXPECT_THROW(Renderer(scene, IdealCamera()).Render(Eigen::Isometry3d(Eigen::Matrix4d::Constant(std::nan(""))), 0),
               std::invalid_argument);
}

}  // namespace
}  // namespace uav::world
