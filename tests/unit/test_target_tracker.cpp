// Target tracking (thesis 3.7) against the renderer's exact object boxes: a coloured ball and a
// car moving slowly past a static camera, a jump, and bad selections. CamShift must hold the
// centre within 2 px (median) and re-lock within 10 frames of a jump; KCF and CSRT run on the
// same frames for the documentation's comparison.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/target_tracker.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

world::CameraSetup TestCamera() {
  world::CameraSetup c;
  c.name = "gimbal";
  c.intrinsics.width = 640;
  c.intrinsics.height = 480;
  c.intrinsics.fx = c.intrinsics.fy = 500.0;
  c.intrinsics.cx = 319.5;
  c.intrinsics.cy = 239.5;
  c.noise_sigma = 2.0;
  return c;
}

// A camera 2 m up, looking north and 8 degrees down.
Eigen::Isometry3d CameraPose() {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  EulerAngles e;
  e.theta = -8.0 * M_PI / 180.0;
  T.linear() = RotationNBFromEuler(e) * RotationBCForward();
  T.translation() = Eigen::Vector3d(0, 0, -2);
  return T;
}

struct Sequence {
  std::vector<cv::Mat> images;
  std::vector<cv::Rect> truth;  // exact box of the target per frame
};

enum class Target { kBall, kCar };
const char* TargetName(Target t) { return t == Target::kBall ? "ball" : "car"; }

// Frames at 10 Hz of the target crossing the view on grass among grey people and poles. With
// `jump_after` >= 0 the clock skips 2 s after that frame (the target leaps across the image).
Sequence Render(Target target, int frames, int jump_after = -1) {
  world::Scene scene(11);
  world::GroundSpec ground;
  ground.material = "grass";
  scene.SetGround(ground);
  scene.AddPerson(Eigen::Vector3d(14, 3, 0), 1.75);
  scene.AddPerson(Eigen::Vector3d(16, -4, 0), 1.8);
  scene.AddCylinder("pole", Eigen::Vector3d(18, 1, 0), 0.15, 5, "concrete");
  scene.AddTree(Eigen::Vector3d(30, -6, 0), 8, 2.5);
  int id = 0;
  world::ObjectPath path;
  path.loop = false;
  if (target == Target::kBall) {
    id = scene.AddSphere("ball", Eigen::Vector3d(10, -3, -0.35), 0.35, "red");
    path.waypoints_NE = {{10, -3}, {10, 3}};
    path.speed_mps = 0.8;  // 4 px per frame at 10 m
  } else {
    id = scene.AddBox("car", Eigen::Vector3d(20, -5, -0.75), Eigen::Vector3d(1.8, 4.2, 1.5), 0.0, "blue");
    path.waypoints_NE = {{20, -5}, {20, 5}};
    path.speed_mps = 1.5;  // 3.75 px per frame at 20 m
  }
  scene.SetPath(id, path);
  const world::Renderer renderer(scene, TestCamera());
  Sequence s;
  int64_t utime = 0;
  for (int k = 0; k < frames; ++k) {
    const world::Frame f = renderer.Render(CameraPose(), utime);
    s.images.push_back(f.image);
    s.truth.push_back(world::ObjectBox(f, id));
    utime += 100'000;
    if (k == jump_after) utime += 2'000'000;
  }
  return s;
}

const Sequence& Cached(Target target) {
  static std::map<Target, Sequence> cache;
  auto it = cache.find(target);
  if (it == cache.end()) it = cache.emplace(target, Render(target, 60)).first;
  return it->second;
}

double CentreError(const TrackResult& r, const cv::Rect& truth) {
  const cv::Point2f c(truth.x + 0.5f * (truth.width - 1), truth.y + 0.5f * (truth.height - 1));
  return std::hypot(r.box.center.x - c.x, r.box.center.y - c.y);
}

struct Case {
  TrackerKind kind;
  Target target;
};
void PrintTo(const Case& c, std::ostream* os) { *os << Name(c.kind) << " on the " << TargetName(c.target); }

