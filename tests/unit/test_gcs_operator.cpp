// Issue 6: the operator's telemetry tree, plot panels, target selection on video, live map
// navigation and keyboard shortcuts, first on the model, then on the real panels headless with
// scripted mouse and keyboard input (as uav-gcs --headless --script drives them).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <imgui.h>
#include <opencv2/imgcodecs.hpp>

#include "unit/gcs_test_util.hpp"
#include "uav/gcs/gcs_ui.hpp"
#include "uav/gcs/platform.hpp"
#include "uav/gcs/script.hpp"
#include "uav/gcs/script_input.hpp"
#include "uav/gcs/signal_series.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::gcs {
namespace {

TEST(SignalSeries, MinMaxMatchesAScanAcrossTheRingsWrap) {
  SignalSeries s(1000);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5, 5);
  for (int i = 0; i < 2537; ++i) s.Push(i * 0.02, u(rng));  // wrapped more than twice
  std::uniform_int_distribution<int> pick(0, 999);
  for (int k = 0; k < 500; ++k) {
    int i = pick(rng), j = pick(rng);
    if (i > j) std::swap(i, j);
    ++j;
    float lo, hi;
    s.MinMax(i, j, &lo, &hi);
    float want_lo = 1e9f, want_hi = -1e9f;
    for (int n = i; n < j; ++n)
      want_lo = std::min(want_lo, static_cast<float>(s.ValueAt(n))), want_hi = std::max(want_hi, static_cast<float>(s.ValueAt(n)));
    ASSERT_EQ(lo, want_lo) << i << ".." << j;
    ASSERT_EQ(hi, want_hi) << i << ".." << j;
  }
  for (int from = 0; from < 1000; from += 37)
    for (double t : {s.TimeAt(from), s.TimeAt(from) + 0.001, s.TimeAt(from) + 3.0, s.TimeAt(999) + 1.0})
      ASSERT_EQ(s.LowerBoundFrom(t, from), s.LowerBound(t)) << from << " " << t;
  EXPECT_EQ(s.UpperBound(s.TimeAt(10)), 11u);
  EXPECT_EQ(s.LowerBound(s.TimeAt(10)), 10u);
}

TEST(GcsTelemetryTree, GroupsCarryTheirRateAndAge) {
  GcsModel m("gcs", 1);
  for (int i = 0; i < 50; ++i) m.OnState("UAV1", i + 1, StateOf(i * 0.02, {{"alt", 1.0}}), 10.0 + i * 0.02);
  m.OnHeartbeat("UAV1", 1, Hb(2, true), 10.5);
  const VehicleModel& v = m.vehicles().at("UAV1");
  EXPECT_NEAR(v.group(SignalGroupId::kState).Rate(10.99), 50, 1);
  EXPECT_NEAR(v.group(SignalGroupId::kState).Age(11.5), 11.5 - 10.98, 1e-9);
  EXPECT_EQ(v.group(SignalGroupId::kHeartbeat).Rate(11.0), 1);
  EXPECT_EQ(v.Latest(Sig("HEARTBEAT.task")).value(), 2);  // heartbeats are in the tree too (no history)
  EXPECT_EQ((v.History(Sig("HEARTBEAT.task")) ? 1u : 0u), 0u);
}

TEST(GcsPlots, PanelsAxesAndRangesAreCheckedOnBothSides) {
  GcsModel m("gcs", 1);
  EXPECT_EQ(m.plots().specs().size(), 1u);
  m.plots().Toggle(Sig("STATE.alt"));
  EXPECT_EQ(m.plots().Add(), 1);
  EXPECT_EQ(m.plots().active(), 1);
  m.plots().Toggle(Sig("STATE.x"));
  m.plots().SetAxis(1, Sig("STATE.x"), PlotAxis::kRight);
  EXPECT_EQ(m.plots().specs()[1].signals.at(Sig("STATE.x")), PlotAxis::kRight);
  EXPECT_EQ(Keys(m.plots().ticked()), (std::set<std::string>{"STATE.alt", "STATE.x"}));
  EXPECT_FALSE(m.plots().SetRange(1, PlotAxis::kRight, false, 2.0, 2.0));  // lo must be below hi
  EXPECT_FALSE(m.plots().SetRange(1, PlotAxis::kRight, false, 0.0, NAN));
  EXPECT_TRUE(m.plots().specs()[1].auto_y[1]);
  EXPECT_TRUE(m.plots().SetRange(1, PlotAxis::kRight, false, -1.0, -0.999));
  EXPECT_FALSE(m.plots().specs()[1].auto_y[1]);
  m.plots().Remove(0);
  EXPECT_EQ(m.plots().specs().size(), 1u);
  m.plots().Remove(0);  // the last one stays
  EXPECT_EQ(m.plots().specs().size(), 1u);
  EXPECT_EQ(Keys(m.plots().ticked()), std::set<std::string>{"STATE.x"});
}

