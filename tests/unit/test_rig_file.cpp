// Rig files: which recorded or live camera feeds which worker, read and checked before a run;
// each mistake named by its field.
#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "uav/runtime/rig_file.hpp"
#include "unit/runtime_test_data.hpp"

namespace uav::runtime {
namespace {

using ::testing::HasSubstr;

std::string Kitti(const std::string& extra_workers = "") {
  return R"({"cameras": {"front": {"type": "kitti", "path": ")" + KittiDir() +
         R"(", "mount": {"xyz_m": [0, 0, -1.65]}}}, "workers": {"odometry": "front", "obstacles": "front")" + extra_workers + "}}";
}

TEST(RigFileTest, AKittiRigFeedsOdometryAndObstaclesWithTheTruthAsPose) {
  const auto rig = RigFile::Parse(Kitti(R"(, "wires": "front")"), "", "kitti.rig.json", 0);
  EXPECT_NE(rig->rig().odometry, nullptr);
  EXPECT_EQ(rig->rig().odometry, rig->rig().obstacles);
  EXPECT_EQ(rig->rig().wires, rig->rig().obstacles);  // the obstacle worker finds the wires too
  EXPECT_EQ(rig->rig().survey, nullptr);
  EXPECT_EQ(rig->pose_source(), RigFile::PoseSource::kTruth);
  ASSERT_NE(rig->truth(), nullptr);
  // 51 frames at 10 Hz: the last is exposed 5 s in, and taken half a frame later.
  EXPECT_EQ(rig->end_utime(), 5'050'000);
  EXPECT_THAT(rig->Describe(), HasSubstr("front: KITTI sequence"));
  EXPECT_THAT(rig->Describe(), HasSubstr("51 pairs at 10.0 Hz, ground truth; obstacles, odometry, wires"));
  // The truth at the vehicle's time: 2.5 s in is frame 25's pose.
  EXPECT_GT(rig->TruthAt(2'500'000).translation().x(), 20.0);
}

TEST(RigFileTest, APhotoFolderWithItsCalibrationFeedsTheTracker) {
  TempDir dir("rig_photos");
  CopyKittiLeft(dir.path(), 3);
  std::ofstream(dir.path() + "/cam.yaml") << "%YAML:1.0\n---\nimage_width: 1226\nimage_height: 370\n"
                                          << "camera_matrix: !!opencv-matrix\n   rows: 3\n   cols: 3\n   dt: d\n"
                                          << "   data: [ 707.0912, 0., 601.8873, 0., 707.0912, 183.1104, 0., 0., 1. ]\n"
                                          << "distortion_coefficients: !!opencv-matrix\n   rows: 1\n   cols: 5\n   dt: d\n"
                                          << "   data: [ -0.1, 0.01, 0., 0., 0. ]\n";
  const std::string text =
      R"({"cameras": {"gimbal": {"type": "photos", "path": "photos", "calibration": "cam.yaml", "rate_hz": 5,
                                 "mount": {"pitch_deg": -30}}},
          "workers": {"tracking": "gimbal"}})";
  const auto rig = RigFile::Parse(text, dir.path(), "photos.rig.json", 0);
  ASSERT_NE(rig->rig().tracking, nullptr);
  EXPECT_NEAR(rig->rig().tracking->pitch_rad(), -30 * M_PI / 180, 1e-9);
  EXPECT_DOUBLE_EQ(rig->rig().tracking->info().intrinsics.distortion[0], -0.1);
  EXPECT_EQ(rig->pose_source(), RigFile::PoseSource::kFixed);  // no truth, no odometry
}

struct Refusal {
  std::string name, text, expected;
};

class RigFileRefusal : public ::testing::TestWithParam<Refusal> {};

TEST_P(RigFileRefusal, IsNamed) {
  TempDir dir("rig_refusal");
  CopyKittiLeft(dir.path(), 2);
  std::ofstream(dir.path() + "/small.camera") << "sensor_width_mm 4.8\nsensor_height_mm 3.6\nfocal_length_mm 4\n"
                                              << "image_width_px 320\nimage_height_px 240\n";
  std::ofstream(dir.path() + "/kitti.camera") << "sensor_width_mm 5.5\nsensor_height_mm 1.66\nfocal_length_mm 3.2\n"
                                              << "image_width_px 1226\nimage_height_px 370\n";
  try {
    RigFile::Parse(GetParam().text, dir.path(), "bad.rig.json", 0);
    FAIL() << "accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("rig file 'bad.rig.json'"));
    EXPECT_THAT(e.what(), HasSubstr(GetParam().expected));
  }
}

INSTANTIATE_TEST_SUITE_P(
    EachMistake, RigFileRefusal,
    ::testing::Values(
        Refusal{"NotJson", "{", "not JSON"},
        Refusal{"UnknownField", R"({"cameras": {}, "workers": {}, "speed": 2})", "$: unknown field 'speed'"},
        Refusal{"NoCameras", R"({"cameras": {}, "workers": {"odometry": "x"}})", "needs \"cameras\""},
        Refusal{"UnknownType", R"({"cameras": {"a": {"type": "zed", "path": "x"}}, "workers": {"tracking": "a"}})",
                "cameras.a.type: 'zed' is not a camera type"},
        Refusal{"MissingFolder", R"({"cameras": {"a": {"type": "kitti", "path": "nowhere"}}, "workers": {"odometry": "a"}})",
                "cameras.a: KITTI sequence"},
        Refusal{"UnknownWorker", Kitti(R"(, "slam": "front")"), "workers.slam: not a worker"},
        Refusal{"UndeclaredCamera", Kitti(R"(, "wires": "rear")"), "workers.wires: names 'rear'"},
        Refusal{"MonoForOdometry",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "kitti.camera", "rate_hz": 5}},
                    "workers": {"odometry": "a"}})",
                "'a' is a mono camera; odometry needs a stereo pair"},
        Refusal{"CalibrationOfAnotherSize",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "small.camera", "rate_hz": 5}},
                    "workers": {"tracking": "a"}})",
                "1226 x 370 px but the calibration is 320 x 240"},
        Refusal{"MissingCalibration",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "none.yaml", "rate_hz": 5}},
                    "workers": {"tracking": "a"}})",
                "calibration '"},
        Refusal{"PhotosWithoutTimes",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "small.camera"}},
                    "workers": {"tracking": "a"}})",
                "no frame times"},
        Refusal{"UnusedCamera",
                R"({"cameras": {"a": {"type": "kitti", "path": ")" + KittiDir() + R"("},
                                "b": {"type": "kitti", "path": ")" + KittiDir() + R"("}},
                    "workers": {"odometry": "a"}})",
                "cameras.b: no worker uses it"},
        Refusal{"TruthWithoutOne",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "kitti.camera", "rate_hz": 5}},
                    "workers": {"tracking": "a"}, "pose": "truth"})",
                "pose: \"truth\" but no recording here has ground truth"},
        Refusal{"OdometryPoseWithNoOdometryWorker",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "kitti.camera", "rate_hz": 5}},
                    "workers": {"tracking": "a"}, "pose": "odometry"})",
                "pose: \"odometry\" but no stereo pair feeds the odometry worker"},
        Refusal{"BadMount",
                R"({"cameras": {"a": {"type": "photos", "path": "photos", "calibration": "kitti.camera", "rate_hz": 5,
                                      "mount": {"pitch_deg": 120}}},
                    "workers": {"tracking": "a"}})",
                "cameras.a.mount.pitch_deg: must be a number in [-90"}),
    [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace uav::runtime
