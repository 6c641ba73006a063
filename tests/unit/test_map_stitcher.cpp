// Map stitching (thesis ch. 6) on a simulated 200-frame survey of the village (buildings, trees,
// drifting cloud shadows) with a noisy navigation solution, against the renderer's ground truth.
#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <gtest/gtest.h>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/map_stitcher.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

const world::Scene& Village() {
  static const world::Scene scene =
      world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
  return scene;
}

struct SurveyFrame {
  Eigen::Isometry3d T_NC_true, T_NC_nav;
  int64_t utime;
  double distance_m;  // flown since the first frame
  Eigen::Vector2d nav_error_NE;
};

// GPS error as a receiver shows it: a bias, a random walk (per frame, per axis) and white noise
// per fix [m]. The default is a receiver over a minute (bias ~1.5 m, slow wander).
struct GpsError {
  double bias_m = 1.5, walk_m = 0.03, white_m = 0.2;
  unsigned seed = 7;
};

// `lines` 60 m lines 30 m apart joined by 10-frame cross legs, 1 m per frame (5 m/s at 5 Hz),
// heading north throughout, with a vehicle's small attitude wobble. The navigation solution
// sees the position through GPS-like errors and the attitude to 0.3 deg.
std::vector<SurveyFrame> Survey(const world::CameraSetup& cam, double altitude, int lines, const GpsError& gps = GpsError()) {
  std::vector<Eigen::Vector2d> ne;
  Eigen::Vector2d p(-30, -40 - 15.0 * (lines - 3));
  auto leg = [&](const Eigen::Vector2d& step, int n) {
    for (int i = 0; i < n; ++i) {
      ne.push_back(p);
      p += step;
    }
  };
  for (int line = 0; line < lines; ++line) {
    if (line > 0) leg({0, 3}, 10);
    leg({line % 2 == 0 ? 1.0 : -1.0, 0}, 60);
  }
  std::mt19937 rng(gps.seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  // GPS error as a receiver shows it over a minute: a bias of ~1.5 m, a slow wander, and
  // white noise per fix.
  const Eigen::Vector2d bias = gps.bias_m * Eigen::Vector2d(unit(rng), unit(rng));
  Eigen::Vector2d wander(0, 0);
  std::vector<SurveyFrame> frames;
  double distance = 0;
  for (size_t i = 0; i < ne.size(); ++i) {
    if (i > 0) distance += (ne[i] - ne[i - 1]).norm();
    EulerAngles truth;
    truth.phi = 0.03 * std::sin(0.37 * i);
    truth.theta = 0.025 * std::sin(0.23 * i + 1);
    truth.psi = 0.02 * std::sin(0.11 * i);
    EulerAngles nav = truth;
    nav.phi += 0.005 * unit(rng);
    nav.theta += 0.005 * unit(rng);
    nav.psi += 0.005 * unit(rng);
    wander += gps.walk_m * Eigen::Vector2d(unit(rng), unit(rng));
    const Eigen::Vector2d gps_error = bias + wander + gps.white_m * Eigen::Vector2d(unit(rng), unit(rng));
    auto pose = [&](const EulerAngles& e, const Eigen::Vector2d& at) {
      Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
      T_NB.linear() = RotationNBFromEuler(e);
      T_NB.translation() = Eigen::Vector3d(at.x(), at.y(), -altitude);
      return T_NB * cam.T_BC;
    };
    frames.push_back({pose(truth, ne[i]), pose(nav, ne[i] + gps_error), static_cast<int64_t>(1e6 + i * 2e5), distance,
                      gps_error});
  }
  return frames;
}

// Where the principal ray of the true camera meets the ground.
Eigen::Vector2d TrueCentre(const Eigen::Isometry3d& T_NC) {
  const Eigen::Vector3d d = T_NC.linear().col(2), o = T_NC.translation();
  const double t = -o.z() / d.z();
  return (o + t * d).head<2>();
}

// 3 lines: 200 frames (the accuracy survey); 15 lines: 1040 frames, 1 km flown (the map
// must stay straight over 1000 frames).
class VillageSurvey : public ::testing::TestWithParam<int> {};

TEST_P(VillageSurvey, KeepsPositionAndScale) {
  const int lines = GetParam();
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  const double altitude = 40;
  const std::vector<SurveyFrame> survey = Survey(cam, altitude, lines);
  ASSERT_EQ(survey.size(), static_cast<size_t>(lines * 70 - 10));
  MapStitcher stitcher(cam.intrinsics);
  int registered = 0;
  double seconds = 0, worst_scale = 0;
  std::vector<Eigen::Vector2d> centre_errors;
  for (size_t i = 0; i < survey.size(); ++i) {
    const world::Frame f = renderer.Render(survey[i].T_NC_true, survey[i].utime);
    const StitchStep step = stitcher.Add({f.image, survey[i].utime, survey[i].T_NC_nav});
    ASSERT_TRUE(step.placed) << "frame " << i << ": " << step.failure;
    registered += step.registered;
    seconds += step.seconds;
    const int k = stitcher.frames() - 1;
    centre_errors.push_back(stitcher.PlacedCentreNE(k) - TrueCentre(survey[i].T_NC_true));
    // True ground size of the centre pixel: range along the principal ray over the focal length.
    const double range = (survey[i].T_NC_true.translation().head<2>() - TrueCentre(survey[i].T_NC_true)).norm();
    const double true_pixel = std::hypot(range, altitude) / std::sqrt(cam.intrinsics.fx * cam.intrinsics.fy) /
                              (altitude / std::hypot(range, altitude));
    worst_scale = std::max(worst_scale, std::abs(stitcher.PlacedPixelSize(k) / true_pixel - 1.0));
  }
  const double flown = survey.back().distance_m;
  // The map is geo-referenced by the navigation solution, so it shares its GPS bias: the common
  // offset must be that bias (no more), and what the stitcher adds is the drift of the frame
  // centres about it, which must stay within 1 % of the distance flown.
  Eigen::Vector2d offset = Eigen::Vector2d::Zero(), nav_offset = Eigen::Vector2d::Zero();
  for (const auto& e : centre_errors) offset += e / centre_errors.size();
  for (const auto& f : survey) nav_offset += f.nav_error_NE / survey.size();
  double worst_centre = 0;
  for (const auto& e : centre_errors) worst_centre = std::max(worst_centre, (e - offset).norm());
  const Mosaic map = stitcher.Render();
  std::printf("[ stitch ] %zu frames, %d registered, %.1f ms/frame, offset %.2f m (navigation's %.2f m), worst centre drift %.2f m of %.0f m "
              "flown (%.2f %%), worst scale %.2f %%, map %dx%d at %.3f m/px, %zu tiles (%.1f MB)\n",
              survey.size(), registered, 1e3 * seconds / survey.size(), offset.norm(), nav_offset.norm(), worst_centre, flown,
              100 * worst_centre / flown,
              100 * worst_scale, map.bgr.cols, map.bgr.rows, map.gsd_m, stitcher.tiles(), stitcher.memory_bytes() / 1e6);
  if (const char* out = std::getenv("UAV_TEST_MAP_OUT")) cv::imwrite(out, map.bgr);  // to look at it
  EXPECT_GT(registered, 0.95 * survey.size());  // the cross legs move 3 m per frame: still registered
  // Issue 7's 1 %: measured 0.50-0.66 % over four navigation-noise seeds.
  EXPECT_LT(worst_centre, 0.01 * flown);
  EXPECT_LT((offset - nav_offset).norm(), 0.5) << "navigation's mean error " << nav_offset.transpose();
  EXPECT_LT(worst_scale, 0.02);
  // The map covers the area flown: 60 m lines plus the footprint, north up.
  EXPECT_GT(map.bgr.rows * map.gsd_m, 60 + 30);
  EXPECT_GT(map.bgr.cols * map.gsd_m, 30 * (lines - 1) + 40);
}
INSTANTIATE_TEST_SUITE_P(MapStitcher, VillageSurvey, ::testing::Values(3, 15),
                         [](const auto& info) { return std::to_string(info.param) + "_lines"; });

// The seam jump against ground truth: ground points seen by two frames of different lines,
// projected into each with the true poses, and placed on the map by each frame's placement;
// the distance between the two map positions is what shows as a step across the seam.
std::vector<double> SeamJumps(const std::vector<FramePlacement>& placed, const std::vector<SurveyFrame>& survey,
                              const CameraIntrinsics& k) {
  auto project = [&](const Eigen::Isometry3d& T_NC, const Eigen::Vector3d& p_N, Eigen::Vector2d* px) {
    const Eigen::Vector3d p_C = T_NC.inverse() * p_N;
    if (p_C.z() <= 0) return false;
    *px = Eigen::Vector2d(k.fx * p_C.x() / p_C.z() + k.cx, k.fy * p_C.y() / p_C.z() + k.cy);
    return px->x() >= 0 && px->y() >= 0 && px->x() <= k.width - 1 && px->y() <= k.height - 1;
  };
  auto apply = [](const Eigen::Matrix3d& H, const Eigen::Vector2d& p) {
    const Eigen::Vector3d q = H * p.homogeneous();
    return Eigen::Vector2d(q.head<2>() / q.z());
  };
  std::vector<double> jumps;
  for (size_t b = 0; b < survey.size(); b += 5) {
    for (size_t a = 0; a + 40 < b; a += 5) {  // frames at least 40 m of flight apart: another line
      const Eigen::Vector2d ca = TrueCentre(survey[a].T_NC_true), cb = TrueCentre(survey[b].T_NC_true);
      if ((ca - cb).norm() > 35) continue;
      for (int i = -3; i <= 3; ++i)
        for (int j = -3; j <= 3; ++j) {
          const Eigen::Vector2d g = 0.5 * (ca + cb) + Eigen::Vector2d(4.0 * i, 4.0 * j);
          Eigen::Vector2d pa, pb;
          if (!project(survey[a].T_NC_true, {g.x(), g.y(), 0}, &pa) || !project(survey[b].T_NC_true, {g.x(), g.y(), 0}, &pb))
            continue;
          jumps.push_back((apply(placed[a].H_map_img, pa) - apply(placed[b].H_map_img, pb)).norm());
        }
    }
  }
  return jumps;
}

double Percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[static_cast<size_t>(q * (v.size() - 1) + 0.5)];
}