class TrackerAccuracy : public ::testing::TestWithParam<Case> {};

TEST_P(TrackerAccuracy, SlowMotionCentreError) {
  const Case c = GetParam();
  const Sequence& s = Cached(c.target);
  TrackerParams p;
  p.kind = c.kind;
  TargetTracker tracker(p);
  tracker.Start(s.images[0], 0.0, s.truth[0]);
  std::vector<double> errors, ms;
  int losses = 0;
  TrackState last = TrackState::kTracking;
  for (std::size_t k = 1; k < s.images.size(); ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    const TrackResult r = tracker.Update(s.images[k], 0.1 * k);
    ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
    if (r.state == TrackState::kLost && last != TrackState::kLost) ++losses;
    last = r.state;
    errors.push_back(CentreError(r, s.truth[k]));
  }
  std::sort(errors.begin(), errors.end());
  std::sort(ms.begin(), ms.end());
  const double median = errors[errors.size() / 2];
  std::printf("[ table ] %s %s: centre error median %.2f px, p90 %.2f px, max %.2f px, losses %d, %.2f ms/frame\n",
              Name(c.kind), TargetName(c.target), median, errors[errors.size() * 9 / 10], errors.back(), losses,
              ms[ms.size() / 2]);
  if (c.kind == TrackerKind::kCamShift) {
    EXPECT_LT(median, 2.0);  // thesis 3.7.3: under 2 px for slow motion
    EXPECT_EQ(losses, 0);
  }
}

INSTANTIATE_TEST_SUITE_P(Trackers, TrackerAccuracy,
                         ::testing::Values(Case{TrackerKind::kCamShift, Target::kBall}, Case{TrackerKind::kCorrelation, Target::kBall},
                                           Case{TrackerKind::kKcf, Target::kBall}, Case{TrackerKind::kCsrt, Target::kBall},
                                           Case{TrackerKind::kCamShift, Target::kCar}, Case{TrackerKind::kCorrelation, Target::kCar},
                                           Case{TrackerKind::kKcf, Target::kCar}, Case{TrackerKind::kCsrt, Target::kCar}),
                         [](const auto& info) {
                           return std::string(Name(info.param.kind)) + "_" + TargetName(info.param.target);
                         });

// Thesis 3.7.3: after a sudden jump the box drifts, then reconverges. Ours re-locks (centre
// within 3 px) within 10 frames, both with the adaptive and the static window.
TEST(TrackerJump, RelocksWithinTenFrames) {
  const Sequence s = Render(Target::kBall, 30, 9);
  for (SearchWindowMode mode : {SearchWindowMode::kAdaptive, SearchWindowMode::kStatic}) {
    TrackerParams p;
    p.window = mode;
    TargetTracker tracker(p);
    tracker.Start(s.images[0], 0.0, s.truth[0]);
    int relocked_after = -1;
    for (std::size_t k = 1; k < s.images.size(); ++k) {
      const TrackResult r = tracker.Update(s.images[k], 0.1 * k);
      const double e = CentreError(r, s.truth[k]);
      if (k < 10) {
        EXPECT_LT(e, 3.0) << Name(mode) << " frame " << k;
      }
      if (k >= 10 && relocked_after < 0 && e < 3.0 && r.state == TrackState::kTracking) relocked_after = static_cast<int>(k - 10);
    }
    std::printf("[ jump ] %s window: re-locked %d frame(s) after the jump\n", Name(mode), relocked_after);
    EXPECT_GE(relocked_after, 0) << Name(mode);
    EXPECT_LE(relocked_after, 10) << Name(mode);
  }
}