TEST(GcsTracking, SelectionIsValidatedAndStatusIsPerVehicle) {
  GcsModel m("gcs", 1);
  TrackTarget t;
  t.method = TrackTarget::kDrag;
  t.x = 0.2, t.y = 0.3, t.width = 0.1, t.height = 0.2;
  t.corners = {{{0.2, 0.3}, {0.3, 0.3}, {0.3, 0.5}, {0.2, 0.5}}};
  EXPECT_FALSE(m.SelectTarget(t, 0.0));
  EXPECT_EQ(m.video().error(), "no vehicle selected");
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.OnHeartbeat("UAV2", 1, Hb(0, false), 0.0);
  EXPECT_TRUE(m.SelectTarget(t, 0.0));
  auto out = m.video().TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].vehicle_id, "UAV1");
  EXPECT_DOUBLE_EQ(out[0].x, 0.2);
  // Both sides of the image's edges, and the smallest box.
  TrackTarget edge = t;
  edge.x = 0.9, edge.width = 0.1;  // right edge exactly at 1
  for (auto& c : edge.corners) c[0] = std::min(1.0, c[0] + 0.7);
  EXPECT_TRUE(m.SelectTarget(edge, 0.1)) << m.video().error();
  edge.width = 0.1001;
  EXPECT_FALSE(m.SelectTarget(edge, 0.1));
  EXPECT_NE(m.video().error().find("outside the image"), std::string::npos);
  TrackTarget tiny = t;
  tiny.width = 0.0049;
  EXPECT_FALSE(m.SelectTarget(tiny, 0.1));
  EXPECT_NE(m.video().error().find("too small"), std::string::npos);
  tiny.width = 0.005;
  EXPECT_TRUE(m.SelectTarget(tiny, 0.1));
  TrackTarget nan = t;
  nan.corners[2][1] = NAN;
  EXPECT_FALSE(m.SelectTarget(nan, 0.1));
  EXPECT_EQ(m.video().TakeOutgoing().size(), 2u);
  // Status: validated, kept per vehicle, in the tree as TRACK.*.
  TrackStatus st;
  st.utime = 1000000;
  st.state = TrackStatus::kTracking;
  st.center_x = 0.25, st.center_y = 0.4, st.width = 0.1, st.height = 0.2;
  m.OnTrackStatus("UAV2", 1, st, 0.2);
  EXPECT_FALSE(m.vehicles().at("UAV1").track);
  ASSERT_TRUE(m.vehicles().at("UAV2").track);
  EXPECT_EQ(m.vehicles().at("UAV2").Latest(Sig("TRACK.center_x")).value(), 0.25);
  TrackStatus bad = st;
  bad.center_x = NAN;
  m.OnTrackStatus("UAV1", 2, bad, 0.3);
  // A state outside the enum is refused by the link before it becomes one (LinkTest).
  bad = st;
  bad.center_y = 1.6;
  m.OnTrackStatus("UAV1", 2, bad, 0.3);
  EXPECT_FALSE(m.vehicles().at("UAV1").track);
}

