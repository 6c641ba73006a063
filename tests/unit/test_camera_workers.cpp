// The onboard camera threads (issue 4 item 6) on the simulated clock: the downward camera's
// preview rate is independent of its frame and capture rates, and the stereo worker turns
// rendered pairs into the obstacle range the GCS and the log receive.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <opencv2/core/utility.hpp>

#include "uav/sim/sim_cameras.hpp"
#include "uav/runtime/active_stereo_worker.hpp"
#include "uav/runtime/camera_worker.hpp"
#include "uav/runtime/stereo_worker.hpp"
#include "uav/runtime/track_worker.hpp"
#include "uav/world/renderer.hpp"

namespace uav::runtime {
namespace {

#if defined(__SANITIZE_THREAD__)
// Under ThreadSanitizer (tests/sanitizers/sanitize.sh tsan): OpenCV's parallel_for_ runs on TBB
// threads that TSan cannot see joined (neither library is instrumented), so every loop in the
// renderer and the vision code would be reported. Run them on the calling thread: the workers'
// own threads, the blackboard and the scheduler are what is checked.
const int kSerialOpenCv = (cv::setNumThreads(0), 0);
#endif

world::Scene LoadScene(const std::string& name) {
  return world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/" + name + ".scene.json");
}

Eigen::Isometry3d Pose(double n, double e, double d) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(n, e, d);
  return T;
}

int CountLines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  for (std::string line; std::getline(in, line);) ++n;
  return n;
}

TEST(CameraWorker, PreviewRateIsIndependentOfFrameAndCaptureRates) {
  const world::Scene scene = LoadScene("survey_village");
  world::CameraSetup camera = *scene.downward_camera();
  camera.rate_hz = 10;
  camera.preview_rate_hz = 4;  // does not divide 10 Hz: the schedule keeps the average
  const std::string dir = (std::filesystem::temp_directory_path() / "uav_test_camera_worker").string();
  std::filesystem::remove_all(dir);
  Blackboard board;
  board.Update([](BlackboardData& d) { d.capture_interval_s = 0.2; });
  CameraWorker::Options options;
  options.capture_dir = dir;
  sim::SimCamera sim_camera(scene, camera, [](int64_t) { return Pose(0, 0, -20); });
  CameraWorker worker(sim_camera, board, options);
  int previews_taken = 0;
  for (int i = 0; i < 50; ++i) {  // 5 s at 10 Hz
    worker.Tick(1'000'000 + i * 100'000);
    previews_taken += static_cast<int>(board.previews.TakeAll().size());
  }
  EXPECT_EQ(worker.previews(), 20);  // 4 Hz for 5 s
  EXPECT_EQ(previews_taken, 20);
  EXPECT_EQ(worker.captures(), 25);  // every 0.2 s
  EXPECT_EQ(CountLines(dir + "/captures.csv"), 26);  // header + one row per image
  EXPECT_TRUE(std::filesystem::exists(dir + "/IMG_000024.jpg"));
  std::filesystem::remove_all(dir);
}

TEST(CameraWorker, ZeroPreviewRateSendsNoPreview) {
  const world::Scene scene = LoadScene("survey_village");
  world::CameraSetup camera = *scene.downward_camera();
  camera.preview_rate_hz = 0;
  Blackboard board;
  sim::SimCamera sim_camera(scene, camera, [](int64_t) { return Pose(0, 0, -20); });
  CameraWorker worker(sim_camera, board, CameraWorker::Options());
  for (int i = 0; i < 5; ++i) worker.Tick(1'000'000 + i * 200'000);
  EXPECT_EQ(worker.previews(), 0);
  EXPECT_TRUE(board.previews.TakeAll().empty());
}

TEST(StereoWorker, PostsTheObstacleRangeAhead) {
  const world::Scene scene = LoadScene("forest");
  Blackboard board;
  Eigen::Isometry3d T_NB = Pose(4, 3, -1.5);  // the pole at (8, 3) 4 m ahead
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return T_NB; });
  StereoWorker worker(sim_pair, board, StereoWorkerParams());
  worker.Tick(1'000'000);
  EXPECT_NEAR(board.Snapshot().obstacle_range_m, 3.7, 0.15);  // truth 3.70 m (test_vision)
  T_NB = Pose(-58, 55, -1.5);  // the corner of the forest, looking out over open ground
  T_NB.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  worker.Tick(1'066'667);
  EXPECT_LT(board.Snapshot().obstacle_range_m, 0.0);
  EXPECT_EQ(worker.frames(), 2);
}