// Global alignment (issue: seamless maps): three lines flown on a navigation solution whose GPS
// error is a random walk of about 2 m (0.14 m per frame per axis over 200 frames). The live map
// steps where lines meet; after the joint adjustment the cross-line matches agree to 1.5 px
// (p95), the seam jump measured against true projections too, and the frames sit where
// they are up to the navigation's mean error, which no image can see.
class GlobalAlignment : public ::testing::TestWithParam<unsigned> {};

TEST_P(GlobalAlignment, RemovesTheStepsBetweenSurveyLines) {
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  GpsError gps;
  gps.bias_m = 0.0;
  gps.walk_m = 0.14;
  gps.seed = GetParam();
  const std::vector<SurveyFrame> survey = Survey(cam, 40, 3, gps);
  MapStitcher stitcher(cam.intrinsics);
  for (const SurveyFrame& f : survey) ASSERT_TRUE(stitcher.Add({renderer.Render(f.T_NC_true, f.utime).image, f.utime, f.T_NC_nav}).placed);
  const std::vector<FramePlacement> live = stitcher.Placements();
  const Mosaic live_map = stitcher.Render();
  const AlignmentReport report = stitcher.Align();
  ASSERT_TRUE(report.adjusted) << report.message;
  const std::vector<FramePlacement> adjusted = stitcher.Placements();
  ASSERT_EQ(adjusted.size(), survey.size());

  const std::vector<double> jumps_before = SeamJumps(live, survey, cam.intrinsics);
  const std::vector<double> jumps_after = SeamJumps(adjusted, survey, cam.intrinsics);
  // Placement against truth: the frame centres, and their common offset (the navigation's
  // mean error carries the whole map; images cannot see it).
  std::vector<Eigen::Vector2d> error(survey.size());
  Eigen::Vector2d mean = Eigen::Vector2d::Zero(), nav_mean = Eigen::Vector2d::Zero(), nav_worst = Eigen::Vector2d::Zero();
  for (size_t i = 0; i < survey.size(); ++i) {
    error[i] = stitcher.PlacedCentreNE(static_cast<int>(i)) - TrueCentre(survey[i].T_NC_true);
    mean += error[i] / survey.size();
    nav_mean += survey[i].nav_error_NE / survey.size();
    if (survey[i].nav_error_NE.norm() > nav_worst.norm()) nav_worst = survey[i].nav_error_NE;
  }
  std::vector<double> absolute, relative;
  for (const Eigen::Vector2d& e : error) {
    absolute.push_back(e.norm());
    relative.push_back((e - mean).norm());
  }
  std::printf("[ align ] seed %u: %d cross pairs, %d frame pairs; cross-line residual median/p95 %.2f/%.2f px -> %.2f/%.2f px; "
              "seam jump vs truth p95 %.2f -> %.2f px (%zu points); placement median %.2f m (about the mean %.2f m; "
              "navigation's mean error %.2f m, worst %.2f m); %d iterations, %.2f s matching, %.2f s solving\n",
              gps.seed, report.cross_pairs, report.consecutive_pairs, report.cross_before.median_px, report.cross_before.p95_px,
              report.cross_after.median_px, report.cross_after.p95_px, Percentile(jumps_before, 0.95),
              Percentile(jumps_after, 0.95), jumps_after.size(), Percentile(absolute, 0.5), Percentile(relative, 0.5),
              nav_mean.norm(), nav_worst.norm(), report.iterations, report.seconds_matching, report.seconds_solving);
  EXPECT_GT(report.cross_pairs, 60);
  EXPECT_LE(report.cross_after.p95_px, 1.5);
  // The goal on real surveys is 2 px. Measured 0.98 and 0.66 px with each frame's tilt solved
  // (2.00 and 1.50 px with a similarity per frame: the attitude error, 0.3 deg, leans each
  // footprint).
  EXPECT_LE(Percentile(jumps_after, 0.95), 1.5);
  EXPECT_GT(Percentile(jumps_before, 0.95), 3 * Percentile(jumps_after, 0.95));  // the live map did step
  EXPECT_LE(Percentile(relative, 0.5), 0.5);
  EXPECT_LE((mean - nav_mean).norm(), 0.5);

  const Mosaic seamless = stitcher.RenderSeamless();
  ASSERT_FALSE(seamless.bgr.empty());
  // The final map covers what the live map covers, at the same place.
  EXPECT_NEAR(cv::countNonZero(seamless.mask), cv::countNonZero(live_map.mask), 0.03 * cv::countNonZero(live_map.mask));
  EXPECT_NEAR(seamless.north_top_m, live_map.north_top_m, 3.0);
  EXPECT_NEAR(seamless.east_left_m, live_map.east_left_m, 3.0);
  if (const char* out = std::getenv("UAV_TEST_MAP_OUT")) {  // to look at them
    cv::imwrite(std::string(out) + "_live.png", live_map.bgr);
    cv::imwrite(std::string(out) + "_seamless.png", seamless.bgr);
  }
}
INSTANTIATE_TEST_SUITE_P(MapStitcher, GlobalAlignment, ::testing::Values(7u, 11u),
                         [](const auto& info) { return "seed_" + std::to_string(info.param); });