TEST(GcsVideo, FreezeHoldsTheFrameAndSwitchingVehicleDropsIt) {
  GcsModel m("gcs", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  m.OnHeartbeat("UAV2", 1, Hb(0, false), 0.0);
  EXPECT_FALSE(m.FreezeVideo(true));  // no frame yet
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  VideoFrame f;
  f.utime = 5;
  f.camera = "downward";
  f.width = 64, f.height = 48, f.source_width = 640, f.source_height = 480;
  cv::imencode(".jpg", img, f.jpeg);
  m.OnVideoFrame("UAV1", f, 0.1);
  ASSERT_TRUE(m.FreezeVideo(true));
  f.utime = 6;
  m.OnVideoFrame("UAV1", f, 0.2);
  EXPECT_EQ(m.video().frozen()->utime, 5);  // the frozen frame stays
  m.SelectVehicle("UAV2");
  EXPECT_FALSE(m.video().frozen());  // nothing of UAV1 on UAV2's panels
}

// Two cameras streaming: the panel shows the first seen until the operator picks the other;
// frames of the camera not shown are not decoded into the picture.
TEST(GcsVideo, OneOfSeveralCamerasIsChosen) {
  GcsModel m("gcs", 1);
  m.OnHeartbeat("UAV1", 1, Hb(0, false), 0.0);
  cv::Mat img(48, 64, CV_8UC3, cv::Scalar(10, 20, 30));
  VideoFrame f;
  f.width = 64, f.height = 48, f.source_width = 640, f.source_height = 480;
  cv::imencode(".jpg", img, f.jpeg);
  for (int k = 0; k < 4; ++k) {
    f.utime = k;
    f.camera = k % 2 ? "gimbal" : "downward";
    m.OnVideoFrame("UAV1", f, 0.1 * k);
  }
  const VehicleModel& v = *m.selected();
  EXPECT_EQ(v.cameras, (std::vector<std::string>{"downward", "gimbal"}));
  EXPECT_EQ(v.camera, "downward");
  EXPECT_EQ(v.video.frames, 2);
  EXPECT_EQ(v.video.camera, "downward");
  EXPECT_FALSE(m.ChooseVideoCamera("forward"));  // never streamed
  ASSERT_TRUE(m.ChooseVideoCamera("gimbal"));
  f.camera = "gimbal";
  f.utime = 9;
  m.OnVideoFrame("UAV1", f, 0.5);
  EXPECT_EQ(m.selected()->video.frames, 1);
  EXPECT_EQ(m.selected()->video.camera, "gimbal");
  EXPECT_EQ(m.selected()->video.utime, 9);
}

// ---- The panels headless, driven like a person: a fake vehicle fed into the model.

class Panels : public ::testing::Test {
 protected:
  Panels() : platform_(MakeNullPlatform(1600, 900)), model_("gcs", 1), driver_(ctx_, nullptr) {
    model_.OnHeartbeat("UAV1", 1, Hb(2, true), 0.0);
    model_.OnHeartbeat("UAV2", 1, Hb(0, false), 0.0);
  }
  void Frames(int n) {
    for (int i = 0; i < n; ++i) {
      now_ += 1.0 / 60;
      ctx_.now = now_;
      platform_->NewFrame(1.0 / 60);
      driver_.ApplyNextEvent();
      ImGui::NewFrame();
      DrawGcs(model_, ctx_);
      platform_->Render();
    }
  }
  void RunUntilIdle() {
    for (int i = 0; i < 200 && driver_.InputPending(); ++i) Frames(1);
    Frames(3);
  }
  void Telemetry(int samples) {
    for (int i = 0; i < samples; ++i, ++seq_)
      model_.OnState("UAV1", seq_, StateOf(seq_ * 0.02, {{"alt", std::sin(seq_ * 0.01)}, {"x", seq_ * 0.001}}), now_);
  }
  void Video(const std::string& vehicle) {
    cv::Mat img(120, 160, CV_8UC3, cv::Scalar(40, 90, 140));
    VideoFrame f;
    f.utime = 123456;
    f.camera = "downward";
    f.width = 160, f.height = 120, f.source_width = 640, f.source_height = 480;
    cv::imencode(".jpg", img, f.jpeg);
    model_.OnVideoFrame(vehicle, f, now_);
  }
  std::unique_ptr<Platform> platform_;
  GcsModel model_;
  UiContext ctx_;
  ImGuiScriptDriver driver_;
  double now_ = 0.0;
  int64_t seq_ = 1;
  std::string err_;
};

TEST_F(Panels, TargetByFourClicksAndByADragOnAFrozenFrame) {
  Video("UAV1");
  Frames(3);
  ASSERT_TRUE(driver_.StartClick("video:freeze", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(model_.video().frozen());
  // Four corners (thesis 3.7.3), clockwise from the top left.
  const double pts[4][2] = {{0.25, 0.20}, {0.55, 0.22}, {0.50, 0.60}, {0.27, 0.58}};
  for (const auto& p : pts) {
    ASSERT_TRUE(driver_.StartGesture("video:image", ScriptDriver::Gesture::kClick, p[0], p[1], 0, 0, 0, &err_)) << err_;
    RunUntilIdle();
  }
  auto out = model_.video().TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);
  const TrackTarget& t = out[0];
  EXPECT_EQ(t.method, TrackTarget::kFourClicks);
  EXPECT_EQ(t.frame_utime, 123456);
  const WidgetRect r = ctx_.widgets.at("video:image");
  const double px = 1.0 / (r.x1 - r.x0);  // one screen pixel in normalised units
  EXPECT_NEAR(t.x, 0.25, 2 * px);
  EXPECT_NEAR(t.y, 0.20, 2 * px);
  EXPECT_NEAR(t.x + t.width, 0.55, 2 * px);
  EXPECT_NEAR(t.y + t.height, 0.60, 2 * px);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(t.corners[i][0], pts[i][0], 2 * px);
  EXPECT_FALSE(model_.video().frozen());  // back to live to watch it track
  // The tracker's answer is drawn over the live video (headless: the state is what we check).
  TrackStatus st;
  st.target_seq = t.target_seq - 1;  // about an earlier selection: not this one's answer
  st.state = TrackStatus::kTracking;
  st.center_x = 0.4, st.center_y = 0.4, st.width = 0.3, st.height = 0.4;
  model_.OnTrackStatus("UAV1", 1, st, now_);
  EXPECT_FALSE(model_.vehicles().at("UAV1").track);
  EXPECT_EQ(model_.vehicles().at("UAV1").stale_track_statuses, 1);
  st.target_seq = t.target_seq;
  model_.OnTrackStatus("UAV1", 2, st, now_);
  ASSERT_TRUE(model_.vehicles().at("UAV1").track);
  Frames(2);
  // A drag on a new frozen frame.
  ASSERT_TRUE(driver_.StartClick("video:freeze", &err_));
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartGesture("video:image", ScriptDriver::Gesture::kDrag, 0.6, 0.7, 0.8, 0.9, 0, &err_));
  RunUntilIdle();
  out = model_.video().TakeOutgoing();
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].method, TrackTarget::kDrag);
  EXPECT_NEAR(out[0].x, 0.6, 2 * px);
  EXPECT_NEAR(out[0].width, 0.2, 3 * px);
  EXPECT_NEAR(out[0].height, 0.2, 3 * px);
  // A right click clears half-done corners; nothing is sent.
  ASSERT_TRUE(driver_.StartClick("video:freeze", &err_));
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartGesture("video:image", ScriptDriver::Gesture::kClick, 0.1, 0.1, 0, 0, 0, &err_));
  RunUntilIdle();
  EXPECT_EQ(ctx_.state.video_clicks.size(), 1u);
  ASSERT_TRUE(driver_.StartGesture("video:image", ScriptDriver::Gesture::kRightClick, 0.1, 0.1, 0, 0, 0, &err_));
  RunUntilIdle();
  EXPECT_TRUE(ctx_.state.video_clicks.empty());
  EXPECT_TRUE(model_.video().TakeOutgoing().empty());
}