// The downward active rig over the indoor scene's bare floor at 1.2 m: the height goes to the
// report and to the INS; over the table, whose top hides the floor from every dot, neither.
// Workers sharing a pair at one rate ask for the same exposure: it is rendered once, and each gets
// its own copy. The projector's mode matters only on a rig that has one.
TEST(SimStereoCamera, OneExposureIsRenderedOnceAndEachWorkerGetsItsOwnCopy) {
  const world::Scene forest = LoadScene("forest");
  sim::SimStereoCamera plain(forest, *forest.stereo_camera(), [](int64_t) { return Pose(0, 0, -1.5); });
  hal::StereoImages dark = plain.Capture(1'000'000, hal::Emitter::kOff);
  const hal::StereoImages lit = plain.Capture(1'000'000, hal::Emitter::kOn);
  EXPECT_EQ(plain.renders(), 1) << "no projector: one exposure";
  EXPECT_EQ(cv::norm(dark.left, lit.left, cv::NORM_INF), 0.0);
  EXPECT_NE(dark.left.data, lit.left.data) << "each its own copy";
  dark.left.setTo(0);
  EXPECT_GT(cv::norm(plain.Capture(1'000'000, hal::Emitter::kOff).left, cv::NORM_L1), 0.0)
      << "a worker's change does not reach the next";
  EXPECT_GT(cv::norm(plain.Capture(1'100'000, hal::Emitter::kOff).left, lit.left, cv::NORM_L1), 0.0)
      << "another exposure time: rendered again";
  EXPECT_EQ(plain.renders(), 2);
  const world::Scene room = LoadScene("indoor_active");
  sim::SimStereoCamera projector(room, *room.stereo_camera(), [](int64_t) { return Pose(0.5, -1.5, -1.2); });
  const cv::Mat off = projector.Capture(1'000'000, hal::Emitter::kOff).left;
  const cv::Mat on = projector.Capture(1'000'000, hal::Emitter::kOn).left;
  EXPECT_GT(cv::norm(on, off, cv::NORM_L1), 0.0) << "the dots are on one exposure and not the other";
  EXPECT_EQ(projector.renders(), 2);
}

TEST(ActiveStereoWorker, PostsTheHeightForTheLinkAndTheInsAndNoneOverATable) {
  const world::Scene scene = LoadScene("indoor_active");
  Blackboard board;
  Eigen::Isometry3d T_NB = Pose(0.5, -1.5, -1.2);
  board.Update([&](BlackboardData& d) { d.estimate.p_N = T_NB.translation(); });
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return T_NB; });
  ActiveStereoWorkerParams params;
  params.enabled = true;
  ActiveStereoWorker worker(sim_pair, board, params);
  worker.Tick(1'000'000);
  const auto report = board.reports.Take<ActiveStereoReport>();
  ASSERT_TRUE(report);
  ASSERT_TRUE(report->healthy) << report->reason;
  EXPECT_NEAR(report->height_m, 1.2, 0.01);
  EXPECT_GE(report->dots.size(), 50u);
  EXPECT_EQ(report->camera, "stereo_left");
  ASSERT_TRUE(board.Snapshot().vision_height);
  EXPECT_EQ(board.Snapshot().vision_height->utime, 1'000'000);
  EXPECT_NEAR(board.Snapshot().vision_height->sigma_m, 0.02, 1e-9);  // at least asv_height_noise
  // The rig over the middle of the first table (2.5, 0.2) at 1.5 m, 0.75 m above its top.
  T_NB = Pose(2.35, 0.2, -1.5);  // the rig sits 0.15 m ahead of the body origin
  board.Update([&](BlackboardData& d) { d.estimate.p_N = T_NB.translation(); });
  worker.Tick(1'066'667);
  const auto hidden = board.reports.Take<ActiveStereoReport>();
  ASSERT_TRUE(hidden);
  EXPECT_FALSE(hidden->healthy);
  EXPECT_NE(hidden->reason.find("the floor is hidden"), std::string::npos) << hidden->reason;
  EXPECT_EQ(board.Snapshot().vision_height->utime, 1'000'000);  // nothing new for the INS
  EXPECT_EQ(worker.unhealthy(), 1);
}

