// The onboard runtime on the bench, apart from the simulator (this executable does not link it):
// real recorded frames through the vision workers and the link to a GCS on memq://; the
// odometry on a recording equal to uav-vo's; a target picked on recorded real video followed by
// the onboard tracker; a live camera that stops, shown in the sensing health.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "uav/gcs/gcs_link.hpp"
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/log_replay.hpp"
#include "uav/runtime/bench_flight.hpp"
#include "uav/runtime/event_log.hpp"
#include "uav/runtime/flight_log.hpp"
#include "uav/runtime/link_worker.hpp"
#include "uav/runtime/workers.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/program.hpp"
#include "uav/vision/kitti_odometry.hpp"
#include "uav/vision/stereo_vo.hpp"
#include "uav/wire/bus.hpp"
#include "unit/runtime_test_data.hpp"

namespace uav::runtime {
namespace {

using ::testing::HasSubstr;
namespace fs = std::filesystem;

constexpr int64_t kStart = 1'700'000'000'000'000;

ParameterSet Params() { return ParameterSet::LoadFile(ResourcePath("vehicles/x650.params"), VehicleParameterSchema()); }

// A bench with its link to a GCS in this process: the GCS polls after the link's tick, on the
// vehicle clock (one thread at a time on the shared bus).
struct BenchWithGcs {
  Bus bus{"memq://"};
  gcs::GcsModel model{"gcs", 1};
  gcs::GcsLink gcs_link{&bus, model, std::nullopt};
  MissionStore missions;
  BenchFlight bench;
  LinkWorker link;

  std::unique_ptr<LogWorker> dlg;

  // With `log_dir`: the flight log and the event log, as uav-onboard writes them.
  BenchWithGcs(const RigFile& rig, const std::string& log_dir = "", double speed = 0.0, double duration_s = 0.0)
      : missions(TempPathsDir(), {1.3, 103.8, 15}, {}),
        bench(Params(), rig, {{1.3, 103.8, 15}, kStart, speed, duration_s, log_dir}),
        link("UAV1", bus, LinkParams::FromParameters(Params(), AttitudeMode::kGyroCruise), bench.board(), missions,
             log_dir.empty() ? nullptr : std::make_unique<EventLog>(log_dir, kStart)) {
    if (!log_dir.empty()) {
      dlg = std::make_unique<LogWorker>(std::make_unique<FlightLog>(log_dir, kStart, AttitudeMode::kGyroCruise), bench.board());
      bench.scheduler().AddWorker("DLG", 3, BenchFlight::kPeriodUs, [this](int64_t t) { dlg->Tick(t); });
    }
    bench.scheduler().AddWorker("CMM", 3, BenchFlight::kPeriodUs, [this](int64_t t) { link.Tick(t); });
    bench.scheduler().AddWorker("GCS", 4, BenchFlight::kPeriodUs, [this](int64_t t) {
      gcs_link.Poll(0, t * 1e-6);
      model.Tick(t * 1e-6);
      if (each_period) each_period(t);
    });
  }
  static std::string TempPathsDir() {
    const std::string d = (fs::temp_directory_path() / "uav_bench_paths").string();
    fs::create_directories(d);
    return d;
  }
  std::function<void(int64_t)> each_period;
  const gcs::VehicleModel& vehicle() const { return model.vehicles().at("UAV1"); }
  bool Logged(const std::string& text) const {
    const auto& lines = model.log().lines();
    return std::any_of(lines.begin(), lines.end(), [&](const auto& l) { return l.text.find(text) != std::string::npos; });
  }
};

TEST(BenchFlightTest, RealKittiFramesReachTheGcsAsInAFlight) {
  TempDir dir("bench_kitti");
  const std::string seq = CopyKitti(dir.path(), 12);
  const auto rig = RigFile::Parse(R"({"cameras": {"front": {"type": "kitti", "path": ")" + seq +
                                      R"(", "mount": {"xyz_m": [0, 0, -1.65]}}},
                                      "workers": {"odometry": "front", "obstacles": "front", "wires": "front"}})",
                                  "", "kitti.rig.json", kStart);
  BenchWithGcs b(*rig);
  bool asked = false;
  b.each_period = [&](int64_t t) {
    if (!asked && t >= kStart + 300'000) asked = b.model.SubmitCommand("arm", t * 1e-6);
  };
  b.bench.Run();
  ASSERT_EQ(b.model.vehicles().count("UAV1"), 1u);
  const gcs::VehicleModel& v = b.vehicle();
  // The odometry's report, healthy, with the truth beside it.
  const auto& vo = v.reports.Get<VisualOdometryReport>().newest;
  ASSERT_TRUE(vo);
  EXPECT_TRUE(vo->healthy) << vo->reason;
  EXPECT_GT(vo->inliers, 50);
  // The state follows the recording's truth: about 1.1 m a frame north, 11 frames.
  ASSERT_TRUE(v.state);
  const auto truth = vision::ReadKittiPoses(seq + "/poses.txt");
  EXPECT_NEAR(v.state->p_N.x(), truth.back().translation().z(), 0.5);
  EXPECT_GT(v.state->p_N.x(), 10.0);
  // The left camera's video, the obstacle pair's report and the sensing health, as in a flight.
  EXPECT_GT(v.video.frames, 0);
  EXPECT_EQ(v.camera, "front");
  EXPECT_TRUE(v.reports.Get<SensingReport>().newest);
  // No arming on the bench: the pre-arm report says why and the command is refused saying so.
  const auto& prearm = v.reports.Get<PreArmReport>().newest;
  ASSERT_TRUE(prearm);
  EXPECT_THAT(prearm->Failing(), HasSubstr("bench mode: control is off"));
  EXPECT_TRUE(asked);
  EXPECT_TRUE(b.Logged("bench mode: control is off")) << "the arm command's refusal";
  EXPECT_FALSE(v.armed);
}

