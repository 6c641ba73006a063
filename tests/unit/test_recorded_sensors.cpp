// The recorded and live camera back-ends on real data: the KITTI development sequence of
// ../shared/data/kitti_vo played on the vehicle clock, EuRoC/ASL and photo-folder layouts made
// from its frames, a video file, and GStreamer's test source as a live camera; and every way a
// recording or a device can be broken, each named.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <thread>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/runtime/live_camera.hpp"
#include "uav/runtime/recorded_sensors.hpp"
#include "uav/vision/kitti_odometry.hpp"
#include "unit/runtime_test_data.hpp"

namespace uav::runtime {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

constexpr int64_t kStart = 1'000'000'000;

TEST(RecordedStereo, AKittiSequencePlaysEachPairAtItsRecordedTime) {
  StereoRecording rec = ReadKittiRecording(KittiDir(), CameraMount({0, 0, -1.65}, 0.0));
  ASSERT_EQ(rec.frames.size(), 51u);
  EXPECT_NEAR(rec.rate_hz, 10.0, 1e-9);
  EXPECT_EQ(rec.layout, "KITTI");
  EXPECT_FALSE(rec.truth.empty());
  RecordedStereoCamera camera("front", std::move(rec), kStart);
  EXPECT_NEAR(camera.left().rate_hz, 10.0, 1e-9);
  EXPECT_NEAR((camera.T_LR().translation() - Eigen::Vector3d(0.537, 0, 0)).norm(), 0, 1e-3);

  // Before the first exposure: nothing, and the camera says why.
  EXPECT_TRUE(camera.Capture(kStart - 100'000, hal::Emitter::kOff).left.empty());
  EXPECT_THAT(camera.problem(), HasSubstr("not started"));
  // Frame 7 is exposed 0.7 s in; a clock 40 ms later still sees it, the image as recorded.
  const hal::StereoImages pair = camera.Capture(kStart + 740'000, hal::Emitter::kOff);
  EXPECT_EQ(pair.left_utime, kStart + 700'000);
  EXPECT_EQ(camera.problem(), "");
  cv::Mat grey;
  cv::cvtColor(pair.left, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::norm(grey, cv::imread(KittiDir() + "/image_0/000007.png", cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);
  // Past the end: nothing, named.
  EXPECT_TRUE(camera.Capture(kStart + 6'000'000, hal::Emitter::kOff).left.empty());
  EXPECT_THAT(camera.problem(), HasSubstr("recording ended (51 pairs)"));
}

TEST(RecordedStereo, TheKittiTruthPutsTheBodyInNAtItsFirstFrame) {
  const Eigen::Isometry3d T_BL = CameraMount({0, 0, -1.65}, 0.0);
  const StereoRecording rec = ReadKittiRecording(KittiDir(), T_BL);
  const std::vector<Eigen::Isometry3d> T_C0C = vision::ReadKittiPoses(KittiDir() + "/poses.txt");
  EXPECT_TRUE(rec.truth.At(rec.frames[0].t_us).isApprox(Eigen::Isometry3d::Identity(), 1e-9));
  // The camera in N: its forward (z) is north, its right (x) east, its down (y) down, from where
  // it was mounted at the start (1.65 m up). The car drives about 60 m north.
  const Eigen::Vector3d p_N = (rec.truth.At(rec.frames.back().t_us) * T_BL).translation();
  const Eigen::Vector3d t = T_C0C.back().translation();
  EXPECT_NEAR((p_N - Eigen::Vector3d(t.z(), t.x(), t.y() - 1.65)).norm(), 0.0, 1e-9);
  EXPECT_GT(p_N.x(), 50.0);
  // Between frames the pose is interpolated.
  const double mid = (rec.truth.At((rec.frames[10].t_us + rec.frames[11].t_us) / 2) * T_BL).translation().x();
  EXPECT_NEAR(mid, (T_C0C[10].translation().z() + T_C0C[11].translation().z()) / 2, 1e-4);
}

TEST(RecordedStereo, BrokenKittiFoldersAreRefusedNamingWhatIsWrong) {
  TempDir dir("kitti_broken");
  const std::string seq = CopyKitti(dir.path(), 5);
  fs::remove(seq + "/image_1/000003.png");
  try {
    ReadKittiRecording(seq, Eigen::Isometry3d::Identity());
    FAIL() << "a missing right image was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("image_0/ has 5 images but image_1/ has 4"));
  }
  const std::string seq2 = CopyKitti(dir.path() + "/b", 5);
  std::ofstream(seq2 + "/times.txt") << "0.0\n0.1\n0.1\n0.3\n0.4\n";
  try {
    ReadKittiRecording(seq2, Eigen::Isometry3d::Identity());
    FAIL() << "repeated times were accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("does not increase"));
  }
}

TEST(RecordedStereo, AnEurocFolderIsPairedByTimeWithItsCalibrationAndTruth) {
  TempDir dir("euroc");
  const std::string mav0 = MakeEuroc(dir.path(), 6);
  ASSERT_EQ(StereoLayoutOf(dir.path()), "EuRoC");
  const StereoRecording rec = ReadEurocRecording(dir.path());
  ASSERT_EQ(rec.frames.size(), 6u);
  EXPECT_NEAR(rec.rate_hz, 10.0, 1e-6);
  EXPECT_DOUBLE_EQ(rec.left.fx, 707.0912);
  EXPECT_NEAR(((rec.T_BL.inverse() * rec.T_BR).translation() - Eigen::Vector3d(0.537, 0, 0)).norm(), 0.0, 1e-9);
  ASSERT_FALSE(rec.truth.empty());
  // The z-up world's +y is N's -y (east), and N starts where the body is at the first frame.
  EXPECT_NEAR(rec.truth.At(rec.frames[0].t_us).translation().norm(), 0.0, 1e-9);
  EXPECT_NEAR(rec.truth.At(rec.frames[5].t_us).translation().y(), -0.5, 1e-9);
  RecordedStereoCamera camera("euroc", rec, kStart);
  EXPECT_FALSE(camera.Capture(kStart + 100'000, hal::Emitter::kOff).right.empty());

  // A left image without its right one, and a calibration of another size than the images.
  fs::remove(mav0 + "/cam1/data/" + std::to_string(EurocTime(2)) + ".png");
  std::ofstream(mav0 + "/cam1/data.csv", std::ios::trunc) << "#timestamp [ns],filename\n"
                                                          << EurocTime(0) << "," << EurocTime(0) << ".png\n";
  try {
    ReadEurocRecording(dir.path());
    FAIL() << "a missing right image was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("no right image at " + std::to_string(EurocTime(1)) + " ns"));
  }
  TempDir dir2("euroc_size");
  MakeEuroc(dir2.path(), 3, /*width=*/640, /*height=*/480);
  try {
    RecordedStereoCamera("euroc", ReadEurocRecording(dir2.path()), kStart);
    FAIL() << "a calibration of another size was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("image is 1226 x 370 px but the calibration is 640 x 480"));
  }
}

TEST(RecordedStereo, AnEurocImuIsReadInTheBodyFrame) {
  TempDir dir("euroc_imu");
  MakeEuroc(dir.path(), 11, 1226, 370, /*imu=*/true);
  const StereoRecording rec = ReadEurocRecording(dir.path());
  ASSERT_EQ(rec.imu.size(), 200u);  // 10 intervals of 0.1 s at 200 Hz
  EXPECT_EQ(rec.imu[1].t_us - rec.imu[0].t_us, 5000);
  // A car on a level road: the specific force is g, up (-z in FRD).
  EXPECT_NEAR(rec.imu[0].accel_B.z(), -9.80665, 0.5);
  // And the truth is KITTI's: 10 frames on, about 11 m north.
  EXPECT_NEAR(rec.truth.At(rec.frames[10].t_us).translation().x(), KittiBodyPoses_N()[10].translation().x(), 1e-6);
  // An IMU time that goes back is refused, named.
  std::ofstream(dir.path() + "/mav0/imu0/data.csv", std::ios::app) << EurocTime(0) << ",0,0,0,0,0,-9.8\n";
  try {
    ReadEurocRecording(dir.path());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("imu0/data.csv line 202: the time repeats or goes backwards"));
  }
}

TEST(RecordedMono, APhotoFolderPlaysAtItsTimesAndRefusesTimesThatGoBack) {
  TempDir dir("photos");
  const std::string photos = CopyKittiLeft(dir.path(), 4);
  std::ofstream(dir.path() + "/times.txt") << "0.0\n0.25\n0.5\n0.75\n";
  RecordedCamera::Options o;
  o.name = "down";
  o.path = photos;
  o.intrinsics = KittiIntrinsics();
  o.times_path = dir.path() + "/times.txt";
  o.start_utime = kStart;
  RecordedCamera camera(o);
  EXPECT_NEAR(camera.info().rate_hz, 4.0, 1e-9);
  EXPECT_EQ(camera.frames(), 4u);
  const cv::Mat frame2 = camera.Capture(kStart + 600'000).image;
  cv::Mat grey;
  cv::cvtColor(frame2, grey, cv::COLOR_BGR2GRAY);
  EXPECT_EQ(cv::norm(grey, cv::imread(KittiDir() + "/image_0/000002.png", cv::IMREAD_GRAYSCALE), cv::NORM_INF), 0.0);

  std::ofstream(dir.path() + "/back.txt") << "0.0\n0.25\n0.2\n0.75\n";
  o.times_path = dir.path() + "/back.txt";
  EXPECT_THROW(
      {
        try {
          RecordedCamera bad(o);
        } catch (const std::runtime_error& e) {
          EXPECT_THAT(e.what(), HasSubstr("frame 2 (000002.png) is at 200000 us, not after frame 1"));
          throw;
        }
      },
      std::runtime_error);
  o.times_path = dir.path() + "/times.txt";
  o.intrinsics.width = 640;
  o.intrinsics.height = 480;
  o.intrinsics.cx = 319.5;
  o.intrinsics.cy = 239.5;
  try {
    RecordedCamera bad(o);
    FAIL() << "a calibration of another size was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("1226 x 370 px but the calibration is 640 x 480"));
  }
}

TEST(RecordedMono, AVideoFilePlaysItsFramesByTime) {
  TempDir dir("video");
  const std::string path = dir.path() + "/levels.avi";
  WriteLevelsVideo(path, 8, 10.0);
  RecordedCamera::Options o;
  o.name = "gimbal";
  o.path = path;
  o.intrinsics = SmallIntrinsics();
  o.start_utime = kStart;
  RecordedCamera camera(o);
  EXPECT_EQ(camera.frames(), 8u);
  // Frame k is grey level 20 + 25 k; 0.35 s in is frame 3.
  EXPECT_NEAR(cv::mean(camera.Capture(kStart + 350'000).image)[0], 20 + 25 * 3, 3.0);
  EXPECT_NEAR(cv::mean(camera.Capture(kStart + 700'000).image)[0], 20 + 25 * 7, 3.0);
  EXPECT_TRUE(camera.Capture(kStart + 2'000'000).image.empty());
  EXPECT_THAT(camera.problem(), HasSubstr("recording ended (8 frames)"));
}

// GStreamer's test source as a live camera: OpenCV's VideoCapture through a pipeline, as a
// camera on a companion computer is opened (a v4l2src in place of videotestsrc).
std::string TestSource(const std::string& pattern, int buffers) {
  return "videotestsrc pattern=" + pattern + " num-buffers=" + std::to_string(buffers) +
         " ! video/x-raw,width=320,height=240,framerate=30/1 ! videoconvert ! video/x-raw,format=BGR ! appsink";
}

TEST(LiveCameraTest, AGstreamerSourceDeliversAndAStreamThatStopsIsNamed) {
  LiveCamera::Options o;
  o.name = "gimbal";
  o.source = TestSource("smpte", 45);
  o.intrinsics = SmallIntrinsics();
  o.rate_hz = 30;
  LiveCamera camera(o);
  const cv::Mat image = camera.Capture(0).image;
  ASSERT_EQ(image.size(), cv::Size(320, 240));
  EXPECT_EQ(camera.problem(), "");
  // 45 frames at 30 Hz: the stream ends after 1.5 s; the camera says so (and reopens it).
  std::string problem;
  for (int i = 0; i < 400 && problem.find("stopped delivering") == std::string::npos; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    problem = camera.problem();
  }
  EXPECT_THAT(problem, HasSubstr("the device stopped delivering frames"));
  EXPECT_TRUE(camera.Capture(0).image.empty());
  EXPECT_GE(camera.frames(), 30);
}

TEST(LiveCameraTest, AMissingDeviceABlankSensorAndAWrongSizeAreRefusedBeforeTheRun) {
  LiveCamera::Options o;
  o.name = "gimbal";
  o.intrinsics = SmallIntrinsics();
  o.source = "/dev/video-that-is-not-there";
  try {
    LiveCamera camera(o, 1.0);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("cannot open '/dev/video-that-is-not-there'"));
  }
  o.source = TestSource("black", 200);
  try {
    LiveCamera camera(o, 1.0);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("one grey level"));
  }
  o.source = TestSource("smpte", 200);
  o.intrinsics = KittiIntrinsics();
  try {
    LiveCamera camera(o, 1.0);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_THAT(e.what(), HasSubstr("a 320 x 240 px frame, the calibration is 1226 x 370"));
  }
}

}  // namespace
}  // namespace uav::runtime