// The power-line scene's rig is rolled 45 degrees (level wires are diagonal to its baseline).
// Facing the line from 15 m with the estimate equal to the truth, the wires come out in NED
// where the scene strung them (20 m north, 8.5-10 m up), and the nearest one in the state.
TEST(StereoWorker, ReportsPowerLinesInNedAndTheNearestWire) {
  const world::Scene scene = LoadScene("power_lines");
  Blackboard board;
  Eigen::Isometry3d T_NB = Pose(5, 0, -7);
  board.Update([&](BlackboardData& d) {
    d.estimate.p_N = T_NB.translation();
    d.estimate.euler = {0.0, 0.0, 0.0};
  });
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return T_NB; });
  StereoWorker worker(sim_pair, board, StereoWorkerParams());
  // The reported nearest wire is the median of three pairs: one pair alone does not make it.
  worker.Tick(1'000'000);
  EXPECT_LT(board.Snapshot().nearest_wire_m, 0.0);
  worker.Tick(1'066'667);
  const auto report = board.reports.Take<PowerLines>();
  ASSERT_TRUE(report);
  EXPECT_EQ(report->camera, "stereo_left");
  ASSERT_FALSE(report->wires.empty());
  // Ranged wires lie on the line: at its north (+-1.2 m wire spacing) and above the vehicle
  // (poles 10 m, 1.5 m sag). Today the boundary between two fields near the horizon, parallel to
  // the wires and different on its two sides only in shade, is ranged too (15-60 m, a disparity of
  // 1-4 px on a line with no texture along it): at most three such are held (two before the
  // detector's second search for faint wires, which finds one more of these boundaries).
  int on_line = 0, off_line = 0;
  for (const PowerLine& w : report->wires) {
    for (const Eigen::Vector2d& uv : w.image_uv) {
      EXPECT_GE(uv.x(), -0.01);
      EXPECT_LE(uv.x(), 1.01);
    }
    if (w.p_N.empty()) continue;
    const bool on = std::all_of(w.p_N.begin(), w.p_N.end(), [](const Eigen::Vector3d& p) {
      return std::abs(p.x() - 20.0) < 2.5 && p.z() < -7.0 && p.z() > -11.0;
    });
    ++(on ? on_line : off_line);
  }
  EXPECT_GT(on_line, 0);
  EXPECT_LE(off_line, 3);
  EXPECT_NEAR(board.Snapshot().nearest_wire_m, 13.8, 2.0);  // nearest visible cable point 13.77 m
  EXPECT_DOUBLE_EQ(board.Snapshot().nearest_wire_m, report->nearest_m);
  // Turned away from the line: one pair without wires does not clear it, two do.
  T_NB.linear() = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  worker.Tick(1'133'333);
  EXPECT_NEAR(board.Snapshot().nearest_wire_m, 13.8, 2.0);
  worker.Tick(1'200'000);
  EXPECT_LT(board.Snapshot().nearest_wire_m, 0.0);
}

TEST(StereoWorker, PowerLinesOffSendsNone) {
  const world::Scene scene = LoadScene("power_lines");
  Blackboard board;
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return Pose(5, 0, -7); });
  StereoWorkerParams params;
  params.power_lines = false;
  StereoWorker worker(sim_pair, board, params);
  worker.Tick(1'000'000);
  EXPECT_FALSE(board.reports.Take<PowerLines>());
  EXPECT_LT(board.Snapshot().nearest_wire_m, 0.0);
}