// uav-vo's loop, as its tool runs it: every pair of the folder through StereoVo.
std::vector<Eigen::Isometry3d> UavVoPoses(const std::string& dir) {
  const vision::KittiSequence seq = vision::ReadKittiSequence(dir);
  vision::StereoVo vo(seq.geometry, vision::VoParams());
  std::vector<Eigen::Isometry3d> poses;
  for (std::size_t i = 0; i < seq.left.size(); ++i) {
    vision::RectifiedPair pair;
    pair.left = cv::imread(seq.left[i], cv::IMREAD_GRAYSCALE);
    pair.right = cv::imread(seq.right[i], cv::IMREAD_GRAYSCALE);
    pair.left_utime = pair.right_utime = static_cast<int64_t>(seq.times_s[i] * 1e6);
    poses.push_back(vo.Process(pair).T_WC);
  }
  return poses;
}

TEST(BenchFlightTest, TheOdometryWorkerOnARecordingGivesUavVosTrajectory) {
  TempDir dir("bench_vo");
  const auto rig = RigFile::Parse(R"({"cameras": {"front": {"type": "kitti", "path": ")" + KittiDir() +
                                      R"("}}, "workers": {"odometry": "front"}})",
                                  "", "kitti.rig.json", kStart);
  {
    BenchWithGcs b(*rig, dir.path());
    b.bench.Run();
  }
  const std::string poses_path = dir.path() + "/vo_" + std::to_string(kStart) + ".txt";
  ASSERT_TRUE(fs::exists(poses_path));
  const std::vector<Eigen::Isometry3d> worker = vision::ReadKittiPoses(poses_path);
  const std::vector<Eigen::Isometry3d> tool = UavVoPoses(KittiDir());
  ASSERT_EQ(worker.size(), 51u);
  ASSERT_EQ(tool.size(), 51u);
  const auto truth = vision::ReadKittiPoses(KittiDir() + "/poses.txt");
  const double e_worker = vision::EvaluateKittiOdometry(truth, worker, {10, 20, 30, 40, 50}).translation_pct;
  const double e_tool = vision::EvaluateKittiOdometry(truth, tool, {10, 20, 30, 40, 50}).translation_pct;
  EXPECT_NEAR(e_worker, e_tool, 0.001 * e_tool) << "worker " << e_worker << " %, uav-vo " << e_tool << " %";
  EXPECT_LT(e_tool, 3.0);

  // The run is recorded: the flight log has a row each 20 ms, and the event log replays in the
  // GCS with the odometry's reports and the vehicle following the truth.
  std::ifstream csv(dir.path() + "/flight_" + std::to_string(kStart) + ".csv");
  int rows = 0;
  for (std::string line; std::getline(csv, line);) ++rows;
  EXPECT_NEAR(rows, 1 + 5.05 / 0.02, 2);
  std::unique_ptr<gcs::GcsModel> model;
  std::unique_ptr<gcs::GcsLink> replay_link;
  gcs::LogReplay replay(dir.path() + "/events_" + std::to_string(kStart) + ".lcmlog", [&]() -> gcs::GcsLink& {
    replay_link.reset();
    model = std::make_unique<gcs::GcsModel>("gcs", 1);
    model->SetReplay(true);
    replay_link = std::make_unique<gcs::GcsLink>(nullptr, *model, std::nullopt);
    return *replay_link;
  });
  EXPECT_TRUE(replay.damage().empty());
  replay.SetSpeed(10.0);
  while (!replay.finished()) replay.Advance(0.1);
  const gcs::VehicleModel& v = model->vehicles().at("UAV1");
  ASSERT_TRUE(v.reports.Get<VisualOdometryReport>().newest);
  ASSERT_TRUE(v.state);
  EXPECT_NEAR(v.state->p_N.x(), truth.back().translation().z(), 1.0);
}

