// Monocular depth from motion (thesis 3.4) on rendered frames with exact depth: the grid's
// cells against the renderer's depth at the same features, in the thesis's two scenarios
// (level flight at 20 m, a descent to landing), and the frames it must refuse.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/vision/mono_depth.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

world::Scene Village() {
  return world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
}

// A camera pose looking straight down (camera x east... the scene's mount) at p_N with heading psi.
Eigen::Isometry3d DownwardPose(const world::CameraSetup& cam, const Eigen::Vector3d& p_N, double psi) {
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.linear() = Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T_NB.translation() = p_N;
  return T_NB * cam.T_BC;
}

struct CellError {
  double mean_rel = 0, max_rel = 0;  // over the frames after convergence, per cell, worst cell
  int converged_frame = -1;          // first frame at which every cell had a depth
  int cells_checked = 0;
};

// Flies `path(t)` (body position in NED) for `seconds` at the camera's rate, feeding the
// estimator the pose `nav(t, truth)` (what the navigation solution says). Every cell with a depth
// is compared with the mean exact depth at its converged features.
CellError Fly(const std::function<Eigen::Vector3d(double)>& path, double seconds,
              const std::function<Eigen::Isometry3d(double, const Eigen::Isometry3d&)>& nav, std::vector<double>* per_cell_mean = nullptr) {
  const world::Scene scene = Village();
  const world::CameraSetup cam = *scene.downward_camera();
  const world::Renderer renderer(scene, cam);
  MonoDepthEstimator est(cam.intrinsics, MonoDepthParams{});
  const double rate = cam.rate_hz;
  CellError out;
  const int cells = 12;
  std::vector<double> sum(cells, 0.0);
  std::vector<int> n(cells, 0);
  for (int i = 0; i * (1.0 / rate) <= seconds; ++i) {
    const double t = i / rate;
    const int64_t utime = static_cast<int64_t>(std::llround(t * 1e6)) + 1'000'000;
    const Eigen::Isometry3d T_NC = DownwardPose(cam, path(t), 0.3);
    const world::Frame frame = renderer.Render(T_NC, utime);
    const DepthGrid g = est.Update(frame.image, utime, nav(t, T_NC));
    EXPECT_TRUE(g.healthy) << g.reason;
    std::vector<double> truth(cells, 0.0);
    std::vector<int> count(cells, 0);
    for (const DepthFeature& f : est.features()) {
      if (!f.converged) continue;
      const int c = std::min(3, static_cast<int>(f.px.x * 4 / frame.image.cols)) +
                    4 * std::min(2, static_cast<int>(f.px.y * 3 / frame.image.rows));
      truth[c] += frame.depth.at<float>(cv::Point(std::lround(f.px.x), std::lround(f.px.y)));
      ++count[c];
    }
    bool all = true;
    for (int c = 0; c < cells; ++c) all = all && g.cells[c].state != CellState::kUnknown;
    if (all && out.converged_frame < 0) out.converged_frame = i;
    if (out.converged_frame < 0) continue;
    for (int c = 0; c < cells; ++c) {
      const DepthCell& cell = g.cells[c];
      if (cell.state == CellState::kUnknown) continue;
      EXPECT_EQ(cell.features, count[c]);
      const double rel = std::abs(cell.depth_m - truth[c] / count[c]) / (truth[c] / count[c]);
      out.max_rel = std::max(out.max_rel, rel);
      sum[c] += rel;
      ++n[c];
      ++out.cells_checked;
    }
  }
  for (int c = 0; c < cells; ++c) {
    const double m = n[c] ? sum[c] / n[c] : 1.0;
    out.mean_rel = std::max(out.mean_rel, m);
    if (per_cell_mean) per_cell_mean->push_back(m);
  }
  return out;
}

Eigen::Isometry3d Exact(double, const Eigen::Isometry3d& T) { return T; }

