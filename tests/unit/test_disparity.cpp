// Disparity (thesis 3.5.1) on real and rendered pairs: opencv-doc's Middlebury aloe pair against
// its ground truth beside OpenCV's StereoSGBM with its documented defaults; BM and SGBM against
// the renderer's exact disparity; bad input named.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "unit/scene_test_util.hpp"
#include "uav/vision/disparity.hpp"
#include "uav/vision/stereo_rectifier.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

const std::string kOpenCvData = "/usr/share/doc/opencv-doc/examples/data/";

struct AloeCase {
  MatcherKind matcher;
  int downscale;        // the pair and its ground truth shrunk by this factor
  int num_disparities;  // the same search range for every matcher
  double measured_share;  // our bad-pixel rate (missing counted bad) at most this share of OpenCV's
  double dense_share;     // the same for the densified map
};

class AloeDisparity : public ::testing::TestWithParam<AloeCase> {};

// opencv-doc's Middlebury aloe pair against aloeGT.png (disparity in pixels at full resolution,
// 0 unknown): ours (uav-stereo's defaults: SGBM, 5 px window, no texture mask) against OpenCV's
// StereoSGBM with its documented defaults widened to the same search range. At full resolution
// the scene spans 211 px of disparity: 256 covers it, 128 does not (pixels beyond the range
// cannot be measured by anyone); at half resolution 128 covers it.
TEST_P(AloeDisparity, HalvesTheBadPixelRateOfOpenCvDefaultSgbm) {
  const AloeCase c = GetParam();
  cv::Mat left = cv::imread(kOpenCvData + "aloeL.jpg", cv::IMREAD_GRAYSCALE);
  cv::Mat right = cv::imread(kOpenCvData + "aloeR.jpg", cv::IMREAD_GRAYSCALE);
  const cv::Mat truth8 = cv::imread(kOpenCvData + "aloeGT.png", cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(left.empty() || right.empty() || truth8.empty()) << "opencv-doc is not installed (.ci/setup installs it)";
  cv::Mat truth;
  truth8.convertTo(truth, CV_32F, 1.0 / c.downscale);
  if (c.downscale > 1) {
    const cv::Size small(left.cols / c.downscale, left.rows / c.downscale);
    cv::resize(left, left, small, 0, 0, cv::INTER_AREA);
    cv::resize(right, right, small, 0, 0, cv::INTER_AREA);
    cv::resize(truth, truth, small, 0, 0, cv::INTER_NEAREST);
  }
  DisparityParams p;
  p.matcher = c.matcher;
  p.downscale = 1;
  p.num_disparities = c.num_disparities;
  p.block_size = 5;
  p.texture_threshold = 0.0;
  const DisparityMap ours = DisparityMatcher(p).Compute(left, right);
  const DisparityErrors measured = CompareDisparity(ours.d16, truth);
  const DisparityErrors dense = CompareDisparity(ours.Densified().d16, truth);
  cv::Mat d;
  cv::Ptr<cv::StereoSGBM> sgbm = cv::StereoSGBM::create();
  sgbm->setNumDisparities(c.num_disparities);
  sgbm->compute(left, right, d);
  const DisparityErrors opencv = CompareDisparity(d, truth);
  std::printf("[ %s, aloe 1/%d, %d disparities ] bad pixels: ours %.1f %% (missing %.1f %%, wrong of given %.1f %%), "
              "densified %.1f %%; OpenCV SGBM defaults %.1f %% (missing %.1f %%, wrong of given %.1f %%)\n",
              MatcherKindName(c.matcher), c.downscale, c.num_disparities, 100 * measured.bad_fraction, 100 * measured.invalid_fraction,
              100 * measured.bad_valid_fraction, 100 * dense.bad_fraction, 100 * opencv.bad_fraction,
              100 * opencv.invalid_fraction, 100 * opencv.bad_valid_fraction);
  EXPECT_LT(measured.bad_fraction, c.measured_share * opencv.bad_fraction);
  EXPECT_LT(dense.bad_fraction, c.dense_share * opencv.bad_fraction);
  EXPECT_LT(measured.bad_valid_fraction, 0.5 * opencv.bad_valid_fraction);
  EXPECT_EQ(dense.invalid_fraction, 0.0);
}

// Our census matcher leaves more holes than SGBM refined (it has five paths, no 5 x 5 cost
// window) and wrong values are fewer; its densified map is the one that halves OpenCV's rate.
INSTANTIATE_TEST_SUITE_P(Ranges, AloeDisparity,
                         ::testing::Values(AloeCase{MatcherKind::kSemiGlobal, 1, 256, 0.5, 0.3},
                                           AloeCase{MatcherKind::kSemiGlobal, 2, 128, 0.5, 0.3},
                                           AloeCase{MatcherKind::kSemiGlobal, 1, 128, 0.6, 0.45},
                                           AloeCase{MatcherKind::kCensusSemiGlobal, 1, 256, 0.6, 0.35},
                                           AloeCase{MatcherKind::kCensusSemiGlobal, 2, 128, 0.6, 0.35},
                                           AloeCase{MatcherKind::kCensusSemiGlobal, 1, 128, 0.7, 0.5}),
                         [](const auto& info) {
                           return std::string(MatcherKindName(info.param.matcher)) + "_scale_1_in_" +
                                  std::to_string(info.param.downscale) + "_range_" + std::to_string(info.param.num_disparities);
                         });

class RenderedDisparity : public ::testing::TestWithParam<MatcherKind> {};

TEST_P(RenderedDisparity, MatchesTheRenderersExactDisparity) {
  const world::Scene& scene = test::CachedScene("forest");
  const world::StereoSetup& setup = *scene.stereo_camera();
  const world::StereoRenderer renderer(scene, setup);
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(4, 1.5, -1.2);
  const world::StereoFrame f = renderer.Render(T_NB, 1000000);
  const StereoRectifier rectifier({setup.left.intrinsics, setup.right.intrinsics, setup.T_LR()});
  cv::Mat l, r;
  rectifier.Rectify(f.left.image, f.right.image, &l, &r);
  DisparityParams p;
  p.matcher = GetParam();
  const DisparityMap d = DisparityMatcher(p).Compute(l, r);
  const cv::Mat full = d.FullResolution16U(l.size());
  cv::Mat truth(l.size(), CV_32F, cv::Scalar(0));
  const RectifiedGeometry& g = rectifier.geometry();
  // Truth from the exact depth of each raw pixel, placed at its rectified position.
  for (int v = 0; v < f.left.depth.rows; ++v)
    for (int u = 0; u < f.left.depth.cols; ++u) {
      const float z = f.left.depth.at<float>(v, u);
      if (!(z > 0)) continue;
      const Eigen::Vector2d x = Unproject(setup.left.intrinsics, Eigen::Vector2d(u, v));
      const Eigen::Vector3d p_rect = g.R_L_rect.transpose() * Eigen::Vector3d(x.x() * z, x.y() * z, z);
      const int ur = static_cast<int>(std::lround(g.cx + g.f_px * p_rect.x() / p_rect.z()));
      const int vr = static_cast<int>(std::lround(g.cy + g.f_px * p_rect.y() / p_rect.z()));
      if (ur >= 0 && vr >= 0 && ur < truth.cols && vr < truth.rows)
        truth.at<float>(vr, ur) = static_cast<float>(g.f_px * g.baseline_m / p_rect.z());
    }
  // Score only where the matcher claims a disparity (texture mask on): wrong matches, not coverage.
  cv::Mat claimed = truth.clone();
  claimed.setTo(0, full == 0);
  const DisparityErrors e = CompareDisparity(full, claimed, 2.0);
  std::printf("[ %s ] valid %.1f %%, of those off by > 2 px %.1f %%, mean |error| %.2f px\n", MatcherKindName(GetParam()),
              100 * d.ValidFraction(), 100 * e.bad_fraction, e.mean_abs_error_px);
  EXPECT_GT(d.ValidFraction(), GetParam() == MatcherKind::kBlockMatching ? 0.15 : 0.3);
  EXPECT_LT(e.bad_fraction, 0.15);
}

INSTANTIATE_TEST_SUITE_P(Matchers, RenderedDisparity,
                         ::testing::Values(MatcherKind::kBlockMatching, MatcherKind::kSemiGlobal, MatcherKind::kCensusSemiGlobal),
                         [](const auto& info) { return std::string(MatcherKindName(info.param)); });

// A textured plane at a known sub-pixel disparity (the right image is the left one shifted by
// resampling): our census matcher finds it everywhere it can see it, to a small fraction of a
// pixel, and gives the same map whatever the number of threads (the strips are fixed).
TEST(CensusDisparity, FindsAKnownShiftAndDoesNotDependOnTheThreadCount) {
  cv::Mat noise(480, 640, CV_8UC1);
  cv::RNG rng(7);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 255);
  cv::Mat left;
  cv::GaussianBlur(noise, left, cv::Size(), 1.2);  // texture of a few pixels, as a camera sees it
  constexpr double kShiftPx = 37.3;
  cv::Mat map_x(left.size(), CV_32F), map_y(left.size(), CV_32F);
  for (int v = 0; v < left.rows; ++v)
    for (int u = 0; u < left.cols; ++u) {
      map_x.at<float>(v, u) = static_cast<float>(u + kShiftPx);  // right(u) = left(u + d)
      map_y.at<float>(v, u) = static_cast<float>(v);
    }
  cv::Mat right;
  cv::remap(left, right, map_x, map_y, cv::INTER_CUBIC, cv::BORDER_REFLECT);
  DisparityParams p;
  p.matcher = MatcherKind::kCensusSemiGlobal;
  p.downscale = 1;
  p.num_disparities = 128;
  const DisparityMap refined = DisparityMatcher(p).Compute(left, right);
  p.subpixel_refinement = false;  // the census costs' own parabola: pixel-locked, within half a pixel
  const DisparityMatcher matcher(p);
  const DisparityMap two = matcher.Compute(left, right);
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const DisparityMap one = matcher.Compute(left, right);
  cv::setNumThreads(threads);
  EXPECT_EQ(cv::countNonZero(two.d16 != one.d16), 0);
  long seen = 0, found = 0, within_half = 0, refined_found = 0, refined_close = 0;
  for (int v = 0; v < left.rows; ++v)
    for (int u = 40; u < left.cols; ++u) {  // left of 38 px the partner is outside the right image
      ++seen;
      const int d16 = two.d16.at<int16_t>(v, u), r16 = refined.d16.at<int16_t>(v, u);
      if (d16 > 0) {
        ++found;
        if (std::abs(d16 / 16.0 - kShiftPx) < 0.5) ++within_half;
      }
      if (r16 > 0) {
        ++refined_found;
        if (std::abs(r16 / 16.0 - kShiftPx) < 0.25) ++refined_close;
      }
    }
  std::printf("[ census, shift %.1f px ] found %.1f %%, within 0.5 px %.1f %% of those; refined: within 0.25 px %.1f %%\n",
              kShiftPx, 100.0 * found / seen, 100.0 * within_half / found, 100.0 * refined_close / refined_found);
  EXPECT_GT(found, 0.97 * seen);
  EXPECT_GT(within_half, 0.97 * found);
  EXPECT_GT(refined_found, 0.97 * seen);
  EXPECT_GT(refined_close, 0.97 * refined_found);
  for (int v = 0; v < left.rows; ++v)
    for (int u = 0; u < 30; ++u) EXPECT_LE(two.d16.at<int16_t>(v, u), 16 * u) << "a disparity past the image edge at " << u;
}

