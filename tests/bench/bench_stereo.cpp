// Stereo obstacle chain speed (thesis 3.5) on a rendered 640x480 forest pair (a person and a
// pole within range, trees beyond): rectification, disparity, reprojection, range gate, voxel
// grid, ground plane, clustering and cylinders, each stage's mean time as a counter.
// Target: 25 pairs/s (40 ms) for the whole chain on this 2-core machine.
// BM_Disparity: the disparity alone on a real pair with ground truth (opencv-doc's Middlebury
// Aloe at half size, 640 x 480 cut from its middle), warm, beside OpenCV's SGBM with its
// defaults and with its sample's settings in three-way mode, with the same search range; each
// one's bad-pixel share (over 1 px off, or missing) as a counter.
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <vector>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <benchmark/benchmark.h>

#include "uav/shared/frames.hpp"
#include "uav/vision/disparity.hpp"
#include "uav/vision/stereo_obstacles.hpp"
#include "uav/world/renderer.hpp"
#include "uav/world/scene.hpp"

namespace {

void BM_StereoObstacles(benchmark::State& state) {
  const auto scene = uav::world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/forest.scene.json");
  const uav::world::StereoSetup& rig = *scene.stereo_camera();
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(3, 0, -1.5);
  const uav::world::StereoFrame pair = uav::world::StereoRenderer(scene, rig).Render(T_NB, 1'000'000);
  const uav::vision::StereoRectifier rectifier({rig.left.intrinsics, rig.right.intrinsics, rig.T_LR()});
  uav::vision::ObstacleParams params;
  params.disparity.matcher = static_cast<uav::vision::MatcherKind>(state.range(0));
  params.disparity.wls_filter = state.range(1) != 0;
  const uav::vision::StereoObstacleDetector detector(rectifier.geometry(), params);
  const Eigen::Isometry3d T_NL = T_NB * rig.left.T_BC;
  uav::vision::StereoStageTimes sum;
  double rectify_ms = 0;
  std::size_t obstacles = 0;
  for (auto _ : state) {
    const auto t0 = std::chrono::steady_clock::now();
    cv::Mat l, r;
    rectifier.Rectify(pair.left.image, pair.right.image, &l, &r);
    rectify_ms += std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    const uav::vision::StereoObstacles found = detector.Process(l, r, T_NL);
    obstacles = found.obstacles.size();
    sum.disparity_ms += found.times.disparity_ms;
    sum.reproject_ms += found.times.reproject_ms;
    sum.voxel_ms += found.times.voxel_ms;
    sum.ground_ms += found.times.ground_ms;
    sum.cluster_ms += found.times.cluster_ms;
    sum.cylinders_ms += found.times.cylinders_ms;
  }
  const double n = static_cast<double>(state.iterations());
  state.counters["obstacles"] = static_cast<double>(obstacles);
  state.counters["rectify_ms"] = rectify_ms / n;
  state.counters["disparity_ms"] = sum.disparity_ms / n;
  state.counters["reproject_ms"] = sum.reproject_ms / n;
  state.counters["voxel_ms"] = sum.voxel_ms / n;
  state.counters["ground_ms"] = sum.ground_ms / n;
  state.counters["cluster_ms"] = sum.cluster_ms / n;
  state.counters["cylinders_ms"] = sum.cylinders_ms / n;
  state.counters["pairs_per_s"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
}
// {matcher (0 BM, 1 SGBM), WLS}
BENCHMARK(BM_StereoObstacles)->Args({1, 0})->Args({0, 0})->Args({1, 1})->ArgNames({"sgbm", "wls"})
    ->Unit(benchmark::kMillisecond)->UseRealTime();

struct AloePair {
  cv::Mat left, right;  // grey, 640 x 480
  cv::Mat truth_px;     // CV_32F disparity [px], 0 unknown
};

const AloePair& Aloe() {
  static const AloePair pair = [] {
    const std::string dir = "/usr/share/doc/opencv-doc/examples/data/";
    const cv::Mat l = cv::imread(dir + "aloeL.jpg", cv::IMREAD_GRAYSCALE), r = cv::imread(dir + "aloeR.jpg", cv::IMREAD_GRAYSCALE),
                  gt = cv::imread(dir + "aloeGT.png", cv::IMREAD_GRAYSCALE);
    if (l.empty() || r.empty() || gt.empty()) throw std::runtime_error("opencv-doc's aloe pair is missing (.ci/setup installs opencv-doc)");
    const cv::Size half(l.cols / 2, l.rows / 2);
    const cv::Rect middle(0, (half.height - 480) / 2, 640, 480);
    AloePair p;
    cv::Mat small;
    cv::resize(l, small, half, 0, 0, cv::INTER_AREA);
    p.left = small(middle).clone();
    cv::resize(r, small, half, 0, 0, cv::INTER_AREA);
    p.right = small(middle).clone();
    cv::resize(gt, small, half, 0, 0, cv::INTER_NEAREST);  // a disparity is not averaged across an edge
    small(middle).convertTo(p.truth_px, CV_32F, 0.5);         // and halves with the image
    return p;
  }();
  return pair;
}

// {matcher: 0 ours on OpenCV's SGBM, 1 OpenCV SGBM defaults, 2 OpenCV SGBM as its sample
// (three-way), 3 our census matcher, 4 the same without the sub-pixel refinement}, {disparities}
void BM_Disparity(benchmark::State& state) {
  const AloePair& aloe = Aloe();
  const int matcher = static_cast<int>(state.range(0)), disparities = static_cast<int>(state.range(1));
  const bool census = matcher >= 3;
  uav::vision::DisparityParams params;
  params.downscale = 1;
  params.num_disparities = disparities;
  if (census) params.matcher = uav::vision::MatcherKind::kCensusSemiGlobal;
  params.subpixel_refinement = matcher != 4;
  const uav::vision::DisparityMatcher ours(params);
  cv::Ptr<cv::StereoSGBM> opencv =
      matcher == 1 ? cv::StereoSGBM::create(0, disparities)
                   : cv::StereoSGBM::create(0, disparities, 5, 8 * 25, 32 * 25, 1, 31, 10, 100, 32, cv::StereoSGBM::MODE_SGBM_3WAY);
  cv::Mat d16;
  uav::vision::DisparityMap map;
  for (auto _ : state) {
    if (matcher == 0 || census) {
      map = ours.Compute(aloe.left, aloe.right);
    } else {
      opencv->compute(aloe.left, aloe.right, d16);
    }
  }
  if (matcher == 0 || census) {
    state.counters["bad"] = uav::vision::CompareDisparity(map.FullResolution16U(aloe.left.size()), aloe.truth_px).bad_fraction;
    state.counters["bad_densified"] =
        uav::vision::CompareDisparity(map.Densified().FullResolution16U(aloe.left.size()), aloe.truth_px).bad_fraction;
    // The densified map's extra time (occlusion filling and a 3 x 3 median), median of 9.
    std::vector<double> ms;
    for (int i = 0; i < 9; ++i) {
      const auto t0 = std::chrono::steady_clock::now();
      benchmark::DoNotOptimize(map.Densified());
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    }
    std::nth_element(ms.begin(), ms.begin() + 4, ms.end());
    state.counters["densify_ms"] = ms[4];
  } else {
    state.counters["bad"] = uav::vision::CompareDisparity(d16, aloe.truth_px).bad_fraction;
  }
}
BENCHMARK(BM_Disparity)
    ->ArgsProduct({{0, 1, 2, 3, 4}, {64, 128}})
    ->ArgNames({"matcher", "disparities"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