TEST(MonoDepthAccuracy, LevelFlightAtTwentyMetres) {
  // Scenario 1: level, straight, constant heading and speed (3 m/s) at 20 m.
  const CellError e = Fly([](double t) { return Eigen::Vector3d(-30 + 3.0 * t, 40, -20); }, 12.0, Exact);
  std::printf("level 20 m: converged at frame %d, worst cell mean error %.2f %%, worst single %.2f %% (%d cell checks)\n",
              e.converged_frame, 100 * e.mean_rel, 100 * e.max_rel, e.cells_checked);
  ASSERT_GE(e.converged_frame, 0);
  EXPECT_LT(e.mean_rel, 0.05);
  EXPECT_LT(e.max_rel, 0.10);
}

TEST(MonoDepthAccuracy, DescentToLanding) {
  // Scenario 2: constant attitude and velocity (2 m/s forward, 1 m/s down) from 20 m to 4 m.
  const CellError e = Fly([](double t) { return Eigen::Vector3d(-30 + 2.0 * t, 40, -20 + 1.0 * t); }, 16.0, Exact);
  std::printf("descent 20 -> 4 m: converged at frame %d, worst cell mean error %.2f %%, worst single %.2f %% (%d cell checks)\n",
              e.converged_frame, 100 * e.mean_rel, 100 * e.max_rel, e.cells_checked);
  ASSERT_GE(e.converged_frame, 0);
  EXPECT_LT(e.mean_rel, 0.05);
  EXPECT_LT(e.max_rel, 0.10);
}

// Frames it cannot use: cells unknown with the reason, never a made-up depth.
TEST(MonoDepthRefuses, NoNavigationNonFinitePoseWrongSizeAndNoParallax) {
  const world::Scene scene = Village();
  const world::CameraSetup cam = *scene.downward_camera();
  const world::Renderer renderer(scene, cam);
  MonoDepthEstimator est(cam.intrinsics, MonoDepthParams{});
  auto all_unknown = [](const DepthGrid& g) {
    for (const DepthCell& c : g.cells)
      if (c.state != CellState::kUnknown || c.depth_m != 0.0) return false;
    return g.cells.size() == 12u;
  };
  // Hovering: the same pose frame after frame. Features are tracked but nothing is measured.
  const Eigen::Isometry3d T = DownwardPose(cam, Eigen::Vector3d(0, 40, -20), 0.3);
  for (int i = 0; i < 10; ++i) {
    const int64_t utime = 1'000'000 + i * 200'000;
    const DepthGrid g = est.Update(renderer.Render(T, utime).image, utime, T);
    EXPECT_TRUE(g.healthy);
    EXPECT_TRUE(all_unknown(g));
    if (i > 0) {
      EXPECT_GT(g.tracked, 100);
      EXPECT_EQ(g.measured, 0);
      EXPECT_NE(g.cells[5].reason.find("no parallax"), std::string::npos) << g.cells[5].reason;
    }
  }
  const cv::Mat image = renderer.Render(T, 3'000'000).image;
  DepthGrid g = est.Update(image, 3'000'000, std::nullopt);
  EXPECT_FALSE(g.healthy);
  EXPECT_EQ(g.reason, "no navigation sample for this frame");
  EXPECT_TRUE(all_unknown(g));
  Eigen::Isometry3d nan_pose = T;
  nan_pose.translation().x() = NAN;
  g = est.Update(image, 3'200'000, nan_pose);
  EXPECT_EQ(g.reason, "the navigation pose or velocity is not finite");
  EXPECT_TRUE(all_unknown(g));
  cv::Mat small;
  cv::resize(image, small, cv::Size(320, 240));
  g = est.Update(small, 3'400'000, T);
  EXPECT_EQ(g.reason, "the image is 320x240, the calibration 640x480");
  g = est.Update(image, 3'400'000, T);
  EXPECT_TRUE(g.healthy);
  g = est.Update(image, 3'400'000, T);
  EXPECT_EQ(g.reason, "frame time is not after the previous frame's");
  EXPECT_THROW(MonoDepthEstimator(cam.intrinsics, [] { MonoDepthParams p; p.grid_cols = 0; return p; }()), std::invalid_argument);
}

}  // namespace
}  // namespace uav::vision