TEST(Disparity, BadInputIsNamed) {
  const DisparityMatcher m{DisparityParams()};
  const cv::Mat grey(240, 320, CV_8UC1, cv::Scalar(9));
  auto message = [&](const cv::Mat& l, const cv::Mat& r) {
    try {
      m.Compute(l, r);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message(grey, cv::Mat(240, 322, CV_8UC1)).find("322x240"), std::string::npos);
  EXPECT_NE(message(cv::Mat(), grey).find("empty"), std::string::npos);
  EXPECT_NE(message(grey, cv::Mat(240, 320, CV_16U)).find("8-bit"), std::string::npos);
  EXPECT_NE(message(cv::Mat(241, 320, CV_8UC1), cv::Mat(241, 320, CV_8UC1)).find("divisible"), std::string::npos);
  EXPECT_THROW(ParseMatcherKind("sad"), std::invalid_argument);
  DisparityParams bad;
  bad.block_size = 4;
  EXPECT_THROW(DisparityMatcher{bad}, std::invalid_argument);
  bad = DisparityParams();
  bad.downscale = 3;
  EXPECT_THROW(DisparityMatcher{bad}, std::invalid_argument);
  bad = DisparityParams();
  bad.matcher = ParseMatcherKind("census");
  bad.wls_filter = true;
  try {
    DisparityMatcher{bad};
    ADD_FAILURE() << "WLS with the census matcher was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("WLS"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace uav::vision