// The target leaves the image: the tracker says lost instead of holding on to the background,
// and finds it again when it comes back.
TEST(TrackerLoss, TargetLeavingIsLostAndFoundAgain) {
  const Sequence& s = Cached(Target::kBall);
  TargetTracker tracker(TrackerParams{});
  tracker.Start(s.images[0], 0.0, s.truth[0]);
  // A frame with the ball painted over by grass from elsewhere in the same image.
  cv::Mat hidden = s.images[1].clone();
  const cv::Rect b = s.truth[1];
  const cv::Rect grass(b.x, std::min(hidden.rows - b.height, b.y + 3 * b.height), b.width, b.height);
  s.images[1](grass).copyTo(hidden(b));
  TrackResult r;
  for (int k = 1; k <= 5; ++k) r = tracker.Update(hidden, 0.1 * k);
  EXPECT_EQ(r.state, TrackState::kLost);
  EXPECT_LT(r.confidence, TrackerParams{}.lost_confidence);
  r = tracker.Update(s.images[2], 0.6);
  EXPECT_EQ(r.state, TrackState::kTracking);
  EXPECT_LT(CentreError(r, s.truth[2]), 3.0);
}

// Loss is a time, not a frame count: at 30 frames/s, 5 hidden frames (0.17 s, a runner behind a
// pole) are not yet a loss; hidden for 0.3 s the target is lost, as after 3 frames at 10 Hz.
// A frame time that is not finite or goes back is refused.
TEST(TrackerLoss, LossComesAfterATimeWhateverTheFrameRate) {
  const Sequence& s = Cached(Target::kBall);
  cv::Mat hidden = s.images[1].clone();
  const cv::Rect b = s.truth[1];
  const cv::Rect grass(b.x, std::min(hidden.rows - b.height, b.y + 3 * b.height), b.width, b.height);
  s.images[1](grass).copyTo(hidden(b));
  TargetTracker tracker(TrackerParams{});
  tracker.Start(s.images[0], 0.0, s.truth[0]);
  const double period = 1.0 / 30;
  TrackResult r;
  for (int k = 1; k <= 5; ++k) r = tracker.Update(hidden, k * period);
  EXPECT_LT(r.confidence, TrackerParams{}.lost_confidence);
  EXPECT_EQ(r.state, TrackState::kTracking) << "lost after 5 frames at 30 frames/s";
  for (int k = 6; k <= 8; ++k) r = tracker.Update(hidden, k * period);
  EXPECT_EQ(r.state, TrackState::kTracking) << "lost after 0.27 s";
  r = tracker.Update(hidden, 9 * period);
  EXPECT_EQ(r.state, TrackState::kLost) << "not lost after 0.3 s";
  EXPECT_THROW(tracker.Update(s.images[2], 0.1), std::invalid_argument);
  EXPECT_THROW(tracker.Update(s.images[2], std::nan("")), std::invalid_argument);
  TargetTracker fresh(TrackerParams{});
  EXPECT_THROW(fresh.Start(s.images[0], std::numeric_limits<double>::infinity(), s.truth[0]), std::invalid_argument);
}