// A camera and IMU rig (EuRoC's layout, made of the real KITTI frames with the IMU their truth
// implies): the bench takes its attitude from the IMU (levelled by gravity, the gyro integrated)
// and its position from the odometry, which the IMU's attitude aids as in flight.
TEST(BenchFlightTest, WithARecordedImuTheAttitudeIsTheImusAndThePositionTheOdometrys) {
  TempDir dir("bench_imu");
  MakeEuroc(dir.path(), 51, 1226, 370, /*imu=*/true);
  const auto rig = RigFile::Parse(R"({"cameras": {"front": {"type": "euroc", "path": ")" + dir.path() +
                                      R"("}}, "workers": {"odometry": "front"}, "pose": "imu"})",
                                  "", "euroc.rig.json", kStart);
  ASSERT_EQ(rig->pose_source(), RigFile::PoseSource::kImuOdometry);
  EXPECT_THAT(rig->Describe(), HasSubstr("IMU (1000 samples)"));
  BenchWithGcs b(*rig);
  double worst_attitude_deg = 0;
  int compared = 0;
  b.each_period = [&](int64_t t) {
    const BlackboardData d = b.bench.board().Snapshot();
    if (d.estimate.utime == 0) return;  // levelling
    const double err = Eigen::Quaterniond(rig->TruthAt(t).linear()).angularDistance(d.estimate.q_NB) * 180 / M_PI;
    worst_attitude_deg = std::max(worst_attitude_deg, err);
    ++compared;
  };
  b.bench.Run();
  EXPECT_GT(compared, 200);  // 5 s at 50 Hz, less the 0.5 s of levelling
  EXPECT_LT(worst_attitude_deg, 1.0) << "the IMU's attitude against the truth";
  const gcs::VehicleModel& v = b.vehicle();
  ASSERT_TRUE(v.state);
  const auto& vo = v.reports.Get<VisualOdometryReport>().newest;
  ASSERT_TRUE(vo);
  EXPECT_TRUE(vo->healthy) << vo->reason;
  // The odometry's position at the end of the 60 m drive: within 2 % of the distance.
  const Eigen::Vector3d truth = rig->TruthAt(kStart + 5'000'000).translation();
  std::printf("IMU attitude worst %.2f deg; the odometry's end %.2f m from the truth's after %.1f m\n", worst_attitude_deg,
              (v.state->p_N - truth).norm(), truth.norm());
  EXPECT_LT((v.state->p_N - truth).norm(), 0.02 * truth.norm()) << v.state->p_N.transpose() << " vs " << truth.transpose();
}