TEST_F(Panels, PlotsTakeTicksZoomPanAndReadOut) {
  Telemetry(3000);  // 60 s
  Frames(3);
  ctx_.state.signal_filter = "STATE.alt";  // the tree is longer than its window: search first
  Frames(1);
  ASSERT_TRUE(driver_.StartClick("tick:STATE.alt", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartClick("plot:add", &err_)) << err_;
  RunUntilIdle();
  ASSERT_EQ(model_.plots().specs().size(), 2u);
  ctx_.state.signal_filter = "STATE.x";
  Frames(1);
  ASSERT_TRUE(driver_.StartClick("tick:STATE.x", &err_));
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartClick("axis:STATE.x", &err_)) << err_;
  RunUntilIdle();
  EXPECT_EQ(model_.plots().specs()[0].signals.size(), 1u);
  EXPECT_EQ(model_.plots().specs()[1].signals.at(Sig("STATE.x")), PlotAxis::kRight);
  // Wheel: two notches in shrink the 60 s window to 60 / 1.25^2.
  ASSERT_TRUE(driver_.StartGesture("plot:1:canvas", ScriptDriver::Gesture::kWheel, 0.5, 0.5, 0, 0, 2, &err_));
  RunUntilIdle();
  EXPECT_NEAR(model_.plots().window(), 60 / 1.5625, 1e-6);
  // Drag right by half the canvas: the time axis holds, half a window earlier.
  const double window = model_.plots().window();
  const double t_end = 59.98;  // the newest sample
  ASSERT_TRUE(driver_.StartGesture("plot:1:canvas", ScriptDriver::Gesture::kDrag, 0.3, 0.5, 0.8, 0.5, 0, &err_));
  RunUntilIdle();
  ASSERT_TRUE(model_.plots().hold());
  EXPECT_NEAR(*model_.plots().hold(), t_end - 0.5 * window, 0.01 * window);
  // Hover: the readout names each signal with its value at that time.
  ASSERT_TRUE(driver_.StartGesture("plot:2:canvas", ScriptDriver::Gesture::kHover, 0.5, 0.5, 0, 0, 0, &err_));
  RunUntilIdle();
  EXPECT_NE(ctx_.state.plot_readout.find("STATE.x = "), std::string::npos) << ctx_.state.plot_readout;
  // The readout's time is half a window before the held end, and x is (t / 0.02 + 1) mm there.
  double t_read = 0, x_read = 0;
  ASSERT_EQ(std::sscanf(ctx_.state.plot_readout.c_str(), "t = %lf s", &t_read), 1);
  ASSERT_EQ(std::sscanf(ctx_.state.plot_readout.c_str() + ctx_.state.plot_readout.find("STATE.x = "), "STATE.x = %lf", &x_read), 1);
  EXPECT_NEAR(t_read, *model_.plots().hold() - 0.5 * window, 0.01 * window);
  EXPECT_NEAR(x_read, (t_read / 0.02 + 1) * 0.001, 0.0011);
}

