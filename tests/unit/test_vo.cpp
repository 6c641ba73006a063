// Stereo visual odometry (thesis ch. 5) against exact ground truth: the RANSAC trial count of
// Table 5.1, the rigid motion of Eq. 5.1-5.8, a rendered 500 m flight over the village (KITTI's
// segment metric), a hovering camera that must not drift, and the pairs it must refuse.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>

#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/vision/kitti_odometry.hpp"
#include "uav/vision/stereo_vo.hpp"
#include "unit/vo_flight.hpp"

namespace uav::vision {
namespace {

using testing::RacetrackPose;
using testing::StereoFlightRenderer;

TEST(StereoVoMath, RansacIterationsAreTable51) {
  // Thesis Table 5.1: s = 3, p = 0.99.
  const double outliers[] = {0.05, 0.10, 0.20, 0.25, 0.30, 0.40, 0.50};
  const int table[] = {3, 4, 7, 9, 11, 19, 35};
  for (int i = 0; i < 7; ++i) EXPECT_EQ(RansacIterations(0.99, outliers[i], 3), table[i]) << outliers[i];
  EXPECT_EQ(RansacIterations(0.99, 0.0, 3), 1);
}

TEST(StereoVoMath, RigidMotionRecoversAKnownMotionAndRefusesALine) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  Eigen::Matrix3Xd P(3, 30);
  for (int i = 0; i < 30; ++i) P.col(i) = Eigen::Vector3d(u(rng), u(rng), 10 + u(rng));
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  T.translation() = Eigen::Vector3d(0.5, -1, 2);
  const Eigen::Matrix3Xd Q = T * P;
  Eigen::Isometry3d est;
  ASSERT_TRUE(RigidMotion(P, Q, Eigen::VectorXd::Ones(30), &est));
  EXPECT_LT((est.matrix() - T.matrix()).norm(), 1e-9);
  Eigen::Matrix3Xd line(3, 3);
  line << 0, 1, 2, 0, 1, 2, 5, 5, 5;
  EXPECT_FALSE(RigidMotion(line, T * line, Eigen::VectorXd::Ones(3), &est));
}

// The racetrack at 20 m, 6 m/s, 10 Hz (517 m), every method on the same pairs.
TEST(StereoVoFlight, VillageRacetrackPnpDriftsUnderOnePercentAndBeatsRigid) {
  const world::Scene scene = testing::VoVillage();
  const StereoFlightRenderer render(scene);
  const double speed = 6.0, alt = 20.0;
  const int frames = static_cast<int>(517.0 / speed * 10);
  // The thesis's three methods on the images alone, and PnP fed the IMU's attitude as it flies.
  const std::vector<VoMethod> methods = {VoMethod::kPnp, VoMethod::kEpnp, VoMethod::kRigid, VoMethod::kPnp};
  const auto label = [&](size_t m) { return m == 3 ? std::string("pnp+imu") : std::string(Name(methods[m])); };
  std::vector<StereoVo> vo;
  for (VoMethod m : methods) {
    VoParams p;
    p.method = m;
    vo.emplace_back(render.geometry(), p);
  }
  testing::ImuAttitude imu;
  std::vector<Eigen::Isometry3d> gt;
  std::vector<std::vector<Eigen::Isometry3d>> est(methods.size());
  std::vector<int> unhealthy(methods.size(), 0), keyframes(methods.size(), 0), restarts(methods.size(), 0);
  Eigen::Isometry3d T_N0 = Eigen::Isometry3d::Identity();
  for (int i = 0; i < frames; ++i) {
    const int64_t utime = 1'000'000 + i * 100'000LL;
    const auto f = render.Render(RacetrackPose(i * speed / 10.0, alt, speed), utime);
    if (i == 0) T_N0 = f.T_NC;
    gt.push_back(T_N0.inverse() * f.T_NC);
    RectifiedPair aided = f.pair;
    aided.R_XC = imu.R_NC(f.T_NC.linear(), 0.1 * i);
    for (size_t m = 0; m < methods.size(); ++m) {
      const VoResult r = vo[m].Process(m == 3 ? aided : f.pair);
      unhealthy[m] += !r.healthy;
      keyframes[m] += r.new_keyframe;
      if (!r.healthy) std::printf("%s frame %d: %s\n", label(m).c_str(), i, r.reason.c_str());
      restarts[m] = r.segment;
      est[m].push_back(r.T_WC);
    }
  }
  std::vector<double> errors;
  // The poses as KITTI files, for uav-vo-eval's plot (the documentation's figure).
  WriteKittiPoses(::testing::TempDir() + "vo_racetrack_truth.txt", gt);
  for (size_t m = 0; m < methods.size(); ++m) {
    WriteKittiPoses(::testing::TempDir() + "vo_racetrack_" + label(m) + ".txt", est[m]);
    const KittiErrors e = EvaluateKittiOdometry(gt, est[m]);
    const double end_error = (gt.back().translation() - est[m].back().translation()).norm();
    // Scale: the distance the odometry reads over the distance flown, frame to frame.
    double flown = 0, read = 0;
    for (size_t i = 1; i < gt.size(); ++i) {
      flown += (gt[i].translation() - gt[i - 1].translation()).norm();
      read += (est[m][i].translation() - est[m][i - 1].translation()).norm();
    }
    std::printf("%-7s: KITTI translation %.2f %% rotation %.4f deg/m over %d segments; end error %.2f m after 517 m; "
                "scale %+.2f %%; %d keyframes, %d unhealthy\n",
                label(m).c_str(), e.translation_pct, e.rotation_deg_per_m, e.segments, end_error,
                100 * (read / flown - 1), keyframes[m], unhealthy[m]);
    for (const auto& pl : e.per_length)
      std::printf("       %3.0f m: %.2f %% %.4f deg/m (%d)\n", pl.length_m, pl.translation_pct, pl.rotation_deg_per_m,
                  pl.segments);
    // A lost frame restarts the chain from the last pose (its motion is missing from the
    // estimate, which the metric then counts); at most one in this flight.
    EXPECT_LE(unhealthy[m], 1) << label(m);
    EXPECT_LE(restarts[m], 1) << label(m);
    EXPECT_GT(e.segments, 100) << label(m);
    // The 1 % asked for (measured 0.76 % PnP, 0.92 % EPnP, PnP with the IMU 0.48 %).
    if (methods[m] != VoMethod::kRigid) {
      EXPECT_LT(e.translation_pct, 1.0) << label(m);
    }
    errors.push_back(e.translation_pct);
  }
  // Thesis 5.9: PnP beats the rigid 3D-3D method, whose depth errors enter both point sets.
  EXPECT_LT(errors[0], errors[2]);
  // The IMU's attitude removes the tilt that plain ground lets vision trade for a translation.
  EXPECT_LT(errors[3], errors[0]);
}

// A hovering vehicle (position wobbling by centimetres, attitude by tenths of a degree) keeps
// seeing its keyframe: the pose is measured against it every frame, nothing is integrated, so
// after 30 s the estimate is still within centimetres of the camera (thesis 5.6).
TEST(StereoVoFlight, HoveringCameraKeepsItsKeyframeAndDoesNotDrift) {
  const world::Scene scene = testing::VoVillage();
  const StereoFlightRenderer render(scene);
  StereoVo vo(render.geometry(), VoParams{});
  std::mt19937 rng(5);
  std::normal_distribution<double> wobble(0.0, 1.0);
  Eigen::Isometry3d T_N0 = Eigen::Isometry3d::Identity();
  int keyframes = 0;
  double worst = 0.0;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector3d p_N(-25 + 0.05 * wobble(rng), 3 + 0.05 * wobble(rng), -20 + 0.03 * wobble(rng));
    const double deg = M_PI / 180;
    const auto f = render.Render(testing::BodyPose(p_N, 0.3 + 0.3 * deg * wobble(rng), -4 * deg + 0.3 * deg * wobble(rng),
                                                   0.3 * deg * wobble(rng)),
                                 1'000'000 + i * 100'000LL);
    if (i == 0) T_N0 = f.T_NC;
    const VoResult r = vo.Process(f.pair);
    ASSERT_TRUE(r.healthy) << "frame " << i << ": " << r.reason;
    keyframes += r.new_keyframe;
    worst = std::max(worst, ((T_N0.inverse() * f.T_NC).translation() - r.T_WC.translation()).norm());
  }
  std::printf("hover 30 s: %d keyframe(s), worst position error %.1f cm\n", keyframes, worst * 100);
  // Bounded by the keyframe's depth noise (0.5 m per point at 20 m with this rig, Eq. 3.7), not
  // growing with time: 11.0 cm measured, 2 keyframes.
  EXPECT_LE(keyframes, 5);
  EXPECT_LT(worst, 0.20);
}

// A vertical climb and descent over one spot (take-off and landing), the nose 3 degrees down.
// Over plain ground a sideways motion and a tilt move the image alike, and the camera's motion
// along its own axis has a sideways part here (the axis is 3 degrees off the vertical): vision
// alone reads part of it as a rotation, which then sends the rest of the climb sideways. With
// the IMU's attitude as a prior (testing::ImuAttitude) the odometry must stay over its spot.
struct ClimbErrors {
  double horizontal_m = 0, vertical_m = 0;
  int unhealthy = 0;
};
ClimbErrors FlyClimbAndDescent(bool imu_prior) {
  const world::Scene scene = testing::VoVillage();
  const StereoFlightRenderer render(scene);
  StereoVo vo(render.geometry(), VoParams{});
  testing::ImuAttitude imu;
  Eigen::Isometry3d T_N0 = Eigen::Isometry3d::Identity();
  ClimbErrors worst;
  const double deg = M_PI / 180;
  // 2 m up to 20 m at 1.5 m/s, then down to 2 m at 1 m/s (the landing's speed), 10 pairs/s.
  std::vector<double> heights;
  for (double h = 2.0; h < 20.0; h += 0.15) heights.push_back(h);
  for (double h = 20.0; h > 2.0; h -= 0.1) heights.push_back(h);
  for (size_t i = 0; i < heights.size(); ++i) {
    const auto f = render.Render(testing::BodyPose({-20, 4, -heights[i]}, 0.3, -3 * deg, 0.5 * deg),
                                 1'000'000 + int64_t(i) * 100'000LL);
    if (i == 0) T_N0 = f.T_NC;
    RectifiedPair pair = f.pair;
    if (imu_prior) pair.R_XC = imu.R_NC(f.T_NC.linear(), 0.1 * double(i));
    const VoResult r = vo.Process(pair);
    if (!r.healthy) {
      std::printf("height %.1f m: %s\n", heights[i], r.reason.c_str());
      ++worst.unhealthy;
      continue;
    }
    // In N (both positions from the first camera's pose).
    const Eigen::Vector3d e = T_N0.linear() * (r.T_WC.translation() - (T_N0.inverse() * f.T_NC).translation());
    worst.horizontal_m = std::max(worst.horizontal_m, e.head<2>().norm());
    worst.vertical_m = std::max(worst.vertical_m, std::abs(e.z()));
  }
  std::printf("climb 2-20 m and back, %s: worst horizontal error %.2f m, vertical %.2f m, %d unhealthy\n",
              imu_prior ? "IMU rotation prior" : "vision alone", worst.horizontal_m, worst.vertical_m, worst.unhealthy);
  return worst;
}

TEST(StereoVoFlight, ClimbAndDescentStayOverTheirSpotWithTheImuRotation) {
  const ClimbErrors alone = FlyClimbAndDescent(false);
  const ClimbErrors aided = FlyClimbAndDescent(true);
  EXPECT_GT(alone.horizontal_m, 0.6);  // the ambiguity the prior removes (measured 0.99 m)
  EXPECT_LT(aided.horizontal_m, 0.35);  // measured 0.27 m
  EXPECT_LT(aided.vertical_m, 0.3);
  EXPECT_EQ(aided.unhealthy, 0);
}

// Pairs it must refuse, each with its reason, leaving the pose where it was.
TEST(StereoVoInput, BadPairsAreRefusedWithTheReasonAndThePoseStays) {
  const world::Scene scene = testing::VoVillage();
  const StereoFlightRenderer render(scene);
  StereoVo vo(render.geometry(), VoParams{});
  const auto good = render.Render(testing::BodyPose({-25, 0, -20}, 0, 0, 0), 1'000'000);
  ASSERT_TRUE(vo.Process(good.pair).healthy);
  const Eigen::Isometry3d before = vo.Process([&] {
    RectifiedPair p = good.pair;
    p.left_utime = p.right_utime = 1'100'000;
    return p;
  }()).T_WC;
  int64_t t = 1'200'000;
  auto expect_refused = [&](RectifiedPair p, const std::string& why) {
    if (p.left_utime == 0) p.left_utime = p.right_utime = (t += 100'000);
    const VoResult r = vo.Process(p);
    EXPECT_FALSE(r.healthy) << why;
    EXPECT_NE(r.reason.find(why), std::string::npos) << "reason: " << r.reason;
    EXPECT_TRUE(r.T_WC.isApprox(before, 1e-12)) << why;
  };
  RectifiedPair p;
  p.left = good.pair.left;
  p.right = good.pair.right(cv::Rect(0, 0, 320, 240)).clone();
  expect_refused(p, "right image is 320x240 but the calibration is for 640x480");
  p.right = cv::Mat();
  expect_refused(p, "right image is empty");
  p.right = good.pair.right;
  p.left.convertTo(p.left, CV_16U);
  expect_refused(p, "left image must be 8-bit grey or BGR");
  p.left = good.pair.left;
  p.left_utime = t + 100'000, p.right_utime = t + 105'000;
  expect_refused(p, "unsynchronised pair: the right image was exposed 5.0 ms from the left");
  p.left_utime = p.right_utime = 0;
  p.left = cv::Mat(good.pair.left.size(), CV_8UC1, cv::Scalar(3));
  expect_refused(p, "left image is blank or dark");
  p.left = good.pair.left;
  p.right = cv::Mat(good.pair.left.size(), CV_8UC1, cv::Scalar(255));
  expect_refused(p, "right image is blank or dark");
  p.right = good.pair.right;
  p.left_utime = p.right_utime = 0;
  p.R_XC = Eigen::Matrix3d::Identity() * 1.1;
  expect_refused(p, "the IMU attitude given with the pair is not a rotation");
  p.R_XC = Eigen::Matrix3d::Identity();
  p.R_XC_covariance(0, 0) = std::nan("");
  expect_refused(p, "the IMU attitude covariance given with the pair is not a covariance");
  p.R_XC_covariance = -Eigen::Matrix3d::Identity();
  expect_refused(p, "the IMU attitude covariance given with the pair is not a covariance");
  p.R_XC.reset();
  p.R_XC_covariance.setZero();
  p.left_utime = p.right_utime = 500'000;
  expect_refused(p, "frame time does not increase");
  // A pair whose right image belongs to another place: nothing lies on the epipolar rows.
  p.left_utime = p.right_utime = 0;
  p.right = render.Render(testing::BodyPose({-5, 30, -20}, 1.0, 0, 0), t).pair.right;
  const VoResult mismatched = vo.Process([&] {
    RectifiedPair q = p;
    q.left_utime = q.right_utime = (t += 100'000);
    return q;
  }());
  EXPECT_FALSE(mismatched.healthy);
  EXPECT_NE(mismatched.reason.find("mismatched pair"), std::string::npos) << mismatched.reason;
  EXPECT_TRUE(mismatched.T_WC.isApprox(before, 1e-12)) << mismatched.reason;
  std::printf("mismatched pair: %s\n", mismatched.reason.c_str());
}

// uav-vo and uav-vo-eval on a KITTI-layout folder written from a rendered 120 m flight: the
// pose file has a line per frame and scores as the library does; a folder without calib.txt is
// refused by name and nothing is written.
// Translation error (KITTI's metric over 10-50 m segments) and scale (distance read over
// distance driven, frame to frame) of an estimate against the truth.
struct DriveScore {
  KittiErrors errors;
  double scale_pct;
};
DriveScore ScoreDrive(const std::vector<Eigen::Isometry3d>& gt, const std::vector<Eigen::Isometry3d>& est) {
  double driven = 0, read = 0;
  for (size_t i = 1; i < gt.size(); ++i) {
    driven += (gt[i].translation() - gt[i - 1].translation()).norm();
    read += (est[i].translation() - est[i - 1].translation()).norm();
  }
  return {EvaluateKittiOdometry(gt, est, {10, 20, 30, 40, 50}), 100 * (read / driven - 1)};
}

// A car through a 90-degree turn with KITTI's rig (40 m, a left turn on a 12 m radius, 40 m, at
// 6 m/s), rendered twice: with the pair as calibrated, and with the right camera's principal
// point 0.3 px to the right of where the calibration puts it (a rectification residual such as
// KITTI's own, which the development sequence shows at about 0.25 px). The disparities then
// read 0.3 px short, every depth long by a share that grows with the depth, and the motion's
// length with them; the odometry learns the offset from the motion and the error goes.
TEST(StereoVoDrive, AMiscalibratedPairThroughATurnIsCorrectedByTheOffsetItLearns) {
  const world::Scene scene = testing::VoVillage();
  const world::StereoSetup calibrated = testing::KittiRig();
  world::StereoSetup actual = calibrated;
  const double offset = 0.3;
  actual.right.intrinsics.cx += offset;
  const double speed = 6.0;
  const int frames = static_cast<int>((40 + 12 * M_PI / 2 + 40) / speed * 10);
  struct Run {
    const char* label;
    std::optional<world::StereoSetup> actual;
    double prior_sigma_px;
  };
  const std::vector<Run> runs = {{"calibrated, offset learnt", std::nullopt, VoParams{}.disparity_offset_prior_sigma_px},
                                 {"0.3 px off, offset learnt", actual, VoParams{}.disparity_offset_prior_sigma_px},
                                 {"0.3 px off, offset taken as 0", actual, 0.0}};
  std::vector<DriveScore> scores;
  std::vector<double> learnt;
  std::vector<StereoVo> vo;
  std::vector<std::vector<Eigen::Isometry3d>> est(runs.size());
  std::vector<Eigen::Isometry3d> gt;
  for (const Run& run : runs) {
    VoParams p;
    p.disparity_offset_prior_sigma_px = run.prior_sigma_px;
    vo.emplace_back(testing::StereoFlightRenderer(scene, calibrated).geometry(), p);
  }
  const StereoFlightRenderer render_calibrated(scene, calibrated), render_off(scene, calibrated, actual);
  int unhealthy = 0;
  Eigen::Isometry3d T_N0 = Eigen::Isometry3d::Identity();
  for (int i = 0; i < frames; ++i) {
    const Eigen::Isometry3d T_NB = testing::DrivePose(i * speed / 10, 40, 12, 90);
    const int64_t utime = 1'000'000 + i * 100'000LL;
    const auto good = render_calibrated.Render(T_NB, utime), off = render_off.Render(T_NB, utime);
    if (i == 0) T_N0 = good.T_NC;
    gt.push_back(T_N0.inverse() * good.T_NC);
    for (size_t r = 0; r < runs.size(); ++r) {
      const VoResult res = vo[r].Process(runs[r].actual ? off.pair : good.pair);
      unhealthy += !res.healthy;
      if (!res.healthy) std::printf("%s, frame %d: %s\n", runs[r].label, i, res.reason.c_str());
      est[r].push_back(res.T_WC);
      if (i == frames - 1) learnt.push_back(res.disparity_offset_px);
    }
  }
  WriteKittiPoses(::testing::TempDir() + "vo_turn_truth.txt", gt);
  for (size_t r = 0; r < runs.size(); ++r) {
    scores.push_back(ScoreDrive(gt, est[r]));
    WriteKittiPoses(::testing::TempDir() + "vo_turn_" + std::to_string(r) + ".txt", est[r]);
    std::printf("%-28s: %.2f %% %.4f deg/m over %d segments, scale %+.2f %%, offset learnt %+.3f px\n", runs[r].label,
                scores[r].errors.translation_pct, scores[r].errors.rotation_deg_per_m, scores[r].errors.segments,
                scores[r].scale_pct, learnt[r]);
  }
  EXPECT_EQ(unhealthy, 0);
  // The matcher's own bias on these renders is about -0.02 px (LK's disparity against the
  // renderer's exact one), so a correct pair should learn about +0.02 px and the shifted one
  // about 0.32 px (measured +0.055 and +0.271).
  EXPECT_NEAR(learnt[0], 0.02, 0.07);
  EXPECT_NEAR(learnt[1], offset + 0.02, 0.07);
  EXPECT_EQ(learnt[2], 0.0);
  // A 100 m drive's figures move by a few tenths of a percent with any change that alters one
  // RANSAC draw or keyframe (the focal length rounded to 6 digits in a calib.txt gives 0.98 % for
  // the calibrated pair's 1.25 %), hence the margins. Measured: 1.25 % and 0.80 %, scale -0.93 %
  // and -0.19 %.
  for (size_t r = 0; r < 2; ++r) {
    EXPECT_LT(scores[r].errors.translation_pct, 1.5) << runs[r].label;
    EXPECT_LT(std::abs(scores[r].scale_pct), 1.3) << runs[r].label;
  }
  // Not learnt, the offset stretches the drive: +1.42 %, 1.6 points longer than learnt.
  EXPECT_GT(scores[2].scale_pct, scores[1].scale_pct + 1.0);
  EXPECT_GT(scores[2].scale_pct, 1.0);
}

// The real development sequence (../shared/data/kitti_vo, 51 pairs, 60 m of straight road): its
// rectified pair carries an offset of about a quarter of a pixel, which made the odometry read
// the road 1.2 % long. Learnt, the error falls under 1 %.
TEST(StereoVoReal, KittiDevelopmentSequenceLearnsItsDisparityOffsetAndDriftsUnderOnePercent) {
  const KittiSequence seq = ReadKittiSequence(UAV_SHARED_DATA "/kitti_vo");
  const std::vector<Eigen::Isometry3d> gt = ReadKittiPoses(UAV_SHARED_DATA "/kitti_vo/poses.txt");
  std::vector<DriveScore> scores;
  double learnt = 0, sigma = 0;
  for (const double prior : {VoParams{}.disparity_offset_prior_sigma_px, 0.0}) {
    VoParams p;
    p.disparity_offset_prior_sigma_px = prior;
    StereoVo vo(seq.geometry, p);
    std::vector<Eigen::Isometry3d> est;
    for (size_t i = 0; i < seq.left.size(); ++i) {
      RectifiedPair pair;
      pair.left = cv::imread(seq.left[i], cv::IMREAD_GRAYSCALE);
      pair.right = cv::imread(seq.right[i], cv::IMREAD_GRAYSCALE);
      pair.left_utime = pair.right_utime = static_cast<int64_t>(seq.times_s[i] * 1e6);
      const VoResult r = vo.Process(pair);
      EXPECT_TRUE(r.healthy) << i << ": " << r.reason;
      est.push_back(r.T_WC);
      if (prior > 0) learnt = r.disparity_offset_px, sigma = r.disparity_offset_sigma_px;
    }
    scores.push_back(ScoreDrive(gt, est));
    std::printf("prior %.1f px: %.2f %% %.4f deg/m, scale %+.2f %%\n", prior, scores.back().errors.translation_pct,
                scores.back().errors.rotation_deg_per_m, scores.back().scale_pct);
  }
  std::printf("offset learnt %.3f px (sigma %.3f px)\n", learnt, sigma);
  EXPECT_GT(learnt, 0.15);  // measured 0.25
  EXPECT_LT(learnt, 0.35);
  EXPECT_LT(scores[0].errors.translation_pct, 1.0);  // measured 0.93 %
  EXPECT_LT(std::abs(scores[0].scale_pct), 0.6);     // measured +0.27 %
  EXPECT_GT(scores[1].scale_pct, 0.9);               // measured +1.18 % without the offset
  EXPECT_GT(scores[1].errors.translation_pct, 1.3);  // measured 1.52 %
}

TEST(UavVoCli, KittiFolderFromARenderedFlightScoresLikeTheLibrary) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "uav_test_vo_cli";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir / "seq" / "image_0");
  std::filesystem::create_directories(dir / "seq" / "image_1");
  const world::Scene scene = testing::VoVillage();
  const StereoFlightRenderer render(scene);
  const RectifiedGeometry& g = render.geometry();
  {
    std::ofstream calib(dir / "seq" / "calib.txt");
    calib << "P0: " << g.f_px << " 0 " << g.cx << " 0 0 " << g.f_px << " " << g.cy << " 0 0 0 1 0\n";
    calib << "P1: " << g.f_px << " 0 " << g.cx << " " << -g.f_px * g.baseline_m << " 0 " << g.f_px << " " << g.cy
          << " 0 0 0 1 0\n";
  }
  std::ofstream times(dir / "seq" / "times.txt");
  std::vector<Eigen::Isometry3d> gt;
  Eigen::Isometry3d T_N0 = Eigen::Isometry3d::Identity();
  const int frames = 200;
  for (int i = 0; i < frames; ++i) {
    const auto f = render.Render(RacetrackPose(i * 0.6, 20.0, 6.0), 1'000'000 + i * 100'000LL);
    if (i == 0) T_N0 = f.T_NC;
    gt.push_back(T_N0.inverse() * f.T_NC);
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", i);
    cv::imwrite((dir / "seq" / "image_0" / name).string(), f.pair.left);
    cv::imwrite((dir / "seq" / "image_1" / name).string(), f.pair.right);
    times << i * 0.1 << "\n";
  }
  times.close();
  WriteKittiPoses((dir / "gt.txt").string(), gt);
  const std::string run = std::string(UAV_VO_BIN) + " " + (dir / "seq").string() + " --method pnp --out " +
                          (dir / "est.txt").string() + " > " + (dir / "vo.json").string() + " 2> " +
                          (dir / "vo.err").string();
  ASSERT_EQ(std::system(run.c_str()), 0) << run;
  const nlohmann::json report = nlohmann::json::parse(std::ifstream(dir / "vo.json"));
  EXPECT_EQ(report["frames"], frames);
  EXPECT_EQ(report["healthy_frames"], frames);
  EXPECT_EQ(report["segments"], 1);
  const std::vector<Eigen::Isometry3d> est = ReadKittiPoses((dir / "est.txt").string());
  ASSERT_EQ(est.size(), gt.size());
  const KittiErrors lib = EvaluateKittiOdometry(gt, est, {25, 50, 100});
  const std::string eval = std::string(UAV_VO_EVAL_BIN) + " " + (dir / "gt.txt").string() + " " +
                           (dir / "est.txt").string() + " --lengths 25,50,100 --json " + (dir / "eval.json").string() +
                           " --plot " + (dir / "plot.png").string() + " > " + (dir / "eval.txt").string();
  ASSERT_EQ(std::system(eval.c_str()), 0) << eval;
  const nlohmann::json scored = nlohmann::json::parse(std::ifstream(dir / "eval.json"));
  EXPECT_NEAR(scored["translation_pct"].get<double>(), lib.translation_pct, 1e-6);  // 9 digits in the file
  EXPECT_NEAR(scored["rotation_deg_per_m"].get<double>(), lib.rotation_deg_per_m, 1e-8);
  EXPECT_EQ(scored["segments"], lib.segments);
  EXPECT_LT(lib.translation_pct, 2.0);
  EXPECT_EQ(cv::imread((dir / "plot.png").string()).cols, 800);
  std::printf("uav-vo on 200 rendered frames: %.2f %% over 25-100 m segments, %.1f ms per frame\n", lib.translation_pct,
              report["ms_per_frame_median"].get<double>());
  // Refusals: no calibration, and an evaluation with fewer poses than ground truth.
  std::filesystem::remove(dir / "seq" / "calib.txt");
  const std::string no_calib = std::string(UAV_VO_BIN) + " " + (dir / "seq").string() + " --out " +
                               (dir / "none.txt").string() + " 2> " + (dir / "err.txt").string();
  EXPECT_EQ(WEXITSTATUS(std::system(no_calib.c_str())), 1);
  EXPECT_FALSE(std::filesystem::exists(dir / "none.txt"));
  std::ifstream err(dir / "err.txt");
  const std::string message((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(message.find("calib.txt"), std::string::npos) << message;
  WriteKittiPoses((dir / "short.txt").string(), std::vector<Eigen::Isometry3d>(est.begin(), est.begin() + 10));
  const std::string short_eval = std::string(UAV_VO_EVAL_BIN) + " " + (dir / "gt.txt").string() + " " +
                                 (dir / "short.txt").string() + " 2> /dev/null";
  EXPECT_EQ(WEXITSTATUS(std::system(short_eval.c_str())), 1);
  if (!HasFailure()) std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace uav::vision