// A second pair for wires alone (pwl_rig): it reports the wires and adds them to the map, but no
// obstacles, no points and no look ahead: with the obstacles' pair gone, its wires must not keep
// the avoidance's perception fresh (the vehicle would fly on, blind to all but wires).
TEST(StereoWorker, AWirePairReportsAndMapsWiresAloneAndKeepsNoPerceptionFresh) {
  const world::Scene scene = LoadScene("power_lines");
  Blackboard board;
  const Eigen::Isometry3d T_NB = Pose(15, 0, -8);
  board.Update([&](BlackboardData& d) {
    d.estimate.p_N = T_NB.translation();
    d.estimate.p_O = T_NB.translation();  // the odometry frame (the map's) at N's origin
    d.estimate.euler = {0.0, 0.0, 0.0};
  });
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return T_NB; });
  StereoWorkerParams params;
  params.detect_obstacles = false;
  params.to_map = true;
  StereoWorker worker(sim_pair, board, params);
  for (int i = 0; i < 3; ++i) worker.Tick(1'000'000 + i * 66'667);
  EXPECT_FALSE(board.reports.Take<Obstacles>());
  EXPECT_FALSE(board.reports.Take<PointCloud>());
  const auto wires = board.reports.Take<PowerLines>();
  ASSERT_TRUE(wires);
  EXPECT_FALSE(wires->wires.empty());
  // The nearest of the line's three cables, 3.8 m north and 0.5 m up: 3.7 m from the camera.
  EXPECT_NEAR(board.Snapshot().nearest_wire_m, 3.7, 0.5);
  const std::vector<avoid::PerceptionUpdate> updates = board.perception.TakeAll();
  ASSERT_EQ(updates.size(), 3u);
  int mapped = 0;
  for (const avoid::PerceptionUpdate& u : updates) {
    EXPECT_FALSE(u.scan.has_value());
    EXPECT_TRUE(u.cylinders.empty());
    EXPECT_FALSE(u.watches_ahead);
    for (const avoid::MapWire& w : u.wires) {
      ++mapped;
      for (const Eigen::Vector3d& p_N : w.p_N) {
        EXPECT_NEAR(p_N.x(), 20.0, 1.7);  // the cables at 18.8, 20 and 21.2 m north
        EXPECT_LT(p_N.z(), -7.5);          // 8.5-10 m up
      }
    }
  }
  EXPECT_GT(mapped, 0);
  StereoWorkerParams neither = params;
  neither.power_lines = false;
  EXPECT_THROW(StereoWorker(sim_pair, board, neither), std::invalid_argument);
}

// Obstacles (thesis 3.5) in NED with the estimate equal to the truth: at (3, -1.5), 1.5 m up,
// facing north, the forest's person (6, -1.5), radius 0.2 m, is straight ahead, its surface
// 2.8 m away; a decimated cloud goes out with the first pair.
TEST(StereoWorker, ReportsObstacleCylindersInNed) {
  const world::Scene scene = LoadScene("forest");
  Blackboard board;
  const Eigen::Isometry3d T_NB = Pose(3, -1.5, -1.5);
  board.Update([&](BlackboardData& d) {
    d.estimate.p_N = T_NB.translation();
    d.estimate.euler = {0.0, 0.0, 0.0};
  });
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return T_NB; });
  StereoWorker worker(sim_pair, board, StereoWorkerParams());
  worker.Tick(1'000'000);
  const auto report = board.reports.Take<Obstacles>();
  ASSERT_TRUE(report);
  EXPECT_TRUE(report->healthy);
  EXPECT_EQ(report->camera, "stereo_left");
  ASSERT_FALSE(report->obstacles.empty());
  const Obstacle& nearest = report->obstacles.front();
  EXPECT_NEAR(nearest.p_NE.x(), 6.0, 0.15);
  EXPECT_NEAR(nearest.p_NE.y(), -1.5, 0.15);
  EXPECT_NEAR(nearest.range_m, 2.8, 0.2);
  EXPECT_GT(nearest.safety_radius_m, nearest.radius_m);
  EXPECT_GT(nearest.cov_NE(0, 0), 0.0);
  // Its box on the left image: around the centre column (the left camera sits 6 cm left of
  // the body axis), from above the head to the ground.
  EXPECT_LT(nearest.image_box[0], 0.5);
  EXPECT_GT(nearest.image_box[2], 0.5);
  EXPECT_LT(nearest.image_box[1], 0.5);
  EXPECT_GT(nearest.image_box[3], 0.6);
  EXPECT_EQ(board.Snapshot().obstacle_count, static_cast<int>(report->obstacles.size()));
  EXPECT_DOUBLE_EQ(board.Snapshot().nearest_obstacle_m, report->nearest_m);
  const auto cloud = board.reports.Take<PointCloud>();
  ASSERT_TRUE(cloud);
  EXPECT_GT(cloud->p_N.size(), 100u);
  EXPECT_TRUE(cloud->origin_N.isApprox(T_NB.translation()));
}

