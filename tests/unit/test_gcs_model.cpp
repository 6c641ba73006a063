// The GCS model without any window or bus: link statistics, command sending and resending,
// vehicle isolation, telemetry history.
#include <fstream>

#include <filesystem>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "uav/gcs/gcs_model.hpp"
#include "unit/gcs_test_util.hpp"
#include "uav/gcs/signal_series.hpp"

namespace uav::gcs {
namespace {

// A hovering, armed vehicle (as its heartbeat says too).
VehicleState State(double t, double alt) { return StateOf(t, {{"alt", alt}, {"x", 1.0}, {"task", 2}, {"armed", 1}}); }

TEST(SignalSeries, KeepsTheNewestWithinCapacityInOrder) {
  SignalSeries s(4);
  for (int i = 0; i < 10; ++i) s.Push(i, 10 * i);
  ASSERT_EQ(s.size(), 4u);
  EXPECT_EQ(s.TimeAt(0), 6);
  EXPECT_EQ(s.LastValue(), 90);
  EXPECT_EQ(s.LowerBound(7.5), 2u);
  EXPECT_EQ(s.LowerBound(100), 4u);
  EXPECT_EQ(s.LowerBound(-1), 0u);
}

TEST(SignalSeries, DefaultHoldsThirtyMinutesAtFiftyHertz) {
  SignalSeries s;
  for (int i = 0; i < 30 * 60 * 50 + 10; ++i) s.Push(i * 0.02, i);
  EXPECT_EQ(s.size(), 90000u);
  EXPECT_NEAR(s.LastTime() - s.TimeAt(0), 30 * 60 - 0.02, 1e-6);
}

TEST(GcsModel, DiscoversVehiclesAndSelectsTheFirst) {
  GcsModel m("gcs", 100);
  EXPECT_EQ(m.selected(), nullptr);
  m.OnHeartbeat("UAV2", 1, Hb(0, false), 10.0);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 10.1);
  EXPECT_EQ(m.selected_id(), "UAV2");
  EXPECT_EQ(m.vehicles().size(), 2u);
  m.SelectVehicle("NOPE");
  EXPECT_EQ(m.selected_id(), "UAV2");
  m.SelectVehicle("UAV1");
  EXPECT_EQ(m.selected_id(), "UAV1");
}

TEST(GcsModel, LinkQualityFromHeartbeatsRatesAndSequenceGaps) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(2, true), 0.0);
  for (int i = 1; i <= 50; ++i)
    if (i % 10 != 0) m.OnState("UAV1", i, State(i * 0.02, 5), 1.0 + i * 0.02);  // 5 lost
  const VehicleModel& v = m.vehicles().at("UAV1");
  EXPECT_EQ(v.sequence_gaps, 4);  // 10,20,30,40 missing (50 is the newest, also missing: not yet seen)
  EXPECT_NEAR(v.MessageRate(2.0), 45, 1);
  EXPECT_TRUE(v.LinkUp(2.9));
  EXPECT_FALSE(v.LinkUp(3.1));
  EXPECT_EQ(v.task, Task::kHover);
  EXPECT_TRUE(v.armed);
}

TEST(GcsModel, InvalidCommandIsNotSentAndSaysWhy) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  EXPECT_FALSE(m.SubmitCommand("takeoff nan", 1.0));
  EXPECT_NE(m.commands().error().find("not a finite number"), std::string::npos);
  EXPECT_TRUE(m.commands().TakeOutgoing().empty());
  EXPECT_TRUE(m.commands().sent().empty());
}