TEST(MapStitcher, RejectsBadParametersAndFrames) {
  const world::CameraSetup& cam = *Village().downward_camera();
  StitcherParams p;
  p.nav_anchor_gain = 1.5;
  EXPECT_THROW(MapStitcher(cam.intrinsics, p), std::invalid_argument);
  p = StitcherParams();
  p.gsd_m = NAN;
  EXPECT_THROW(MapStitcher(cam.intrinsics, p), std::invalid_argument);
  MapStitcher stitcher(cam.intrinsics);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(0, 0, -30);
  EXPECT_THROW(stitcher.Add({cv::Mat(100, 100, CV_8UC3), 0, T}), std::invalid_argument);
  EXPECT_THROW(stitcher.Add({cv::Mat(cam.intrinsics.height, cam.intrinsics.width, CV_8UC1), 0, T}), std::invalid_argument);
  Eigen::Isometry3d nan_pose = T;
  nan_pose.translation().x() = NAN;
  EXPECT_THROW(stitcher.Add({cv::Mat(cam.intrinsics.height, cam.intrinsics.width, CV_8UC3), 0, nan_pose}),
               std::invalid_argument);
  // A camera looking at the sky cannot start a map.
  Eigen::Isometry3d up = T;
  up.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const StitchStep step = stitcher.Add({cv::Mat(cam.intrinsics.height, cam.intrinsics.width, CV_8UC3, cv::Scalar::all(80)), 0, up});
  EXPECT_FALSE(step.placed);
  EXPECT_EQ(stitcher.frames(), 0);
}

}  // namespace
}  // namespace uav::vision

