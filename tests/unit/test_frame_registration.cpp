// Frame-to-frame registration (thesis 6.2-6.3) on rendered village frames, against the exact
// ground-plane correspondence from the renderer's depth: parameterised over height and motion.
#include <algorithm>
#include <cmath>
#include <string>
#include <tuple>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/vision/frame_registration.hpp"
#include "uav/world/renderer.hpp"

namespace uav::vision {
namespace {

const world::Scene& Village() {
  static const world::Scene scene =
      world::Scene::LoadFile(std::string(UAV_RESOURCE_DIR) + "/scenes/survey_village.scene.json");
  return scene;
}

Eigen::Isometry3d CameraPose(const world::CameraSetup& cam, double n, double e, double altitude, double yaw) {
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  EulerAngles a;
  a.psi = yaw;
  T_NB.linear() = RotationNBFromEuler(a);
  T_NB.translation() = Eigen::Vector3d(n, e, -altitude);
  return T_NB * cam.T_BC;
}

cv::Mat Grey(const cv::Mat& bgr) {
  cv::Mat g;
  cv::cvtColor(bgr, g, cv::COLOR_BGR2GRAY);
  return g;
}

struct MotionCase {
  double altitude_m, dn_m, de_m, dyaw_deg, dt_s;
};
void PrintTo(const MotionCase& c, std::ostream* os) {
  *os << c.altitude_m << " m, moved " << c.dn_m << "," << c.de_m << " m, yaw " << c.dyaw_deg << " deg";
}

class FrameRegistrationAccuracy : public ::testing::TestWithParam<std::tuple<MotionCase, Detector>> {};

TEST_P(FrameRegistrationAccuracy, GroundMatchesTheTrueHomography) {
  const MotionCase& c = std::get<0>(GetParam());
  RegistrationParams params;
  params.detector = std::get<1>(GetParam());
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  const Eigen::Isometry3d T_prev = CameraPose(cam, 10, 20, c.altitude_m, 0.3);
  const Eigen::Isometry3d T_cur = CameraPose(cam, 10 + c.dn_m, 20 + c.de_m, c.altitude_m, 0.3 + c.dyaw_deg * M_PI / 180);
  const world::Frame prev = renderer.Render(T_prev, 1'000'000);
  const world::Frame cur = renderer.Render(T_cur, 1'000'000 + static_cast<int64_t>(c.dt_s * 1e6));
  const Registration r = FrameRegistration(params).Register(Grey(prev.image), Grey(cur.image));
  ASSERT_TRUE(r.ok) << r.failure;

  // Truth on a grid of ground pixels: back-project with the exact depth, project into prev.
  const CameraIntrinsics& k = cam.intrinsics;
  std::vector<double> errors;
  for (int v = 8; v < cur.depth.rows; v += 16)
    for (int u = 8; u < cur.depth.cols; u += 16) {
      if (cur.object_id.at<uint16_t>(v, u) != world::kGroundId) continue;
      const double z = cur.depth.at<float>(v, u);
      const Eigen::Vector3d p_N = T_cur * Eigen::Vector3d((u - k.cx) / k.fx * z, (v - k.cy) / k.fy * z, z);
      const Eigen::Vector3d p_prev = T_prev.inverse() * p_N;
      const Eigen::Vector2d truth = Project(k, p_prev);
      if (truth.x() < 0 || truth.y() < 0 || truth.x() > k.width - 1 || truth.y() > k.height - 1) continue;
      const Eigen::Vector3d h = r.H_prev_cur * Eigen::Vector3d(u, v, 1);
      errors.push_back((h.head<2>() / h.z() - truth).norm());
    }
  ASSERT_GT(errors.size(), 200u);
  std::sort(errors.begin(), errors.end());
  const double median = errors[errors.size() / 2], p90 = errors[errors.size() * 9 / 10];
  std::printf("[ register ] %s %.0f m: %d corners, %d tracked, %d inliers; ground error median %.3f px, 90%% %.3f px\n",
              DetectorName(params.detector), c.altitude_m, r.corners, r.tracked, r.inliers, median, p90);
  EXPECT_LT(median, 0.5);
  EXPECT_LT(p90, 1.5);
}

// 40 m at 5 Hz and ~30 m/s, for GFTT + KLT and SIFT + FLANN. FAST + ORB matches mostly roofs
// and crowns here (ground error median 5.6 px): see FastOrbRegistersTheVillage. Lower flights (20 m: 90 %
// error 1.8 px; 10 m: no registration) and cloud shadows that moved between the frames (median
// 3.7 px) do not meet these limits yet.
INSTANTIATE_TEST_SUITE_P(
    Village, FrameRegistrationAccuracy,
    ::testing::Combine(::testing::Values(MotionCase{40, 6, 1, 3, 0.2}, MotionCase{40, -5, 2, -2, 0.2}),
                       ::testing::Values(Detector::kGfttKlt, Detector::kSiftFlann)),
    [](const auto& info) {
      return std::string(DetectorName(std::get<1>(info.param))) + "_case" + std::to_string(info.index);
    });

// The third detector of Table 6.1 registers the same pair within Algorithm 1's checks; its
// accuracy over the ground is the study's finding, not a pass mark (docs/modules/stitching.md).
TEST(FrameRegistration, FastOrbRegistersTheVillage) {
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  const world::Frame a = renderer.Render(CameraPose(cam, 10, 20, 40, 0.3), 1'000'000);
  const world::Frame b = renderer.Render(CameraPose(cam, 16, 21, 40, 0.35), 1'200'000);
  RegistrationParams p;
  p.detector = Detector::kFastOrb;
  const Registration r = FrameRegistration(p).Register(Grey(a.image), Grey(b.image));
  EXPECT_TRUE(r.ok) << r.failure;
  EXPECT_GT(r.inliers, 50);
}

// Features found once serve every partner: a selection keeps their order (strongest first for
// corners) and their descriptors, the pairs come from the selection only, and registering with
// the features found beforehand is registering.
class FeaturesFoundOnce : public ::testing::TestWithParam<Detector> {};

TEST_P(FeaturesFoundOnce, ServeEveryPartner) {
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  const cv::Mat a = Grey(renderer.Render(CameraPose(cam, 10, 20, 40, 0.3), 1'000'000).image);
  const cv::Mat b = Grey(renderer.Render(CameraPose(cam, 16, 21, 40, 0.35), 1'200'000).image);
  RegistrationParams p;
  p.detector = GetParam();
  const FrameRegistration reg(p);
  const FrameFeatures all = reg.Features(a);
  ASSERT_GT(all.points.size(), 100u);
  auto left = [&](const cv::Point2f& q) { return q.x < a.cols / 2; };
  const FrameFeatures half = all.Select(left, 60);
  ASSERT_EQ(half.points.size(), 60u);
  size_t next = 0;  // the selection is the first 60 on the left, in order
  for (const cv::Point2f& q : half.points) {
    while (!(all.points[next] == q)) ASSERT_FALSE(left(all.points[next++]));
    ++next;
  }
  if (p.detector != Detector::kGfttKlt) {
    ASSERT_EQ(half.descriptors.rows, 60);
    const size_t i = std::find(all.points.begin(), all.points.end(), half.points[7]) - all.points.begin();
    EXPECT_EQ(cv::norm(half.descriptors.row(7), all.descriptors.row(static_cast<int>(i)), cv::NORM_L1), 0.0);
  }
  const FeatureMatches m = reg.Match(a, half, b);
  EXPECT_TRUE(m.failure.empty()) << m.failure;
  EXPECT_GE(m.prev.size(), 30u);
  for (const cv::Point2f& q : m.prev) EXPECT_TRUE(left(q));
  const Registration once = reg.Register(a, all, b), again = reg.Register(a, b);
  ASSERT_TRUE(once.ok) << once.failure;
  ASSERT_TRUE(again.ok) << again.failure;
  // The same up to RANSAC's and FLANN's random draws: the image corners land within 0.5 px.
  for (const Eigen::Vector3d& q : {Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(a.cols - 1, 0, 1),
                                  Eigen::Vector3d(0, a.rows - 1, 1), Eigen::Vector3d(a.cols - 1, a.rows - 1, 1)}) {
    const Eigen::Vector3d x = once.H_prev_cur * q, y = again.H_prev_cur * q;
    EXPECT_LT((x.hnormalized() - y.hnormalized()).norm(), 0.5);
  }
}
INSTANTIATE_TEST_SUITE_P(FrameRegistration, FeaturesFoundOnce, ::testing::Values(Detector::kGfttKlt, Detector::kSiftFlann),
                         [](const ::testing::TestParamInfo<Detector>& i) { return std::string(DetectorName(i.param)); });

TEST(FrameRegistration, FailsWithAReasonWhenFramesDoNotOverlap) {
  const world::CameraSetup& cam = *Village().downward_camera();
  const world::Renderer renderer(Village(), cam);
  const world::Frame a = renderer.Render(CameraPose(cam, 0, 0, 30, 0), 0);
  const world::Frame b = renderer.Render(CameraPose(cam, 150, 80, 30, 1.0), 0);
  const Registration r = FrameRegistration().Register(Grey(a.image), Grey(b.image));
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.failure.empty());
}

TEST(FrameRegistration, RejectsBadParametersAndImages) {
  RegistrationParams p;
  p.max_area_change = 0;
  EXPECT_THROW(FrameRegistration{p}, std::invalid_argument);
  p = RegistrationParams();
  p.min_inliers = 3;
  EXPECT_THROW(FrameRegistration{p}, std::invalid_argument);
  EXPECT_THROW(ParseDetector("surf"), std::invalid_argument);
  EXPECT_EQ(ParseDetector("orb"), Detector::kFastOrb);
  const FrameRegistration reg;
  const cv::Mat grey(480, 640, CV_8UC1, cv::Scalar(90));
  EXPECT_THROW(reg.Register(cv::Mat(), grey), std::invalid_argument);
  EXPECT_THROW(reg.Register(grey, cv::Mat(240, 320, CV_8UC1)), std::invalid_argument);
  EXPECT_THROW(reg.Register(grey, cv::Mat(480, 640, CV_8UC3)), std::invalid_argument);
  // A featureless frame has no corners: a failure, not an exception.
  const Registration r = reg.Register(grey, grey);
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.failure.find("corners"), std::string::npos);
}

}  // namespace
}  // namespace uav::vision