// A target with no colour: a grey van seen from above (dark body, lighter windscreen and roof
// panels) on grey gravel, driving right and growing 0.6 % a frame (35 % in 50 frames) as the
// camera descends, hidden for 6 frames on the way (under a bridge).
// The exact box is known in every frame. The default tracker takes it to the correlation filter,
// which holds it by its texture, follows the growth, says lost while it is hidden and relocks
// where it reappears.
TEST(TrackerCorrelation, FollowsAGreyTargetThroughGrowthAndOcclusion) {
  cv::RNG rng(7);
  const auto texture = [&](cv::Size size, int blur) {
    cv::Mat t(size, CV_8U);
    rng.fill(t, cv::RNG::UNIFORM, 60, 200);
    cv::GaussianBlur(t, t, cv::Size(0, 0), blur);
    cv::normalize(t, t, 70, 190, cv::NORM_MINMAX);
    return t;
  };
  const cv::Mat background = texture(cv::Size(640, 480), 2);
  cv::Mat plate(80, 120, CV_8U, cv::Scalar(95));
  cv::rectangle(plate, cv::Rect(8, 8, 24, 64), cv::Scalar(150), -1);    // windscreen
  cv::rectangle(plate, cv::Rect(44, 14, 30, 52), cv::Scalar(125), -1);  // roof panels
  cv::rectangle(plate, cv::Rect(80, 14, 30, 52), cv::Scalar(125), -1);
  cv::line(plate, cv::Point(40, 4), cv::Point(40, 76), cv::Scalar(60), 2);
  constexpr int kFrames = 50, kHiddenFrom = 30, kHiddenTo = 36;
  const auto truth = [](int k) {
    const double s = std::pow(1.006, k);
    return cv::Rect(static_cast<int>(200 + 3 * k - 30 * s), static_cast<int>(240 - 20 * s), static_cast<int>(60 * s),
                    static_cast<int>(40 * s));
  };
  const auto frame = [&](int k) {
    cv::Mat grey = background.clone();
    if (k < kHiddenFrom || k >= kHiddenTo) {
      cv::Mat resized;
      cv::resize(plate, resized, truth(k).size(), 0, 0, cv::INTER_AREA);
      resized.copyTo(grey(truth(k)));
    }
    cv::Mat bgr;
    cv::cvtColor(grey, bgr, cv::COLOR_GRAY2BGR);
    return bgr;
  };
  TargetTracker tracker(TrackerParams{});
  tracker.Start(frame(0), 0.0, truth(0));
  ASSERT_EQ(tracker.method(), TrackerKind::kCorrelation) << tracker.method_reason();
  const auto iou = [](const TrackResult& r, const cv::Rect& t) {
    const cv::Rect2d b = r.box.boundingRect2f();
    const double inter = (b & cv::Rect2d(t)).area();
    return inter / (b.area() + t.area() - inter);
  };
  int relocked = -1;
  TrackState during = TrackState::kIdle;
  for (int k = 1; k < kFrames; ++k) {
    const TrackResult r = tracker.Update(frame(k), 0.1 * k);
    if (k < kHiddenFrom) {
      EXPECT_EQ(r.state, TrackState::kTracking) << "frame " << k;
      EXPECT_GT(iou(r, truth(k)), 0.8) << "frame " << k;
    } else if (k < kHiddenTo) {
      during = r.state;
    } else if (relocked < 0 && r.state == TrackState::kTracking && iou(r, truth(k)) > 0.7) {
      relocked = k - kHiddenTo;
    }
    if (k == kFrames - 1) {
      std::printf("[ dcf ] last frame: box %.1f x %.1f for %d x %d, IoU %.2f; relocked %d frame(s) after reappearing\n",
                  r.box.size.width, r.box.size.height, truth(k).width, truth(k).height, iou(r, truth(k)), relocked);
      EXPECT_NEAR(r.box.size.width / truth(k).width, 1.0, 0.1);
      EXPECT_GT(iou(r, truth(k)), 0.8);
    }
  }
  EXPECT_EQ(during, TrackState::kLost);
  EXPECT_GE(relocked, 0);
  EXPECT_LE(relocked, 2);
}