TEST_F(Panels, ShortcutsAskForConfirmationAndGoToTheSelectedVehicle) {
  Frames(2);
  ASSERT_TRUE(driver_.StartKey("h", true, &err_)) << err_;
  RunUntilIdle();
  EXPECT_EQ(ctx_.state.pending_confirmation, "hover");
  EXPECT_TRUE(model_.commands().sent().empty());
  ASSERT_TRUE(driver_.StartKey("escape", false, &err_));
  RunUntilIdle();
  EXPECT_TRUE(ctx_.state.pending_confirmation.empty());
  ASSERT_TRUE(driver_.StartClick("vehicle:UAV2", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartKey("l", true, &err_));
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartKey("k", true, &err_));
  RunUntilIdle();
  ASSERT_EQ(model_.commands().sent().size(), 1u);
  EXPECT_EQ(model_.commands().sent().back().text, "land");
  EXPECT_EQ(model_.commands().sent().back().vehicle_id, "UAV2");
  EXPECT_FALSE(driver_.StartKey("f13", false, &err_));
}

// "fit to vehicle" in the Survey panel: without the vehicle's parameters nothing changes and the
// log says why; U-Lion's table gives its cruise speed and the radius of its turns at ts_bank_max
// (12 m/s at 0.5 rad: 12^2 / (9.80665 tan 0.5) = 26.88 m); a quadrotor's turns on the spot and
// keeps the planned speed up to its limit.
TEST_F(Panels, TheSurveyIsFittedToTheVehiclesSpeedAndTurns) {
  model_.OnHeartbeat("UAV1", 1, Hb(0, false), now_);
  Frames(2);
  waypoints::SurveyParams& p = model_.missions().planner().params();
  p.speed_m_s = 8.0;
  ASSERT_TRUE(driver_.StartClick("survey:fit", &err_)) << err_;
  RunUntilIdle();
  EXPECT_EQ(p.speed_m_s, 8.0);
  EXPECT_NE(model_.log().lines().back().text.find("no parameter table from the vehicle yet"), std::string::npos);
  const ParameterSet ulion =
      ParameterSet::LoadFile(std::string(UAV_RESOURCE_DIR) + "/vehicles/ulion.params", VehicleParameterSchema());
  model_.OnReport("UAV1", ParameterTable::Of(ulion, 1, 5), now_);
  ASSERT_TRUE(driver_.StartClick("survey:fit", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(p.speed_m_s, 12.0);
  EXPECT_NEAR(p.turn_radius_m, 26.88, 0.01);
  EXPECT_NE(model_.log().lines().back().text.find("a tail-sitter"), std::string::npos) << model_.log().lines().back().text;
  model_.OnReport("UAV1", ParameterTable::Of(ParameterSet::Defaults(VehicleParameterSchema()).With("ctl_speed_max_xy", 5.0), 2, 6), now_);
  ASSERT_TRUE(driver_.StartClick("survey:fit", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(p.speed_m_s, 5.0);
  EXPECT_EQ(p.turn_radius_m, 0.0);
}

// The attitude indicator: opened from the status bar; its horizon banks against the roll (right
// bank: the right end rises) and moves down by the pitch at the ladder's scale; with no state yet
// it says so.
TEST_F(Panels, TheAttitudeIndicatorBanksAndPitchesItsHorizon) {
  const Eigen::Vector2d c(100, 100);
  const HorizonLine level = AttitudeHorizon(0, 0, c, 200, 50);
  EXPECT_NEAR(level.left_px.y(), 100, 1e-9);
  EXPECT_NEAR(level.right_px.y(), 100, 1e-9);
  const HorizonLine h = AttitudeHorizon(30 * M_PI / 180, 10 * M_PI / 180, c, 200, 50);
  EXPECT_LT(h.right_px.y(), h.left_px.y()) << "banked right, the horizon's right end rises";
  EXPECT_NEAR((h.right_px - h.left_px).norm(), 100, 1e-9);
  EXPECT_NEAR(std::atan2(h.left_px.y() - h.right_px.y(), h.right_px.x() - h.left_px.x()), 30 * M_PI / 180, 1e-9);
  const Eigen::Vector2d mid = (h.left_px + h.right_px) / 2;
  EXPECT_NEAR((mid - c).norm(), 200 * 10 * M_PI / 180, 1e-9) << "nose up 10 degrees: the horizon 10 degrees down";
  EXPECT_GT(mid.y(), c.y());
  model_.OnHeartbeat("UAV1", 1, Hb(0, false), now_);
  Frames(2);
  ASSERT_TRUE(driver_.StartClick("status:attitude", &err_)) << err_;
  RunUntilIdle();
  EXPECT_TRUE(ctx_.state.show_attitude);
  EXPECT_FALSE(ctx_.widgets.count("attitude:horizon")) << "no state yet: nothing to draw";
  model_.OnState("UAV1", 1, StateOf(0.0, {{"alt", 30.0}}), now_);
  Frames(2);
  EXPECT_TRUE(ctx_.widgets.count("attitude:horizon"));
}

// Parameters: opened from the status bar, searched, a value typed is checked against the
// vehicle's table and sent as a `param` command; one outside its limits or read only at start is
// not sent and the log says why; reset sends the default; save and load go through both formats.
TEST_F(Panels, ParametersAreSearchedEditedResetSavedAndLoaded) {
  ParameterTable table = ParameterTable::Of(ParameterSet::Defaults(VehicleParameterSchema()).With("ctl_tilt_max", 0.35), 1, 5);
  model_.OnReport("UAV1", table, now_);
  Frames(2);
  ASSERT_TRUE(driver_.StartClick("status:params", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(ctx_.state.show_parameters);
  ASSERT_TRUE(driver_.StartSet("params:search", "horizontal speed", &err_)) << err_;
  RunUntilIdle();
  EXPECT_TRUE(ctx_.widgets.count("params:value:ctl_speed_max_xy"));
  EXPECT_FALSE(ctx_.widgets.count("params:value:mass"));  // filtered out
  ASSERT_TRUE(driver_.StartSet("params:value:ctl_speed_max_xy", "4.5", &err_)) << err_;
  RunUntilIdle();
  ASSERT_EQ(model_.commands().sent().size(), 1u);
  EXPECT_EQ(model_.commands().sent().back().text, "param ctl_speed_max_xy 4.5");
  ASSERT_TRUE(driver_.StartSet("params:value:ctl_speed_max_xy", "400", &err_)) << err_;
  RunUntilIdle();
  EXPECT_EQ(model_.commands().sent().size(), 1u);
  EXPECT_NE(model_.log().lines().back().text.find("ctl_speed_max_xy = 400 is outside [0.1, 15] m/s"), std::string::npos)
      << model_.log().lines().back().text;
  // Read only at start: the field is disabled, saying why.
  ASSERT_TRUE(driver_.StartSet("params:search", "mass", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(ctx_.widgets.count("params:value:mass"));
  EXPECT_EQ(ctx_.widgets.at("params:value:mass").disabled, "mass is read only at start");
  // Reset to the default.
  ASSERT_TRUE(driver_.StartSet("params:search", "ctl_tilt", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartClick("params:reset:ctl_tilt_max", &err_)) << err_;
  RunUntilIdle();
  ASSERT_EQ(model_.commands().sent().size(), 2u);
  EXPECT_EQ(model_.commands().sent().back().text, "param ctl_tilt_max 0.45");
  // Saved as QGroundControl's file, edited, loaded: only what differs and may change is sent.
  const std::string path = ::testing::TempDir() + "uav_params_panel.params";
  ctx_.state.params_file = path;
  ctx_.state.params_format = 1;
  ASSERT_TRUE(driver_.StartClick("params:save", &err_)) << err_;
  RunUntilIdle();
  std::string text = ReadTextFile(path, "saved");
  EXPECT_NE(text.find("1\t1\tctl_tilt_max\t0.35\t9\n"), std::string::npos);
  auto replace = [&](const std::string& from, const std::string& to) { text.replace(text.find(from), from.size(), to); };
  replace("\tflw_distance\t8\t", "\tflw_distance\t12\t");
  replace("\tmass\t1.37\t", "\tmass\t2\t");
  text += "1\t1\tno_such_param\t3\t9\n";
  WriteFileAtomically(path, text);
  ASSERT_TRUE(driver_.StartClick("params:load", &err_)) << err_;
  RunUntilIdle();
  ASSERT_EQ(model_.commands().sent().size(), 3u);
  EXPECT_EQ(model_.commands().sent().back().text, "param flw_distance 12");
  std::string logged;
  for (const LogLine& l : model_.log().lines()) logged += l.text + "\n";
  EXPECT_NE(logged.find("parameter file: mass is read only at start"), std::string::npos) << logged;
  EXPECT_NE(logged.find("parameter file: the vehicle has no parameter 'no_such_param'"), std::string::npos) << logged;
  EXPECT_NE(logged.find(": 1 changes sent, "), std::string::npos) << logged;
  std::filesystem::remove(path);
}

// Emergency stop: off while the vehicle is disarmed, saying why; armed, the button and the typed
// command each ask twice before `emergency_stop` goes out, and Cancel withdraws.
TEST_F(Panels, EmergencyStopAsksTwiceAndIsOffWhileDisarmed) {
  Frames(2);
  ASSERT_TRUE(driver_.StartClick("vehicle:UAV2", &err_)) << err_;  // disarmed
  RunUntilIdle();
  ASSERT_TRUE(ctx_.widgets.count("button:emergency_stop"));
  EXPECT_EQ(ctx_.widgets.at("button:emergency_stop").disabled, "disarmed: the motors are off");
  ASSERT_TRUE(driver_.StartClick("vehicle:UAV1", &err_)) << err_;  // armed
  RunUntilIdle();
  EXPECT_EQ(ctx_.widgets.at("button:emergency_stop").disabled, "");
  ASSERT_TRUE(driver_.StartClick("button:emergency_stop", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartClick("emergency_stop:confirm", &err_)) << err_;
  RunUntilIdle();
  EXPECT_TRUE(model_.commands().sent().empty());  // asked once more
  ASSERT_TRUE(driver_.StartClick("emergency_stop:cancel", &err_)) << err_;
  RunUntilIdle();
  EXPECT_FALSE(ctx_.widgets.count("emergency_stop:confirm_again"));
  ASSERT_TRUE(driver_.StartType("emergency_stop", &err_)) << err_;
  RunUntilIdle();
  EXPECT_TRUE(model_.commands().sent().empty());
  ASSERT_TRUE(driver_.StartClick("emergency_stop:confirm", &err_)) << err_;
  RunUntilIdle();
  ASSERT_TRUE(driver_.StartClick("emergency_stop:confirm_again", &err_)) << err_;
  RunUntilIdle();
  ASSERT_EQ(model_.commands().sent().size(), 1u);
  EXPECT_EQ(model_.commands().sent().back().text, "emergency_stop");
  EXPECT_EQ(model_.commands().sent().back().vehicle_id, "UAV1");
}

TEST_F(Panels, LiveMapZoomsAboutTheCursorAndPans) {
  cv::Mat tile(64, 64, CV_8UC3, cv::Scalar(30, 120, 200));
  MapTile t;
  t.map_id = 1, t.tile_px = 64, t.gsd_m = 0.05;
  cv::imencode(".jpg", tile, t.jpeg);
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 2; ++y) {
      t.tile_x = x, t.tile_y = y;
      model_.OnMapTile("UAV1", t, now_);
    }
  Frames(3);
  ASSERT_TRUE(driver_.StartGesture("livemap", ScriptDriver::Gesture::kWheel, 0.5, 0.5, 0, 0, 3, &err_)) << err_;
  RunUntilIdle();
  EXPECT_NEAR(ctx_.state.live_zoom, std::pow(1.25, 3), 1e-9);
  const double pan_before = ctx_.state.live_pan_x;
  ASSERT_TRUE(driver_.StartGesture("livemap", ScriptDriver::Gesture::kDrag, 0.6, 0.5, 0.4, 0.5, 0, &err_));
  RunUntilIdle();
  EXPECT_GT(ctx_.state.live_pan_x, pan_before + 0.1);  // dragged left: the view moved east
  ASSERT_TRUE(driver_.StartClick("livemap:fit", &err_)) << err_;
  RunUntilIdle();
  EXPECT_EQ(ctx_.state.live_zoom, 1.0);
}

}  // namespace
}  // namespace uav::gcs

namespace uav::gcs {
namespace {

// A replay that only records what it is asked (the real one plays a log: test_log_replay).
class FakeReplay : public ReplayControl {
 public:
  void Seek(double t) override { position_ = t; }
  void Pause() override { paused_ = true; }
  void Play() override { paused_ = false; }
  bool SetSpeed(double s) override {
    if (!(s >= 0.1 && s <= 10.0)) return false;
    speed_ = s;
    return true;
  }
  double speed() const override { return speed_; }
  double position() const override { return position_; }
  double duration() const override { return 100.0; }
  bool paused() const override { return paused_; }
  std::size_t dispatched() const override { return 0; }
  std::size_t events() const override { return 10; }
  std::string damage() const override { return ""; }
  std::string path() const override { return "fake.lcmlog"; }

 private:
  double speed_ = 1.0, position_ = 0.0;
  bool paused_ = false;
};

class ReplayPanels : public Panels {
 protected:
  ReplayPanels() {
    model_.SetReplay(true);
    ctx_.replay = &replay_;
  }
  FakeReplay replay_;
};

// A replay only watches: typing a command or pressing a command button is refused with the
// reason, as a step that fails, and nothing is queued.
TEST_F(ReplayPanels, TheCommandBarIsDisabledWithTheReason) {
  Frames(3);
  EXPECT_FALSE(driver_.StartType("arm", &err_));
  EXPECT_EQ(err_, "'command' is disabled: replaying a log: nothing is sent to any vehicle");
  EXPECT_FALSE(driver_.StartClick("button:arm", &err_));
  EXPECT_NE(err_.find("is disabled: replaying a log"), std::string::npos) << err_;
  ASSERT_TRUE(driver_.StartKey("h", true, &err_)) << err_;  // Ctrl+H asks nothing during a replay
  RunUntilIdle();
  EXPECT_TRUE(ctx_.state.pending_confirmation.empty());
  EXPECT_TRUE(model_.commands().sent().empty());
}

TEST_F(ReplayPanels, SpeedIsSetByTypingAndByPresetsAndRefusedOutOfRange) {
  Frames(3);
  ASSERT_TRUE(driver_.StartSet("replay:speed", "5", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(replay_.speed(), 5.0);
  ASSERT_TRUE(driver_.StartSet("replay:speed", "50", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(replay_.speed(), 5.0);
  EXPECT_EQ(ctx_.state.replay_speed_error, "speed '50' refused: give 0.1 to 10");
  ASSERT_TRUE(driver_.StartSet("replay:speed", "0x2", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(replay_.speed(), 5.0);
  ASSERT_TRUE(driver_.StartClick("replay:x0.5", &err_)) << err_;
  RunUntilIdle();
  EXPECT_DOUBLE_EQ(replay_.speed(), 0.5);
  EXPECT_TRUE(ctx_.state.replay_speed_error.empty());
}

// The scripts' verbs: replay:speed from a script, and a verb that cannot act fails its step.
TEST_F(ReplayPanels, ScriptsSetTheSpeedAndFailStepsThatCannotAct) {
  Frames(3);
  const Script s = Script::Parse("set replay:speed 2.5\nassert replay.speed == 2.5\ntype arm\n", "t.gcs");
  std::FILE* out = std::tmpfile();
  ScriptRunner runner(s, out);
  runner.SetReplay(&replay_);
  for (int i = 0; i < 400 && !runner.finished(); ++i) {
    runner.Update(model_, driver_, now_);
    Frames(1);
  }
  EXPECT_TRUE(runner.failed());
  EXPECT_EQ(runner.passed(), 2);
  EXPECT_DOUBLE_EQ(replay_.speed(), 2.5);
  std::rewind(out);
  char buf[4096] = {0};
  const std::size_t n = std::fread(buf, 1, sizeof buf - 1, out);
  const std::string text(buf, n);
  EXPECT_NE(text.find("FAIL    3: type arm  -> 'command' is disabled: replaying a log"), std::string::npos) << text;
  std::fclose(out);
}

// A long message is kept whole and wrapped in the Messages panel, not cut at its edge.
TEST_F(Panels, LongMessagesWrapInFull) {
  const std::string text =
      "failsafe land: no position source for 5.0 s (GPS lost, visual odometry not healthy); landing where it is, "
      "switch to manual with the RC fail-safe switch to take over";
  model_.OnStatusText("UAV1", Severity::kError, text, now_);
  Frames(3);
  EXPECT_EQ(model_.log().lines().back().text, text);
  const auto it = ctx_.widgets.find("messages:last");
  ASSERT_NE(it, ctx_.widgets.end());
  EXPECT_GT(it->second.y1 - it->second.y0, 1.5f * ImGui::GetTextLineHeight());  // more than one line
}

}  // namespace
}  // namespace uav::gcs