// The map draws the goto a vehicle flies for this GCS: from its acceptance until it ends or
// another command supersedes it.
TEST(GcsModel, ActiveGotoLastsFromAcceptanceToItsEnd) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  ASSERT_TRUE(m.SubmitCommand("goto 12 -3 8", 0.0));
  EXPECT_FALSE(m.commands().ActiveGoto("UAV1"));  // not yet accepted
  m.OnAck("UAV1", {"gcs", 100, "goto", CommandResult::kAccepted, 0, ""}, 0.2);
  ASSERT_TRUE(m.commands().ActiveGoto("UAV1"));
  EXPECT_EQ(*m.commands().ActiveGoto("UAV1"), Eigen::Vector3d(12, -3, -8));
  EXPECT_FALSE(m.commands().ActiveGoto("UAV2"));
  m.OnAck("UAV1", {"gcs", 100, "goto", CommandResult::kInProgress, 40, ""}, 1.0);
  EXPECT_TRUE(m.commands().ActiveGoto("UAV1"));
  ASSERT_TRUE(m.SubmitCommand("gps 1", 1.1));  // not a move: the goto goes on
  m.OnAck("UAV1", {"gcs", 101, "gps", CommandResult::kCompleted, 100, ""}, 1.2);
  EXPECT_TRUE(m.commands().ActiveGoto("UAV1"));
  m.OnAck("UAV1", {"gcs", 100, "goto", CommandResult::kReplaced, 60, "replaced by hover"}, 2.0);
  EXPECT_FALSE(m.commands().ActiveGoto("UAV1"));
  ASSERT_TRUE(m.SubmitCommand("goto 1 2 3", 3.0));
  m.OnAck("UAV1", {"gcs", 102, "goto", CommandResult::kAccepted, 0, ""}, 3.1);
  EXPECT_EQ(*m.commands().ActiveGoto("UAV1"), Eigen::Vector3d(1, 2, -3));
  m.OnAck("UAV1", {"gcs", 102, "goto", CommandResult::kCompleted, 100, ""}, 5.0);
  EXPECT_FALSE(m.commands().ActiveGoto("UAV1"));
}

// What the status bar shows at a glance, from the state: ground speed over N (not the body's),
// heading in [0, 360) degrees and the horizontal distance to home.
TEST(VehicleStateGlance, GroundSpeedHeadingAndHomeDistance) {
  VehicleState s;
  s.euler.psi = -M_PI / 2;        // facing west
  s.v_B = {3, 0, 1};              // 3 m/s forward, 1 m/s down
  s.p_N = {30, -40, -10};
  EXPECT_NEAR(s.ground_speed(), 3.0, 1e-12);
  EXPECT_NEAR(s.heading(), 1.5 * M_PI, 1e-12);
  EXPECT_NEAR(s.home_distance(), 50.0, 1e-12);
  const std::optional<SignalRef> gs = FindSignal("gspeed"), hdg = FindSignal("heading");
  ASSERT_TRUE(gs && hdg && FindSignal("home_dist"));
  EXPECT_EQ(FormatForDisplay(Def(*hdg), s.heading()), "270.0 deg");
}

TEST(GcsModel, CommandNeedsASelectedVehicle) {
  GcsModel m("gcs", 100);
  EXPECT_FALSE(m.SubmitCommand("arm", 1.0));
  EXPECT_EQ(m.commands().error(), "no vehicle selected");
}

TEST(GcsModel, ResendsWithTheSameSequenceThenGivesUp) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  ASSERT_TRUE(m.SubmitCommand("arm", 0.0));
  auto out = m.commands().TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].command_seq, 100);
  EXPECT_EQ(out[0].vehicle_id, "UAV1");
  std::vector<int64_t> seqs;
  for (double t = 0.1; t < 10.0; t += 0.1) {
    m.Tick(t);
    for (const auto& o : m.commands().TakeOutgoing()) seqs.push_back(o.command_seq);
  }
  EXPECT_EQ(seqs, std::vector<int64_t>(CommandCenter::kMaxTries - 1, 100));
  EXPECT_TRUE(m.commands().sent().back().gave_up);
  EXPECT_EQ(m.log().lines().back().severity, Severity::kError);
  EXPECT_NE(m.log().lines().back().text.find("no acknowledgement after 5 tries"), std::string::npos);
}