// A camera that goes blank: the channel reports unhealthy with the reason, no stale obstacles,
// and the thread keeps running.
// What a pair adds to the map: a thin cylinder whole (grown by its axis's standard deviation),
// not a wide one (a crown would fill the space under it; its points describe its face); the
// points as rays from the camera, trusted to the range gate.
TEST(StereoWorker, MapUpdateDrawsThinCylindersCrownsOnTrunksAndThePointsAsRays) {
  vision::StereoObstacles found;
  found.gate_depth_m = 12.0;
  found.ground_z_m = 0.0;
  vision::ObstacleCylinder pole;
  pole.centre_W = {8, 1, -3};
  pole.radius_m = 0.3, pole.top_m = -6, pole.bottom_m = 0;
  pole.cov_xy = Eigen::Matrix2d::Identity() * 0.01;  // sigma 0.1 m
  vision::ObstacleCylinder crown = pole;
  crown.centre_W = {10, -4, -7};
  crown.radius_m = 1.8, crown.top_m = -9, crown.bottom_m = 0;
  // A crown split off the trunk under it: it stands on the trunk, from its top to its bottom.
  vision::ObstacleCylinder crown_on_trunk = crown;
  crown_on_trunk.centre_W = {14, 3, -7};
  crown_on_trunk.top_m = -9, crown_on_trunk.bottom_m = -5;
  crown_on_trunk.on_trunk = true;
  found.obstacles = {pole, crown, crown_on_trunk};
  found.points_L = {{0.f, 0.f, 5.f}};
  Eigen::Isometry3d T_NL = Eigen::Isometry3d::Identity();
  T_NL.translation() = Eigen::Vector3d(1, 2, -4);
  const avoid::PerceptionUpdate u = StereoMapUpdate(42, found, {}, T_NL);
  EXPECT_EQ(u.utime, 42);
  ASSERT_TRUE(u.scan.has_value());
  EXPECT_TRUE(u.scan->origin_N.isApprox(Eigen::Vector3d(1, 2, -4)));
  ASSERT_EQ(u.scan->p_N.size(), 1u);
  EXPECT_TRUE(u.scan->p_N[0].isApprox(Eigen::Vector3f(1, 2, 1)));
  EXPECT_DOUBLE_EQ(u.scan->max_range_m, 12.0);
  ASSERT_EQ(u.cylinders.size(), 2u) << "the crown standing to the ground is left to its points";
  EXPECT_TRUE(u.cylinders[0].p_NE.isApprox(Eigen::Vector2d(8, 1)));
  EXPECT_NEAR(u.cylinders[0].radius_m, 0.4, 1e-9);
  EXPECT_DOUBLE_EQ(u.cylinders[0].top_down_m, -6.0);
  EXPECT_DOUBLE_EQ(u.cylinders[0].bottom_down_m, 0.0);
  EXPECT_TRUE(u.cylinders[1].p_NE.isApprox(Eigen::Vector2d(14, 3)));
  EXPECT_NEAR(u.cylinders[1].radius_m, 1.9, 1e-9);
  EXPECT_DOUBLE_EQ(u.cylinders[1].bottom_down_m, -5.0) << "the space under the crown stays free";
}