TEST(BenchFlightTest, ATargetPickedOnRecordedRealVideoIsTrackedOnboard) {
  // OTB's "jogging" as a recorded gimbal camera: the operator drags the first runner's box.
  TempDir dir("bench_track");
  const std::string img = std::string(UAV_SHARED_DATA) + "/tracking_real/jogging/img";
  std::ofstream(dir.path() + "/otb.camera") << "sensor_width_mm 4.8\nsensor_height_mm 3.93\nfocal_length_mm 4\n"
                                            << "image_width_px 352\nimage_height_px 288\n";
  const auto rig = RigFile::Parse(R"({"cameras": {"gimbal": {"type": "photos", "path": ")" + img +
                                      R"(", "calibration": "otb.camera", "rate_hz": 10, "mount": {"pitch_deg": -20}}},
                                      "workers": {"tracking": "gimbal"}})",
                                  dir.path(), "otb.rig.json", kStart);
  EXPECT_EQ(rig->pose_source(), RigFile::PoseSource::kFixed);
  BenchWithGcs b(*rig, "", 0.0, 6.0);
  std::vector<std::array<double, 4>> truth;  // x y w h per frame, pixels
  {
    std::ifstream in(std::string(UAV_SHARED_DATA) + "/tracking_real/jogging/groundtruth_rect.1.txt");
    std::string line;
    while (std::getline(in, line)) {
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream l(line);
      std::array<double, 4> r{};
      l >> r[0] >> r[1] >> r[2] >> r[3];
      truth.push_back(r);
    }
  }
  bool sent = false;
  std::vector<std::pair<int, TrackStatus>> seen;  // frame index, status
  b.each_period = [&](int64_t t) {
    const gcs::VehicleModel* v = b.model.selected();
    if (!v) return;
    if (!sent && v->video.frames > 0) {
      // The box on the frame the GCS shows now, in the image's fractions.
      const int k = static_cast<int>(std::llround((v->video.utime - kStart) / 100'000.0));
      TrackTarget target;
      target.camera = v->camera;
      target.frame_utime = v->video.utime;
      const auto& r = truth[static_cast<std::size_t>(k)];
      target.x = r[0] / 352, target.y = r[1] / 288, target.width = r[2] / 352, target.height = r[3] / 288;
      target.corners = {{{target.x, target.y},
                         {target.x + target.width, target.y},
                         {target.x + target.width, target.y + target.height},
                         {target.x, target.y + target.height}}};
      sent = b.model.SelectTarget(target, t * 1e-6);
    }
    if (v->track && v->track->state == TrackStatus::kTracking)
      seen.emplace_back(static_cast<int>(std::llround((v->track->utime - kStart) / 100'000.0)), *v->track);
  };
  b.bench.Run();
  ASSERT_TRUE(sent);
  ASSERT_GT(seen.size(), 20u) << "the tracker never reported tracking";
  // Where the tracker has the runner, against OTB's truth: the centre within half the box's width.
  int near = 0;
  for (const auto& [k, s] : seen) {
    const auto& r = truth[static_cast<std::size_t>(k)];
    const double cx = (r[0] + r[2] / 2) / 352, cy = (r[1] + r[3] / 2) / 288;
    near += std::abs(s.center_x - cx) < 0.5 * r[2] / 352 && std::abs(s.center_y - cy) < 0.5 * r[3] / 288;
  }
  EXPECT_GT(near, static_cast<int>(0.8 * seen.size())) << near << " of " << seen.size();
}

TEST(BenchFlightTest, ALiveCameraThatVanishesShowsInTheSensingHealthAndNothingCrashes) {
  // A live source (read through VideoCapture as a device is) that ends and cannot be opened
  // again: a camera unplugged mid-run.
  TempDir dir("bench_live");
  std::ofstream(dir.path() + "/small.camera") << "sensor_width_mm 4.8\nsensor_height_mm 3.6\nfocal_length_mm 4\n"
                                              << "image_width_px 320\nimage_height_px 240\n";
  WriteLevelsVideo(dir.path() + "/device.avi", 30, 10.0);
  const auto rig = RigFile::Parse(R"({"cameras": {"gimbal": {"type": "live", "calibration": "small.camera", "rate_hz": 10,
                                                             "source": "device.avi"}},
                                      "workers": {"tracking": "gimbal"}})",
                                  dir.path(), "live.rig.json", kStart);
  EXPECT_EQ(rig->end_utime(), -1);  // live: no end of its own
  fs::remove(dir.path() + "/device.avi");
  BenchWithGcs b(*rig, "", 1.0, 3.0);
  b.bench.Run();
  const gcs::VehicleModel& v = b.vehicle();
  const auto& sensing = v.reports.Get<SensingReport>().newest;
  ASSERT_TRUE(sensing);
  ASSERT_EQ(sensing->workers.size(), 1u);
  EXPECT_FALSE(sensing->workers[0].healthy);
  EXPECT_THAT(sensing->workers[0].reason, HasSubstr("camera gimbal: "));
  EXPECT_TRUE(b.Logged("sensing: TRK camera gimbal: ")) << "the operator is told";
}

}  // namespace
}  // namespace uav::runtime