TEST(GcsModel, AckStopsResendingAndOnlyOurAcksCount) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.SubmitCommand("arm", 0.0);
  m.commands().TakeOutgoing();
  m.OnAck("UAV1", {"other-gcs", 100, "arm", CommandResult::kCompleted, 100, ""}, 0.5);
  EXPECT_FALSE(m.commands().sent().back().acknowledged);
  m.OnAck("UAV2", {"gcs", 100, "arm", CommandResult::kCompleted, 100, ""}, 0.5);  // wrong vehicle
  EXPECT_FALSE(m.commands().sent().back().acknowledged);
  m.OnAck("UAV1", {"gcs", 100, "arm", CommandResult::kAccepted, 0, ""}, 0.5);
  EXPECT_TRUE(m.commands().sent().back().acknowledged);
  m.Tick(5.0);
  EXPECT_TRUE(m.commands().TakeOutgoing().empty());
}

// After "gps 0" the vehicle's failsafe landing reports as itself: a row of its own, while the
// operator's completed takeoff stays closed, and a replaced command closes as replaced.
TEST(GcsModel, AFailsafeGetsItsOwnRowAndNeverReopensTheLastCommand) {
  GcsModel m("gcs", 100);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.SubmitCommand("takeoff 10", 0.0);
  m.OnAck("UAV1", {"gcs", 100, "takeoff", CommandResult::kCompleted, 100, ""}, 1.0);
  m.SubmitCommand("goto 50 0 10", 2.0);
  m.OnAck("UAV1", {"gcs", 101, "goto", CommandResult::kAccepted, 0, ""}, 2.1);
  m.SubmitCommand("hover", 3.0);
  m.OnAck("UAV1", {"gcs", 101, "goto", CommandResult::kReplaced, 20, "replaced by hover"}, 3.1);
  m.OnAck("UAV1", {"gcs", 102, "hover", CommandResult::kCompleted, 100, ""}, 3.1);
  const std::string vehicle(kVehicleInitiatedSource);
  m.OnAck("UAV1", {vehicle, 1, "failsafe_land", CommandResult::kAccepted, 0, "no position source for 5 s"}, 4.0);
  EXPECT_EQ(m.log().lines().back().severity, Severity::kWarning);
  m.OnAck("UAV1", {vehicle, 1, "failsafe_land", CommandResult::kInProgress, 97, ""}, 9.0);
  const auto& sent = m.commands().sent();
  ASSERT_EQ(sent.size(), 4u);
  EXPECT_EQ(sent[0].last_ack->result, CommandResult::kCompleted);  // takeoff: closed, 100 %
  EXPECT_EQ(sent[0].last_ack->percent, 100);
  EXPECT_EQ(sent[1].last_ack->result, CommandResult::kReplaced);   // goto: replaced, not failed
  EXPECT_FALSE(IsFailure(sent[1].last_ack->result));
  EXPECT_TRUE(sent[3].vehicle_initiated);
  EXPECT_EQ(sent[3].text, "failsafe_land");
  EXPECT_EQ(sent[3].last_ack->percent, 97);
  m.OnAck("UAV1", {vehicle, 1, "failsafe_land", CommandResult::kCompleted, 100, ""}, 12.0);
  EXPECT_EQ(sent.size(), 4u);
  EXPECT_EQ(sent[3].last_ack->result, CommandResult::kCompleted);
  // A vehicle row is never resent (the operator's were answered: nothing goes out again).
  m.commands().TakeOutgoing();
  m.Tick(20.0);
  EXPECT_TRUE(m.commands().TakeOutgoing().empty());
  m.OnAck("UAV1", {vehicle, 2, "failsafe_return", CommandResult::kAccepted, 0, "battery 24 %"}, 13.0);
  EXPECT_EQ(m.commands().sent().size(), 5u);
  EXPECT_NE(m.log().lines().back().text.find("vehicle: failsafe_return accepted (battery 24 %)"), std::string::npos)
      << m.log().lines().back().text;
}