TEST(StereoWorker, BlankCameraReportsUnhealthyAndNoObstacles) {
  const world::Scene scene = LoadScene("forest");
  Blackboard board;
  sim::SimStereoCamera sim_pair(scene, *scene.stereo_camera(), [&](int64_t) { return Pose(3, 0, -1.5); });
  struct Failing : hal::StereoCamera {
    explicit Failing(hal::StereoCamera& c) : inner(c) {}
    const hal::CameraInfo& left() const override { return inner.left(); }
    const hal::CameraInfo& right() const override { return inner.right(); }
    hal::StereoImages Capture(int64_t utime, hal::Emitter emitter) override {
      hal::StereoImages images = inner.Capture(utime, emitter);
      if (blank) images.right = cv::Mat();
      return images;
    }
    hal::StereoCamera& inner;
    bool blank = false;
  } camera(sim_pair);
  StereoWorker worker(camera, board, StereoWorkerParams());
  worker.Tick(1'000'000);
  ASSERT_GT(board.Snapshot().obstacle_count, 0);
  board.reports.Take<Obstacles>();
  camera.blank = true;
  worker.Tick(1'066'667);
  const auto report = board.reports.Take<Obstacles>();
  ASSERT_TRUE(report);
  EXPECT_FALSE(report->healthy);
  EXPECT_NE(report->reason.find("empty"), std::string::npos) << report->reason;
  EXPECT_TRUE(report->obstacles.empty());
  EXPECT_EQ(board.Snapshot().obstacle_count, 0);
  EXPECT_LT(board.Snapshot().nearest_obstacle_m, 0.0);
  EXPECT_LT(board.Snapshot().obstacle_range_m, 0.0);
  EXPECT_EQ(worker.unhealthy(), 1);
  camera.blank = false;
  worker.Tick(1'133'333);
  EXPECT_TRUE(board.reports.Take<Obstacles>()->healthy);
  EXPECT_EQ(worker.frames(), 2);
}

