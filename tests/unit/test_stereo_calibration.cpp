// Stereo calibration (thesis 3.3) from chessboard pairs: rendered boards recover the simulator's
// exact rig, opencv-doc's real 13-pair set gives its known baseline, and the calibration file
// round-trips and refuses bad content by name.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "unit/scene_test_util.hpp"
#include "uav/shared/frames.hpp"
#include "uav/vision/stereo_calibration.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

const std::string kOpenCvData = "/usr/share/doc/opencv-doc/examples/data/";

TEST(StereoCalibration, RenderedBoardsRecoverTheRig) {
  const world::Scene& scene = test::CachedScene("calibration");
  const world::StereoSetup& setup = *scene.stereo_camera();
  const world::StereoRenderer renderer(scene, setup);
  const world::Chessboard& board = scene.chessboards().at(0);
  const Eigen::Vector3d centre_N = board.T_N_board * Eigen::Vector3d(4 * board.square_m, 2.5 * board.square_m, 0);
  std::vector<cv::Mat> left, right;
  for (int i = 0; i < 16; ++i) {
    // Rig positions around the board: distance 0.7..1.3 m, off-axis, yawed, pitched and rolled.
    const double dist = 0.7 + 0.6 * ((i * 7) % 11) / 10.0;
    const Eigen::Vector3d eye = centre_N + Eigen::Vector3d(-dist, 0.25 * std::sin(i * 1.7), 0.15 * std::cos(i * 2.3));
    const Eigen::Vector3d to = centre_N - eye;
    EulerAngles e;
    e.psi = std::atan2(to.y(), to.x()) + 0.08 * std::sin(i * 0.9);
    e.theta = std::atan2(-to.z(), to.head<2>().norm()) + 0.06 * std::cos(i * 1.3);
    e.phi = 0.35 * std::sin(i * 0.77);
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.linear() = RotationNBFromEuler(e);
    T_NB.translation() = eye - T_NB.linear() * setup.T_BE.translation();
    const world::StereoFrame f = renderer.Render(T_NB, i * 100000);
    left.push_back(f.left.image);
    right.push_back(f.right.image);
  }
  const StereoCalibration c = CalibrateStereo(left, right, {board.cols, board.rows, board.square_m});
  std::printf("[ calib ] %zu pairs, RMS %.3f px, baseline %.5f m, fx %.2f (true %.2f)\n", c.used_pairs.size(), c.rms_px,
              c.rig.T_LR.translation().norm(), c.rig.left.fx, setup.left.intrinsics.fx);
  ASSERT_GE(c.used_pairs.size(), 10u);
  EXPECT_NEAR(c.rig.T_LR.translation().norm(), setup.baseline_m, 0.01 * setup.baseline_m);
  EXPECT_NEAR(c.rig.T_LR.translation().x(), setup.baseline_m, 0.01 * setup.baseline_m);  // right camera to the right
  EXPECT_NEAR(c.rig.left.fx, setup.left.intrinsics.fx, 0.01 * setup.left.intrinsics.fx);
  EXPECT_NEAR(c.rig.left.distortion[0], setup.left.intrinsics.distortion[0], 0.02);
  EXPECT_LT(c.rms_px, 0.5);
}

TEST(StereoCalibration, OpenCvDocPairsAndFileRoundTrip) {
  std::vector<cv::Mat> left, right;
  for (int i : {1, 2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14}) {
    char name[32];
    std::snprintf(name, sizeof name, "%02d.jpg", i);
    left.push_back(cv::imread(kOpenCvData + "left" + name, cv::IMREAD_GRAYSCALE));
    right.push_back(cv::imread(kOpenCvData + "right" + name, cv::IMREAD_GRAYSCALE));
    ASSERT_FALSE(left.back().empty() || right.back().empty()) << "opencv-doc is not installed (.ci/setup installs it)";
  }
  // Square size 1: lengths in squares. OpenCV's stereo_calib sample reports |T| of about 3.3 squares.
  const StereoCalibration c = CalibrateStereo(left, right, {9, 6, 1.0});
  std::printf("[ calib ] opencv-doc: %zu of 13 pairs, RMS %.3f px, T_LR %.3f %.3f %.3f squares\n", c.used_pairs.size(),
              c.rms_px, c.rig.T_LR.translation().x(), c.rig.T_LR.translation().y(), c.rig.T_LR.translation().z());
  EXPECT_GE(c.used_pairs.size(), 10u);
  EXPECT_LT(c.rms_px, 1.0);
  EXPECT_NEAR(c.rig.T_LR.translation().norm(), 3.3, 0.3);

  const auto dir = std::filesystem::temp_directory_path() / ("uav_calib_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  for (const char* ext : {".yml", ".json"}) {
    const std::string path = (dir / (std::string("rig") + ext)).string();
    WriteStereoCalibration(path, c);
    const StereoCalibration back = ReadStereoCalibration(path);
    EXPECT_NEAR(back.rig.left.fx, c.rig.left.fx, 1e-9) << ext;
    EXPECT_NEAR(back.rig.right.distortion[1], c.rig.right.distortion[1], 1e-9) << ext;
    EXPECT_TRUE(back.rig.T_LR.isApprox(c.rig.T_LR, 1e-9)) << ext;
    EXPECT_NEAR(back.rms_px, c.rms_px, 1e-12) << ext;
  }
  // Bad files are named with what is wrong.
  auto message = [](const std::string& path) {
    try {
      ReadStereoCalibration(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message((dir / "missing.yml").string()).find("no such file"), std::string::npos);
  const std::string broken = (dir / "broken.yml").string();
  std::ofstream(broken) << "%YAML:1.0\nimage_width: 640\nimage_height: 480\n";
  EXPECT_NE(message(broken).find("missing K1"), std::string::npos) << message(broken);
  std::ofstream(broken) << "%YAML:1.0\nimage_width: 640\nimage_height: 480\nK1: !!opencv-matrix\n  rows: 3\n  cols: 3\n"
                           "  dt: d\n  data: [ .nan, 0, 320, 0, 500, 240, 0, 0, 1 ]\n";
  EXPECT_NE(message(broken).find("K1 is not finite"), std::string::npos);
  std::ofstream(broken) << "not: [yaml";
  EXPECT_NE(message(broken).find(broken), std::string::npos);
  // 56 bytes that make OpenCV's YAML parser loop forever (found by fuzz_stereo_calibration):
  // refused before it sees them.
  std::ofstream(broken) << "%YAML:1.0\n---VVVVVVVVVV%YAML:01\n-.--0\n---VVVVVVVVVVV%VV";
  EXPECT_NE(message(broken).find("line 2 is not"), std::string::npos) << message(broken);
  EXPECT_THROW(WriteStereoCalibration((dir / "rig.txt").string(), c), std::runtime_error);
  std::filesystem::remove_all(dir);
  // Too few boards: named.
  EXPECT_THROW(CalibrateStereo({left[0]}, {right[0]}, {9, 6, 1.0}), std::invalid_argument);
  EXPECT_THROW(CalibrateStereo(left, right, {9, 9, 1.0}), std::invalid_argument);
}

}  // namespace
}  // namespace uav::vision