// A simulator that runs slow sends its 1 Hz heartbeat late in wall time: the link is judged on
// the vehicle's clock and the GCS says the simulator is slow; a real silence is still LOST.
TEST(GcsModel, ASlowSimulatorIsNotALostLink) {
  GcsModel m("gcs", 100);
  HeartbeatInfo slow = Hb(2, true);
  slow.sim_rate_asked = 2.0;
  slow.sim_rate = 0.37;
  m.OnHeartbeat("UAV1", 1, slow, 0.0);
  const VehicleModel& v = m.vehicles().at("UAV1");
  EXPECT_TRUE(v.heartbeat->SimSlow());
  EXPECT_NE(m.log().lines().back().text.find("simulator at 0.37x of the 2x asked"), std::string::npos)
      << m.log().lines().back().text;
  EXPECT_EQ(m.log().lines().back().severity, Severity::kWarning);
  EXPECT_TRUE(v.LinkUp(3.6, m.telemetry_params()));   // 1.3 s of its own clock
  EXPECT_TRUE(v.LinkUp(8.0, m.telemetry_params()));   // 2.96 s
  EXPECT_FALSE(v.LinkUp(8.2, m.telemetry_params()));  // 3.03 s: silent for three of its seconds
  // A real vehicle (or a simulator at pace) is LOST after 3 s of wall time, as before.
  HeartbeatInfo real = Hb(2, true);
  m.OnHeartbeat("UAV2", 1, real, 0.0);
  EXPECT_FALSE(m.vehicles().at("UAV2").heartbeat->SimSlow());
  EXPECT_FALSE(m.vehicles().at("UAV2").LinkUp(3.6, m.telemetry_params()));
  // A simulator faster than real time is judged on wall time too.
  HeartbeatInfo fast = Hb(2, true);
  fast.sim_rate_asked = 0.0;
  fast.sim_rate = 120.0;
  m.OnHeartbeat("UAV3", 1, fast, 0.0);
  EXPECT_FALSE(m.vehicles().at("UAV3").heartbeat->SimSlow());
  EXPECT_TRUE(m.vehicles().at("UAV3").LinkUp(2.9, m.telemetry_params()));
  EXPECT_FALSE(m.vehicles().at("UAV3").LinkUp(3.1, m.telemetry_params()));
  // Back to pace is said once.
  slow.sim_rate = 1.95;
  m.OnHeartbeat("UAV1", 2, slow, 9.0);
  EXPECT_NE(m.log().lines().back().text.find("back to pace"), std::string::npos);
}

TEST(GcsModel, VehiclesDoNotLeakIntoEachOther) {
  GcsModel m("gcs", 100);
  m.OnState("UAV1", 1, State(100.0, 5.0), 0.0);
  m.OnState("UAV2", 1, State(200.0, 50.0), 0.0);
  EXPECT_EQ(m.vehicles().at("UAV1").Latest(Sig("STATE.alt")).value(), 5.0);
  EXPECT_EQ(m.vehicles().at("UAV2").Latest(Sig("STATE.alt")).value(), 50.0);
  EXPECT_EQ(m.vehicles().at("UAV1").History(Sig("STATE.alt"))->size(), 1u);
  m.SelectVehicle("UAV2");
  m.SubmitCommand("land", 1.0);
  EXPECT_EQ(m.commands().TakeOutgoing()[0].vehicle_id, "UAV2");
}