// A runner seen from above (blue shirt, dark trousers, the shirt's folds and arms giving it
// shape) on yellow-green grass with its own texture; the exact box is known. `at` is its box.
struct Field {
  cv::Mat grass;
  cv::Mat runner;  // BGR, the box's size
  explicit Field(cv::Size size) {
    cv::RNG rng(5);
    cv::Mat noise(size, CV_32FC3);
    rng.fill(noise, cv::RNG::NORMAL, 0, 30);
    cv::GaussianBlur(noise, noise, cv::Size(0, 0), 3);
    cv::Mat base(size, CV_32FC3, cv::Scalar(60, 150, 160));  // BGR: dry grass
    cv::Mat f = base + noise;
    f.convertTo(grass, CV_8UC3);
    runner = cv::Mat(64, 28, CV_8UC3, cv::Scalar(60, 150, 160));
    cv::ellipse(runner, cv::Point(14, 7), cv::Size(6, 7), 0, 0, 360, cv::Scalar(60, 90, 150), -1);     // head
    cv::rectangle(runner, cv::Rect(4, 14, 20, 24), cv::Scalar(170, 60, 40), -1);                      // shirt
    cv::line(runner, cv::Point(14, 16), cv::Point(14, 36), cv::Scalar(120, 40, 30), 2);                // fold
    cv::rectangle(runner, cv::Rect(6, 38, 7, 24), cv::Scalar(40, 35, 35), -1);                        // legs
    cv::rectangle(runner, cv::Rect(15, 38, 7, 24), cv::Scalar(40, 35, 35), -1);
  }
  cv::Mat Frame(const std::vector<cv::Point>& at) const {
    cv::Mat f = grass.clone();
    for (const cv::Point& p : at) {
      cv::Mat mask;
      cv::inRange(runner, cv::Scalar(60, 150, 160), cv::Scalar(60, 150, 160), mask);
      runner.copyTo(f(cv::Rect(p, runner.size())), ~mask);
    }
    return f;
  }
  cv::Rect Box(cv::Point p) const { return cv::Rect(p, runner.size()); }
};

double Iou(const TrackResult& r, const cv::Rect& t) {
  const cv::Rect2d b = r.box.boundingRect2f();
  const double inter = (b & cv::Rect2d(t)).area();
  return inter / (b.area() + t.area() - inter);
}

// Drift: the runner jumps 300 px (the video skipped, the camera swung) while the grass where it
// was stays, textured and static, just what a correlation filter on shape holds on to with a
// high peak. The selection's colours are now elsewhere: the box says lost within the loss time
// (0.3 s) instead of tracking grass, and the whole image is searched, where the one blue shirt
// on the field is found again.
TEST(TrackerCorrelation, DriftOntoTheBackgroundIsLostAndTheTargetFoundElsewhere) {
  const Field field(cv::Size(640, 480));
  constexpr int kJumpAt = 15, kFrames = 35;
  const auto where = [](int k) { return k < kJumpAt ? cv::Point(100 + 3 * k, 200 + k) : cv::Point(420 + 3 * (k - kJumpAt), 80 + 2 * (k - kJumpAt)); };
  TrackerParams p;
  p.kind = TrackerKind::kCorrelation;
  TargetTracker tracker(p);
  tracker.Start(field.Frame({where(0)}), 0.0, field.Box(where(0)));
  int lost_at = -1, found_at = -1;
  for (int k = 1; k < kFrames; ++k) {
    const TrackResult r = tracker.Update(field.Frame({where(k)}), 0.1 * k);
    const double iou = Iou(r, field.Box(where(k)));
    if (k < kJumpAt) {
      EXPECT_EQ(r.state, TrackState::kTracking) << "frame " << k;
      EXPECT_GT(iou, 0.6) << "frame " << k;
      continue;
    }
    if (lost_at < 0 && r.state == TrackState::kLost) {
      lost_at = k;
      EXPECT_NE(r.lost_reason.find("colours left the box"), std::string::npos) << r.lost_reason;
    }
    if (found_at < 0 && r.state == TrackState::kTracking && iou > 0.5) found_at = k;
    // Never tracking the grass past the loss time.
    if (r.state == TrackState::kTracking && k > kJumpAt + 3) {
      EXPECT_GT(iou, 0.5) << "frame " << k << " tracks the grass";
    }
  }
  std::printf("[ drift ] runner jumped at frame %d: lost at %d, found again at %d\n", kJumpAt, lost_at, found_at);
  EXPECT_GE(found_at, kJumpAt);
  EXPECT_LE(found_at, kJumpAt + 8);
  if (found_at > kJumpAt) {  // not relocked at once: it said lost in between
    EXPECT_GE(lost_at, kJumpAt);
    EXPECT_LE(lost_at, found_at);
  }
}