namespace uav::vision {
namespace {

// Mean grey level on each side of where the newer frame's edge crosses the older one: a step
// there is a visible seam.
double SeamStep(const Mosaic& map, const cv::Mat& newer_mask) {
  cv::Mat grey, inside, outside, kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(9, 9));
  cv::cvtColor(map.bgr, grey, cv::COLOR_BGR2GRAY);
  cv::Mat not_newer = ~newer_mask & map.mask;  // older content only
  cv::Mat grown_out, grown_in;
  cv::dilate(not_newer, grown_out, kernel);
  cv::dilate(newer_mask, grown_in, kernel);
  inside = grown_out & newer_mask;
  outside = grown_in & not_newer;
  return std::abs(cv::mean(grey, inside)[0] - cv::mean(grey, outside)[0]);
}

// An exposure step between two frames (auto-exposure under a passing cloud: the second frame
// 35 % brighter) must not show as a patch: with gain compensation the step at the newer frame's
// edge is a fraction of what it is without.
TEST(MapStitcher, GainCompensationHidesAnExposureStep) {
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  Eigen::Isometry3d T1 = Eigen::Isometry3d::Identity(), T2 = Eigen::Isometry3d::Identity();
  T1.translation() = Eigen::Vector3d(0, 20, -40);
  T2.translation() = Eigen::Vector3d(12, 20, -40);
  const cv::Mat a = renderer.Render(T1 * cam.T_BC, 1'000'000).image;
  cv::Mat b = renderer.Render(T2 * cam.T_BC, 1'000'000).image;
  b.convertTo(b, CV_8UC3, 1.35);
  double step[2];
  for (const bool compensate : {true, false}) {
    StitcherParams p;
    p.gain_compensation = compensate;
    p.feather_px = 0;  // the edge as the thesis writes it: only the gain differs
    MapStitcher stitcher(cam.intrinsics, p);
    ASSERT_TRUE(stitcher.Add({a, 0, T1 * cam.T_BC}).placed);
    ASSERT_TRUE(stitcher.Add({b, 1, T2 * cam.T_BC}).placed);  // KLT may not follow a 35 % step; navigation places it
    const Mosaic map = stitcher.Render();
    // The newer frame's part of the map: everything north of its south edge.
    cv::Mat newer = cv::Mat::zeros(map.mask.size(), CV_8U);
    // Rows the newer frame covers: its footprint along track (image height) from 40 m, centred
    // 12 m north.
    const double newer_south_m = 12 - 0.5 * cam.intrinsics.height / cam.intrinsics.fy * 40;
    const int last_row = static_cast<int>((map.north_top_m - newer_south_m) / map.gsd_m);
    newer(cv::Rect(0, 0, map.mask.cols, std::min(last_row, map.mask.rows))).setTo(255);
    step[compensate ? 0 : 1] = SeamStep(map, newer & map.mask);
  }
  std::printf("[ gain ] exposure step 35 %%: seam step %.1f grey levels compensated, %.1f not\n", step[0], step[1]);
  EXPECT_LT(step[0], 0.3 * step[1]);
}

// Photos without poses chain by registration alone (Eq. 6.4). A camera tilting up from the
// vertical, 2.5 degrees a frame over a textured plane, gives steps that each pass Algorithm 1's
// gates while their product piles up perspective towards the horizon. The frames whose chained
// footprint has left the scale of a downward view are named and not placed (before, the
// render tried to allocate 34 GB on 30 such frames of UAV123's person11 and the process died);
// the frames placed before sit where the exact homography puts them, and the map renders.
TEST(MapStitcher, AChainThatTiltsTowardsTheHorizonStopsPlacingAndSaysWhy) {
  cv::Mat texture(3000, 3000, CV_8UC1);
  cv::RNG rng(11);
  cv::Mat layer(texture.size(), CV_32F), sum(texture.size(), CV_32F, cv::Scalar(0));
  for (const int blur : {3, 9, 31}) {  // texture at three scales, so corners stay in view as the footprint grows
    rng.fill(layer, cv::RNG::NORMAL, 0.0, 1.0);
    cv::GaussianBlur(layer, layer, cv::Size(0, 0), blur);
    cv::normalize(layer, layer, -1.0, 1.0, cv::NORM_MINMAX);
    sum += layer;
  }
  cv::normalize(sum, sum, 0, 255, cv::NORM_MINMAX);
  sum.convertTo(texture, CV_8U);
  CameraIntrinsics k;
  k.width = 640;
  k.height = 480;
  k.fx = k.fy = 600;
  k.cx = (k.width - 1) / 2.0;
  k.cy = (k.height - 1) / 2.0;
  Eigen::Matrix3d K = Eigen::Matrix3d::Identity();
  K(0, 0) = k.fx;
  K(1, 1) = k.fy;
  K(0, 2) = k.cx;
  K(1, 2) = k.cy;
  Eigen::Matrix3d origin = Eigen::Matrix3d::Identity();  // texture pixel -> first frame pixel
  origin(0, 2) = -1180;
  origin(1, 2) = -1900;
  MapStitcher stitcher(k);
  std::vector<int> placed_frames;
  std::vector<Eigen::Matrix3d> truth;  // first frame (map) pixel -> frame pixel
  int refused = 0;
  for (int i = 0; i < 30; ++i) {
    // Frame i sees the first frame's plane through the camera turned by 2.5 i degrees about its
    // x axis (a rotation homography K R K^-1).
    const Eigen::Matrix3d R = Eigen::AngleAxisd(2.5 * i * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
    const Eigen::Matrix3d frame_from_map = K * R * K.inverse();
    cv::Mat M, grey, bgr;
    cv::eigen2cv(Eigen::Matrix3d(frame_from_map * origin), M);
    cv::warpPerspective(texture, grey, M, cv::Size(k.width, k.height), cv::INTER_AREA, cv::BORDER_REFLECT);
    cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    const StitchStep step = stitcher.Add({bgr, i, std::nullopt});
    if (step.placed) {
      ASSERT_EQ(refused, 0) << "frame " << i << " placed after a refused one";
      placed_frames.push_back(i);
      truth.push_back(frame_from_map);
    } else {
      EXPECT_NE(step.failure.find("chained placement"), std::string::npos) << "frame " << i << ": " << step.failure;
      ++refused;
    }
  }
  std::printf("[ chain ] %zu frames placed, %d refused\n", placed_frames.size(), refused);
  EXPECT_GE(placed_frames.size(), 8u);
  EXPECT_GT(refused, 0);
  // The placed frames' corners against the exact homography.
  const std::vector<FramePlacement> placements = stitcher.Placements();
  ASSERT_EQ(placements.size(), placed_frames.size());
  double worst = 0.0;
  for (size_t j = 0; j < placements.size(); ++j) {
    const Eigen::Matrix3d map_from_frame = truth[j].inverse();
    for (const Eigen::Vector2d& q : {Eigen::Vector2d(0, 0), Eigen::Vector2d(639, 0), Eigen::Vector2d(639, 479),
                                     Eigen::Vector2d(0, 479)}) {
      const Eigen::Vector3d a = placements[j].H_map_img * q.homogeneous(), b = map_from_frame * q.homogeneous();
      worst = std::max(worst, (a.hnormalized() - b.hnormalized()).norm());
    }
  }
  std::printf("[ chain ] worst placed corner %.2f px from the exact homography\n", worst);
  EXPECT_LT(worst, 8.0);
  const Mosaic map = stitcher.RenderSeamless();
  EXPECT_FALSE(map.bgr.empty());
  EXPECT_LT(map.bgr.total(), 16u * 640 * 480);
}

// opencv-doc's real aerial pair: oblique views of a town with the camera turned and tilted and
// tall buildings (parallax). No poses: the map is aero1's pixel grid.
TEST(MapStitcher, RealAerialPairRegistersAndBlendsWithoutASeam) {
  const std::string dir = "/usr/share/doc/opencv-doc/examples/data/";
  const cv::Mat aero1 = cv::imread(dir + "aero1.jpg"), aero3 = cv::imread(dir + "aero3.jpg");
  ASSERT_FALSE(aero1.empty() || aero3.empty()) << "opencv-doc is not installed (.ci/setup installs it)";
  CameraIntrinsics k;  // the lens is unknown; a pixel map needs only the size
  k.width = aero1.cols;
  k.height = aero1.rows;
  k.cx = (k.width - 1) / 2.0;
  k.cy = (k.height - 1) / 2.0;
  // Plain SIFT finds 5 consistent matches here (a wrong homography); the affine simulation of
  // ASIFT is what OpenCV's own sample uses on this pair, with a 10 px RANSAC threshold.
  {
    const Detector detector = Detector::kAsift;
    double seam_blended = 0, seam_hard = 0;
    for (const bool compensate : {true, false}) {
      StitcherParams p;
      p.registration.detector = detector;
      p.registration.ransac_threshold_px = 10;
      p.registration.max_area_change = 2.0;            // an oblique pair, not a 5 Hz sequence
      p.registration.max_translation_fraction = 1.0;
      p.gain_compensation = compensate;
      p.feather_px = compensate ? 24 : 0;  // the thesis's hard newest-on-top edge for comparison
      MapStitcher stitcher(k, p);
      ASSERT_TRUE(stitcher.Add({aero1, 0, std::nullopt}).placed);
      const StitchStep step = stitcher.Add({aero3, 1, std::nullopt});
      ASSERT_TRUE(step.registered) << DetectorName(detector) << ": " << step.failure;
      const Mosaic map = stitcher.Render();
      EXPECT_FALSE(map.georeferenced);
      // Alignment: aero3 warped onto aero1, median grey difference where both exist.
      cv::Mat H, warped, mask, g1, g3;
      cv::eigen2cv(step.registration.H_prev_cur, H);
      cv::warpPerspective(aero3, warped, H, aero1.size());
      cv::warpPerspective(cv::Mat(aero3.size(), CV_8U, cv::Scalar(255)), mask, H, aero1.size(), cv::INTER_NEAREST);
      cv::erode(mask, mask, cv::Mat());
      cv::cvtColor(aero1, g1, cv::COLOR_BGR2GRAY);
      cv::cvtColor(warped, g3, cv::COLOR_BGR2GRAY);
      cv::Mat diff;
      cv::absdiff(g1, g3, diff);
      std::vector<uint8_t> values;
      for (int v = 0; v < diff.rows; ++v)
        for (int u = 0; u < diff.cols; ++u)
          if (mask.at<uint8_t>(v, u)) values.push_back(diff.at<uint8_t>(v, u));
      std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
      const int median = values[values.size() / 2];
      // The seam where aero3's edge crosses aero1 in the map. In a pixel map aero1 is the grid
      // (gsd 1, east = column, north = -row), so the crop starts at column east_left + 0.5 and
      // row 0.5 - north_top.
      cv::Mat placed_mask;
      Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
      shift(0, 2) = -(map.east_left_m + 0.5);
      shift(1, 2) = -(0.5 - map.north_top_m);
      cv::Mat Hm;
      cv::eigen2cv(Eigen::Matrix3d(shift * step.registration.H_prev_cur), Hm);
      cv::warpPerspective(cv::Mat(aero3.size(), CV_8U, cv::Scalar(255)), placed_mask, Hm, map.bgr.size(), cv::INTER_NEAREST);
      cv::erode(placed_mask, placed_mask, cv::Mat());
      const double seam = SeamStep(map, placed_mask & map.mask);
      if (compensate && std::getenv("UAV_TEST_MAP_OUT")) cv::imwrite(std::getenv("UAV_TEST_MAP_OUT"), map.bgr);  // to look at it
      // Landmarks picked by hand in both photographs (aero3 -> aero1): the blue roofs of the
      // shopping centre and the foot of the three red-and-white chimneys.
      const Eigen::Vector3d roofs = step.registration.H_prev_cur * Eigen::Vector3d(235, 262, 1);
      const Eigen::Vector3d chimneys = step.registration.H_prev_cur * Eigen::Vector3d(73, 270, 1);
      std::printf("[ aero ] %s, blend %s: %d inliers of %d, median difference %d grey levels, seam step %.2f, "
                  "roofs at (%.0f, %.0f), chimneys at (%.0f, %.0f)\n",
                  DetectorName(detector), compensate ? "gain + feather" : "hard edge", step.registration.inliers,
                  step.registration.tracked, median, seam, roofs.x() / roofs.z(), roofs.y() / roofs.z(),
                  chimneys.x() / chimneys.z(), chimneys.y() / chimneys.z());
      EXPECT_GT(step.registration.inliers, 40);
      EXPECT_NEAR(roofs.x() / roofs.z(), 318, 15);
      EXPECT_NEAR(roofs.y() / roofs.z(), 258, 15);
      EXPECT_NEAR(chimneys.x() / chimneys.z(), 247, 15);
      EXPECT_NEAR(chimneys.y() / chimneys.z(), 330, 15);
      EXPECT_LT(median, 25);  // the pair differs by haze and viewpoint (tall buildings)
      (compensate ? seam_blended : seam_hard) = seam;
    }
    EXPECT_LT(seam_blended, 0.7 * seam_hard);
  }
}

}  // namespace
}  // namespace uav::vision