TEST(GcsModel, PlotSelectionAndWindowLimits) {
  GcsModel m("gcs", 1);
  m.plots().Toggle(Sig("STATE.alt"));
  m.plots().Toggle(Sig("STATE.x"));
  m.plots().Toggle(Sig("STATE.alt"));
  EXPECT_EQ(Keys(m.plots().ticked()), std::set<std::string>{"STATE.x"});
  m.plots().SetWindow(0.5);
  EXPECT_EQ(m.plots().window(), 60.0);
  m.plots().SetWindow(1800);
  EXPECT_EQ(m.plots().window(), 1800.0);
}

}  // namespace
}  // namespace uav::gcs

namespace uav::gcs {
namespace {

TEST(PlotCsvExport, WritesTheTickedSignalsOverTheRangeAndNothingElse) {
  GcsModel m("gcs", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  for (int i = 0; i <= 100; ++i)  // 2 s at 50 Hz
    m.OnState("UAV1", i + 1, StateOf(10.0 + 0.02 * i, {{"alt", 0.1 * i}, {"x", -1.0 * i}, {"y", 7.0}}), 0.0);
  const std::string path = testing::TempDir() + "/plot_export_test.csv";
  std::remove(path.c_str());
  EXPECT_FALSE(m.ExportPlotCsv(path, 0.0, 2.0, 1.0));  // nothing ticked
  EXPECT_NE(m.log().lines().back().text.find("nothing to export"), std::string::npos);
  m.plots().Toggle(Sig("STATE.alt"));
  m.plots().Toggle(Sig("STATE.x"));
  ASSERT_TRUE(m.ExportPlotCsv(path, 0.5, 1.0, 1.0));
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t,STATE.alt,STATE.x");
  std::vector<std::string> rows;
  while (std::getline(in, line)) rows.push_back(line);
  ASSERT_EQ(rows.size(), 26u);  // 0.50, 0.52, ..., 1.00
  EXPECT_EQ(rows.front(), "0.500,2.5,-25");
  EXPECT_EQ(rows.back(), "1.000,5,-50");
  EXPECT_NE(m.log().lines().back().text.find("exported 26 rows of 2 signals"), std::string::npos);
  EXPECT_FALSE(m.ExportPlotCsv("/nonexistent-dir/x.csv", 0.0, 2.0, 1.0));
  EXPECT_NE(m.log().lines().back().text.find("CSV export failed"), std::string::npos);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace uav::gcs

namespace uav::gcs {
namespace {

// Live map tiles: decoded per vehicle, black (unmapped) made transparent, a newer map replaces
// the old one, bad tiles rejected and counted.
TEST(GcsLiveMap, TilesArePerVehicleAndANewMapReplacesTheOld) {
  GcsModel m("test", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.OnHeartbeat("UAV2", 1, Hb(0, false), 0.0);
  cv::Mat tile(64, 64, CV_8UC3, cv::Scalar(30, 120, 200));
  tile(cv::Rect(0, 0, 32, 64)).setTo(cv::Scalar::all(0));  // the left half unmapped
  MapTile t;
  t.map_id = 1;
  t.tile_px = 64;
  t.gsd_m = 0.05;
  cv::imencode(".jpg", tile, t.jpeg);
  m.OnMapTile("UAV1", t, 0.1);
  t.tile_x = 1;
  m.OnMapTile("UAV1", t, 0.2);
  const LiveMap& map = m.vehicles().at("UAV1").live_map;
  ASSERT_EQ(map.tiles.size(), 2u);
  const auto& rgba = map.tiles.at({0, 0}).rgba;
  EXPECT_EQ(rgba[(10 * 64 + 5) * 4 + 3], 0);     // unmapped: transparent
  EXPECT_EQ(rgba[(10 * 64 + 50) * 4 + 3], 255);  // mapped: opaque
  EXPECT_NEAR(rgba[(10 * 64 + 50) * 4 + 0], 200, 4);
  EXPECT_TRUE(m.vehicles().at("UAV2").live_map.tiles.empty());
  MapTile bad = t;
  bad.tile_px = 128;  // the JPEG is 64 px
  m.OnMapTile("UAV1", bad, 0.3);
  bad = t;
  bad.gsd_m = std::nan("");
  m.OnMapTile("UAV1", bad, 0.3);
  EXPECT_EQ(map.rejected, 2);
  EXPECT_EQ(map.tiles.size(), 2u);
  t.map_id = 2;  // the next survey
  m.OnMapTile("UAV1", t, 0.4);
  EXPECT_EQ(map.map_id, 2);
  EXPECT_EQ(map.tiles.size(), 1u);
  t.map_id = 1;  // a late tile of the old map: rejected (the counters are the new map's)
  m.OnMapTile("UAV1", t, 0.5);
  EXPECT_EQ(map.rejected, 1);
  EXPECT_EQ(map.tiles.size(), 1u);
}

// Downloads: an offered file is fetched by chunk requests and saved after its SHA-256 matched.
TEST(GcsDownload, SavesAVerifiedFileWhereTheOperatorSaid) {
  GcsModel m("test", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.SelectVehicle("UAV1");
  FileSender sender;
  const std::string contents(10000, 'm');
  const FileOffer offer = sender.Offer("map_1.png", contents);
  m.OnFileOffer("UAV1", offer, 0.1);
  const std::string dir = testing::TempDir() + "/gcs_download_test";
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(m.StartDownload(dir, 0.2));
  for (double t = 0.3; t < 3 && m.vehicles().at("UAV1").saved.empty(); t += 0.02) {
    m.Tick(t);
    for (const auto& r : m.maps().TakeOutgoing()) sender.OnRequest(r.request);
    for (const auto& c : sender.Poll(t).chunks) m.OnFileChunk("UAV1", c, t);
  }
  const std::string path = dir + "/map_1.png";
  ASSERT_TRUE(std::filesystem::exists(path));
  EXPECT_EQ(std::filesystem::file_size(path), contents.size());
  EXPECT_FALSE(m.StartDownload("/proc/no_such_dir/x", 3.0));
  EXPECT_NE(m.maps().error().find("cannot use"), std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST(GcsVideo, DecodesFramesPerVehicleAndRejectsBadOnesNamingWhy) {
  GcsModel m("test", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.OnHeartbeat("UAV2", 1, Hb(0, false), 0.0);
  VideoFrame f;
  f.camera = "downward";
  f.width = 8;
  f.height = 6;
  f.source_width = 640;
  f.source_height = 480;
  f.jpeg = Jpeg(8, 6);
  m.OnVideoFrame("UAV1", f, 0.1);
  m.OnVideoFrame("UAV1", f, 0.3);
  const VideoFeed& feed = m.vehicles().at("UAV1").video;
  EXPECT_EQ(feed.frames, 2);
  EXPECT_EQ(feed.rgba.size(), 8u * 6u * 4u);
  EXPECT_EQ(feed.rgba[0], 200);  // RGBA: red first (BGR 30,120,200 encoded)
  EXPECT_NEAR(feed.rgba[1], 120, 3);
  EXPECT_EQ(m.vehicles().at("UAV2").video.frames, 0);  // nothing leaks to the other vehicle
  // Truncated data, wrong stated size, empty: rejected, counted, the last good frame kept.
  VideoFrame bad = f;
  bad.jpeg.resize(20);
  m.OnVideoFrame("UAV1", bad, 0.4);
  bad = f;
  bad.width = 9;
  m.OnVideoFrame("UAV1", bad, 0.5);
  bad.jpeg.clear();
  m.OnVideoFrame("UAV1", bad, 0.6);
  EXPECT_EQ(feed.frames, 2);
  EXPECT_EQ(feed.rejected, 3);
  EXPECT_EQ(feed.width, 8);
  bool logged = false;
  for (const auto& l : m.log().lines()) logged |= l.text.find("video frame rejected") != std::string::npos;
  EXPECT_TRUE(logged);
}

}  // namespace
}  // namespace uav::gcs