// Among look-alikes a lost target is not taken back by colour: two runners in the same shirt,
// the tracked one hidden (painted over by grass). The tracker says lost and stays lost while it is
// hidden, rather than jumping to the other runner 250 px away; when it comes back where it was,
// the track is taken up again.
TEST(TrackerCorrelation, ALostTargetAmongLookAlikesStaysLostUntilItReturns) {
  const Field field(cv::Size(640, 480));
  const cv::Point other(450, 300);
  const auto where = [](int k) { return cv::Point(120 + 2 * k, 150); };
  TrackerParams p;
  p.kind = TrackerKind::kCorrelation;
  TargetTracker tracker(p);
  tracker.Start(field.Frame({where(0), other}), 0.0, field.Box(where(0)));
  constexpr int kHideFrom = 10, kHideTo = 20, kFrames = 26;
  bool lost = false;
  int back_at = -1;
  for (int k = 1; k < kFrames; ++k) {
    const bool hidden = k >= kHideFrom && k < kHideTo;
    const TrackResult r = tracker.Update(hidden ? field.Frame({other}) : field.Frame({where(k), other}), 0.1 * k);
    EXPECT_LT(Iou(r, field.Box(other)), 0.1) << "frame " << k << ": took the other runner";
    if (hidden && k >= kHideFrom + 4) {  // 0.3 s and a frame
      EXPECT_EQ(r.state, TrackState::kLost) << "frame " << k;
      EXPECT_FALSE(r.lost_reason.empty());
      lost = lost || r.state == TrackState::kLost;
    }
    if (!hidden && k >= kHideTo && back_at < 0 && r.state == TrackState::kTracking && Iou(r, field.Box(where(k))) > 0.5) back_at = k;
  }
  std::printf("[ look-alike ] lost while hidden: %s; taken up again at frame %d (back at %d)\n", lost ? "yes" : "no", back_at, kHideTo);
  EXPECT_TRUE(lost);
  EXPECT_GE(back_at, kHideTo);
  EXPECT_LE(back_at, kHideTo + 3);
}

// Any box the tracker accepts, in any image, tracks through frames of anything without a fault
// and with a finite box: boxes touching the edges, the whole image, 4 px in a 6 px image, frames
// of noise, of one colour, of black.
TEST(TrackerCorrelation, AnyAcceptedBoxTracksAnyFramesWithoutFault) {
  cv::RNG rng(3);
  for (int trial = 0; trial < 40; ++trial) {
    const cv::Size size(6 + rng.uniform(0, 200), 6 + rng.uniform(0, 150));
    cv::Mat first(size, CV_8UC3);
    rng.fill(first, cv::RNG::UNIFORM, 0, 256);
    const int w = rng.uniform(4, size.width + 1), h = rng.uniform(4, size.height + 1);
    const cv::Rect2d box(rng.uniform(0, size.width - w + 1), rng.uniform(0, size.height - h + 1), w, h);
    TrackerParams p;
    p.kind = TrackerKind::kCorrelation;
    TargetTracker tracker(p);
    ASSERT_NO_THROW(tracker.Start(first, 0.0, box)) << size << " " << box;
    for (int k = 1; k <= 8; ++k) {
      cv::Mat frame(size, CV_8UC3);
      if (k % 3 == 0)
        frame.setTo(cv::Scalar(rng.uniform(0, 256), rng.uniform(0, 256), rng.uniform(0, 256)));
      else if (k % 4 == 0)
        frame.setTo(cv::Scalar::all(0));
      else
        rng.fill(frame, cv::RNG::UNIFORM, 0, 256);
      const TrackResult r = tracker.Update(frame, 0.1 * k);
      ASSERT_TRUE(std::isfinite(r.box.center.x) && std::isfinite(r.box.center.y) && std::isfinite(r.confidence))
          << size << " " << box << " frame " << k;
      ASSERT_TRUE(r.confidence >= 0 && r.confidence <= 1);
      ASSERT_EQ(r.state == TrackState::kLost, !r.lost_reason.empty());
    }
  }
}