// TRK: a target picked on an older frame is tracked from that frame on; the status goes out
// every frame with the box on the target's exact image position; the gimbal pitches to centre
// it; the target is placed on the ground where it truly is; refusals name why and cancel stops.
TEST(TrackWorker, TracksThePickedTargetCentresItAndPlacesItOnTheGround) {
  const world::Scene scene = LoadScene("tracking");
  const world::CameraSetup cam = *scene.gimbal_camera();
  int tent = -1;
  for (const auto& o : scene.obstacles())
    if (o.kind == "tent") tent = o.id;
  ASSERT_GE(tent, 0);
  Blackboard board;
  const Eigen::Isometry3d T_NB = Pose(0, 0, -6);
  board.Update([&](BlackboardData& d) {
    d.estimate.p_N = T_NB.translation();
    d.estimate.q_NB = Eigen::Quaterniond::Identity();
  });
  sim::SimGimbalCamera camera(scene, cam, [&](int64_t) { return T_NB; }, -15 * M_PI / 180);
  TrackWorkerParams params;
  params.gimbal_pitch_rad = -15 * M_PI / 180;
  // CamShift, whose box shrinks from a loose selection to the coloured object (asserted below);
  // the default (auto) gives this loose box, 22 % tent, to CSRT, which keeps the box as drawn.
  params.tracker.kind = vision::TrackerKind::kCamShift;
  TrackWorker worker(camera, board, params);
  EXPECT_EQ(board.Snapshot().tracking_camera, "gimbal");
  const world::Renderer truth_renderer(scene, cam);
  auto truth_box = [&](int64_t utime) {
    return world::ObjectBox(truth_renderer.Render(hal::GimbalCameraPose(T_NB, cam.T_BC, camera.pitch_rad()), utime), tent);
  };
  // Frames at 10 Hz; the operator picks on the frame of 1.0 s, which reaches the vehicle at 1.3 s.
  const cv::Rect picked = truth_box(1'000'000);
  ASSERT_GT(picked.area(), 100);
  for (int64_t t = 500'000; t <= 1'300'000; t += 100'000) worker.Tick(t);
  EXPECT_TRUE(board.track_reports.TakeAll().empty());  // nothing until a target is set
  TrackTarget r;
  r.vehicle_id = "UAV1";
  r.target_seq = 7;
  r.frame_utime = 1'000'000;
  r.camera = "gimbal";
  // A loose selection, as an operator drags it: 5 % of the image around the tent on each side.
  const double pad = 0.05;
  r.x = picked.x / 640.0 - pad, r.y = picked.y / 480.0 - pad;
  r.width = picked.width / 640.0 + 2 * pad, r.height = picked.height / 480.0 + 2 * pad;
  board.track_requests.Push(r);
  const double pitch0 = camera.pitch_rad();
  std::vector<TrackStatus> reports;
  for (int64_t t = 1'400'000; t <= 3'400'000; t += 100'000) {
    worker.Tick(t);
    for (const TrackStatus& rep : board.track_reports.TakeAll()) reports.push_back(rep);
  }
  ASSERT_EQ(reports.size(), 21u);
  for (const TrackStatus& rep : reports) {
    EXPECT_EQ(rep.state, TrackStatus::State::kTracking);
    EXPECT_EQ(rep.target_seq, 7);
    EXPECT_GT(rep.confidence, 0.5);
  }
  // The last frame's box on the tent (the gimbal moved meanwhile: truth at the same pitch).
  const cv::Rect last = truth_box(3'400'000);
  EXPECT_NEAR(reports.back().center_x * 640, last.x + 0.5 * last.width, 3.0);
  EXPECT_NEAR(reports.back().center_y * 480, last.y + 0.5 * last.height, 3.0);
  // The box shrank from the loose selection to the tent.
  EXPECT_NEAR(reports.back().width * 640, last.width, 0.2 * last.width);
  EXPECT_NEAR(reports.back().height * 480, last.height, 0.2 * last.height);
  // The tent's middle (1.25 m up, 30 m ahead, 6 m below the camera) lies 9 deg below the
  // horizon, above the image centre at -15 deg: the gimbal tilted up to it.
  EXPECT_GT(camera.pitch_rad(), pitch0 + 4.0 * M_PI / 180);
  EXPECT_NEAR(camera.pitch_rad(), -std::atan2(4.75, 30.0), 1.5 * M_PI / 180);
  EXPECT_NEAR(reports.back().center_y, 0.5, 0.02);
  // On the ground: the box centre's ray meets d = 0 behind the tent's middle (it is 2.5 m tall),
  // straight ahead.
  const TrackedTarget target = board.Snapshot().target;
  EXPECT_TRUE(target.locked && target.on_ground);
  EXPECT_NEAR(target.p_N.y(), 0.0, 0.3);
  EXPECT_GT(target.p_N.x(), 28.5);
  EXPECT_LT(target.p_N.x(), 40.0);
  EXPECT_NEAR(target.bearing_rad, 0.0, 0.02);

  // Refusals: another camera, a frame no longer buffered, a tiny box. The target carries on.
  TrackTarget other = r;
  other.target_seq = 8;
  other.camera = "downward";
  TrackTarget old = r;
  old.target_seq = 9;
  old.frame_utime = 100'000;
  TrackTarget tiny = r;
  tiny.target_seq = 10;
  tiny.frame_utime = 3'400'000;
  tiny.width = 2.0 / 640;
  for (const TrackTarget& bad : {other, old, tiny}) board.track_requests.Push(bad);
  worker.Tick(3'500'000);
  reports = board.track_reports.TakeAll();
  ASSERT_EQ(reports.size(), 4u);
  EXPECT_EQ(reports[0].state, TrackStatus::State::kRejected);
  EXPECT_NE(reports[0].reason.find("camera 'downward'"), std::string::npos);
  EXPECT_NE(reports[1].reason.find("is not among the 10.0 s kept"), std::string::npos);
  EXPECT_NE(reports[2].reason.find("smaller than"), std::string::npos);
  EXPECT_EQ(reports[3].state, TrackStatus::State::kTracking);
  EXPECT_EQ(reports[3].target_seq, 7);

  TrackTarget cancel;
  cancel.method = TrackTarget::Method::kCancel;
  cancel.target_seq = 11;
  board.track_requests.Push(cancel);
  worker.Tick(3'600'000);
  reports = board.track_reports.TakeAll();
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].state, TrackStatus::State::kIdle);
  worker.Tick(3'700'000);
  EXPECT_TRUE(board.track_reports.TakeAll().empty());
  EXPECT_FALSE(board.Snapshot().target.locked);
}

}  // namespace
}  // namespace uav::runtime
