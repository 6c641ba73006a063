// The final map's render (seamless_render.hpp, internal to the stitcher) on frames cut from one
// known ground image, so the map must give that image back: a dense sequence is drawn from a
// few of its frames, and none of the ground its frames saw is lost.
#include <atomic>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>

#include "seamless_render.hpp"

namespace uav::vision {
namespace {

cv::Mat Ground(const cv::Size& size) {
  cv::Mat noise(size, CV_32FC3), ground;
  cv::RNG rng(5);
  rng.fill(noise, cv::RNG::UNIFORM, 0.0, 255.0);
  cv::GaussianBlur(noise, noise, cv::Size(0, 0), 4);
  cv::normalize(noise, noise, 20, 235, cv::NORM_MINMAX);
  noise.convertTo(ground, CV_8UC3);
  return ground;
}

struct Rendered {
  SeamlessMap map;
  int frames_loaded = 0;
  double ground_kept = 0.0;     // of the footprints' union (inset by 3 px)
  double mean_error = 0.0;      // grey levels against the ground, where the map has content
};

// Frames of `image_size` seeing the ground through `H_map_img` (map pixel = ground pixel).
Rendered Render(const cv::Mat& ground, const std::vector<Eigen::Matrix3d>& H_map_img, const cv::Size& image_size) {
  const int reduce = ThumbnailReduction(image_size);
  std::vector<cv::Mat> images;
  std::vector<SeamlessFrame> frames;
  for (const Eigen::Matrix3d& H : H_map_img) {
    cv::Mat H_cv, image, grey, thumbnail;
    cv::eigen2cv(Eigen::Matrix3d(H.inverse()), H_cv);
    cv::warpPerspective(ground, image, H_cv, image_size, cv::INTER_LINEAR);
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
    cv::resize(grey, thumbnail, cv::Size(image_size.width / reduce, image_size.height / reduce), 0, 0, cv::INTER_AREA);
    images.push_back(image);
    frames.push_back({H, thumbnail});
  }
  std::vector<std::atomic<int>> loads(frames.size());
  Rendered out;
  out.map = RenderSeamless(frames, image_size, cv::Point2d((image_size.width - 1) / 2.0, (image_size.height - 1) / 2.0), 5,
                           [&](int k, const cv::Rect& region, cv::Point* origin) {
                             ++loads[k];
                             *origin = region.tl();
                             return images[k](region).clone();
                           });
  for (const std::atomic<int>& l : loads) out.frames_loaded += l > 0;
  // The union of the footprints, each inset by 3 px, in map pixels.
  cv::Mat seen(ground.size(), CV_8U, cv::Scalar(0));
  for (const Eigen::Matrix3d& H : H_map_img) {
    cv::Mat H_cv, footprint;
    cv::eigen2cv(H, H_cv);
    cv::warpPerspective(cv::Mat(image_size, CV_8U, cv::Scalar(255)), footprint, H_cv, ground.size(), cv::INTER_NEAREST);
    cv::erode(footprint, footprint, cv::Mat(), cv::Point(-1, -1), 3);
    seen |= footprint;
  }
  cv::Mat in_map(ground.size(), CV_8U, cv::Scalar(0));
  const cv::Rect where(out.map.origin, out.map.bgr.size());
  const cv::Rect inside = where & cv::Rect(cv::Point(0, 0), ground.size());
  out.map.mask(inside - out.map.origin).copyTo(in_map(inside));
  out.ground_kept = static_cast<double>(cv::countNonZero(seen & in_map)) / cv::countNonZero(seen);
  cv::Mat map_grey, ground_grey, diff;
  cv::cvtColor(out.map.bgr(inside - out.map.origin), map_grey, cv::COLOR_BGR2GRAY);
  cv::cvtColor(ground(inside), ground_grey, cv::COLOR_BGR2GRAY);
  cv::absdiff(map_grey, ground_grey, diff);
  out.mean_error = cv::mean(diff, in_map(inside) & seen(inside))[0];
  return out;
}

Eigen::Matrix3d Placement(double angle_rad, const Eigen::Vector2d& centre_map, const cv::Size& image_size) {
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity();
  H.topLeftCorner<2, 2>() = Eigen::Rotation2Dd(angle_rad).toRotationMatrix();
  const Eigen::Vector2d c((image_size.width - 1) / 2.0, (image_size.height - 1) / 2.0);
  H.topRightCorner<2, 1>() = centre_map - H.topLeftCorner<2, 2>() * c;
  return H;
}

// A dense sequence is drawn from a few of its frames; its ground is kept and given back.
struct DenseSequence {
  const char* name;
  cv::Size ground;
  int frames;
  std::function<Eigen::Matrix3d(int k, const cv::Size& image)> placement;
  int most_drawn;
  double least_kept, most_error;
};

class SeamlessRenderOf : public ::testing::TestWithParam<DenseSequence> {};

TEST_P(SeamlessRenderOf, ADenseSequenceIsDrawnFromAFewFramesAndKeepsItsGround) {
  const DenseSequence& c = GetParam();
  const cv::Size image(640, 480);
  std::vector<Eigen::Matrix3d> H;
  for (int k = 0; k < c.frames; ++k) H.push_back(c.placement(k, image));
  const Rendered r = Render(Ground(c.ground), H, image);
  std::printf("[ %s ] %d of %d frames drawn, %.2f %% of the ground kept, error %.2f grey levels\n", c.name,
              r.frames_loaded, c.frames, 100 * r.ground_kept, r.mean_error);
  EXPECT_LE(r.frames_loaded, c.most_drawn);
  EXPECT_GE(r.ground_kept, c.least_kept);
  EXPECT_LT(r.mean_error, c.most_error);
}

// - line: 60 frames 8 px apart with a sideways wobble (a survey at 95 % overlap): 12 drawn,
//   99.97 % of the ground kept, 2.43 grey levels. Drawing all 60, as the render did before,
//   gave it back less well (3.72: more seams).
// - turn: 40 frames turning 1.5 degrees each about a slowly moving centre (a video turning on
//   the spot), each frame's new ground a wedge at its corners: 11 drawn, 1.9 % of the ground
//   (slivers at the outer edge) left out, 3.39 grey levels (all 40 drawn: 7.21).
INSTANTIATE_TEST_SUITE_P(
    Sequences, SeamlessRenderOf,
    ::testing::Values(
        DenseSequence{"line", cv::Size(1200, 700), 60,
                      [](int k, const cv::Size& image) {
                        return Placement(0.0, Eigen::Vector2d(330 + 8 * k, 350 + 6 * std::sin(0.4 * k)), image);
                      },
                      15, 0.999, 3.0},
        DenseSequence{"turn", cv::Size(1300, 1300), 40,
                      [](int k, const cv::Size& image) {
                        return Placement(1.5 * k * M_PI / 180.0, Eigen::Vector2d(640 + 2 * k, 650 - 1.5 * k), image);
                      },
                      15, 0.975, 4.5}),
    [](const ::testing::TestParamInfo<DenseSequence>& info) { return std::string(info.param.name); });

// A placement near the horizon puts a corner ~1e12 px out: named as too large to render, not
// an allocation that fails (a rectangle's int area overflowed and looked small before).
TEST(SeamlessRender, APlacementBeyondAnyMapIsNamedNotAllocated) {
  const cv::Size image(640, 480);
  const cv::Mat grey(image.height / 4, image.width / 4, CV_8U, cv::Scalar(100));
  Eigen::Matrix3d near_horizon = Eigen::Matrix3d::Identity();
  near_horizon(2, 1) = -1.0 / 479.0 + 1e-12;  // the bottom row's w is 1e-12 * 479
  Eigen::Matrix3d huge = Eigen::Matrix3d::Identity();
  huge(0, 0) = huge(1, 1) = 100.0;  // 64000 x 48000 px
  for (const Eigen::Matrix3d& H : {near_horizon, huge}) {
    const std::vector<SeamlessFrame> frames = {{Eigen::Matrix3d::Identity(), grey}, {H, grey}};
    try {
      RenderSeamless(frames, image, cv::Point2d(319.5, 239.5), 5, [&](int, const cv::Rect& region, cv::Point* origin) {
        *origin = region.tl();
        return cv::Mat(region.size(), CV_8UC3, cv::Scalar::all(100));
      });
      ADD_FAILURE() << "rendered";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("too large to render"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace uav::vision