TEST(TrackerBadInput, SelectionsAreRefusedNamingWhy) {
  const Sequence& s = Cached(Target::kBall);
  const cv::Mat& image = s.images[0];
  auto refusal = [&](const cv::Rect2d& box, const cv::Mat& img, TrackerKind kind = TrackerKind::kAuto) {
    TrackerParams p;
    p.kind = kind;
    TargetTracker t(p);
    try {
      t.Start(img, 0.0, box);
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(t.state(), TrackState::kIdle);
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_NE(refusal(cv::Rect2d(700, 100, 40, 40), image).find("outside"), std::string::npos);
  EXPECT_NE(refusal(cv::Rect2d(100, 100, 2, 40), image).find("smaller"), std::string::npos);
  EXPECT_NE(refusal(cv::Rect2d(std::nan(""), 100, 20, 20), image).find("not finite"), std::string::npos);
  EXPECT_NE(refusal(cv::Rect2d(10, 10, 20, 20), cv::Mat()).find("empty"), std::string::npos);
  // A grey patch has no hue for CamShift to track; the default (auto) tracks it by its shape.
  cv::Mat grey(480, 640, CV_8UC3, cv::Scalar(120, 124, 126));
  EXPECT_NE(refusal(cv::Rect2d(100, 100, 40, 20), grey, TrackerKind::kCamShift).find("too little colour"), std::string::npos);
  cv::rectangle(grey, cv::Rect(100, 100, 40, 20), cv::Scalar(60, 62, 64), -1);
  EXPECT_EQ(refusal(cv::Rect2d(100, 100, 40, 20), grey), "accepted");
  EXPECT_EQ(refusal(s.truth[0], image), "accepted");
  TargetTracker t(TrackerParams{});
  t.Start(image, 0.0, s.truth[0]);
  cv::Mat small;
  cv::resize(image, small, cv::Size(320, 240));
  EXPECT_THROW(t.Update(small, 0.1), std::invalid_argument);
  TrackerParams bad;
  bad.hue_bins = 0;
  EXPECT_THROW(TargetTracker{bad}, std::invalid_argument);
  EXPECT_THROW(ParseTrackerKind("meanshift"), std::invalid_argument);
}

// The default tracker picks CamShift where the target's colour stands out (the rendered red ball
// and blue car on grass), the correlation filter where it does not (a dark grey box on grey), and
// says why.
TEST(TrackerAuto, PicksCamShiftForColourAndTheCorrelationFilterWithout) {
  for (Target target : {Target::kBall, Target::kCar}) {
    const Sequence& s = Cached(target);
    TargetTracker t(TrackerParams{});
    t.Start(s.images[0], 0.0, s.truth[0]);
    EXPECT_EQ(t.method(), TrackerKind::kCamShift) << TargetName(target) << ": " << t.method_reason();
    EXPECT_NE(t.method_reason().find("the target's colour stands out"), std::string::npos);
    std::printf("[ auto ] %s: %s\n", TargetName(target), t.method_reason().c_str());
  }
  cv::Mat grey(240, 320, CV_8UC3, cv::Scalar(120, 124, 126));
  cv::rectangle(grey, cv::Rect(100, 100, 40, 20), cv::Scalar(60, 62, 64), -1);
  TargetTracker t(TrackerParams{});
  t.Start(grey, 0.0, cv::Rect2d(100, 100, 40, 20));
  EXPECT_EQ(t.method(), TrackerKind::kCorrelation);
  EXPECT_NE(t.method_reason().find("too little colour"), std::string::npos) << t.method_reason();
  cv::Mat moved = cv::Mat(240, 320, CV_8UC3, cv::Scalar(120, 124, 126));
  cv::rectangle(moved, cv::Rect(104, 102, 40, 20), cv::Scalar(60, 62, 64), -1);
  const TrackResult r = t.Update(moved, 0.1);
  EXPECT_EQ(r.state, TrackState::kTracking);
  EXPECT_NEAR(r.box.center.x, 124, 2.0);
  EXPECT_NEAR(r.box.center.y, 112, 2.0);
}

}  // namespace
}  // namespace uav::vision
