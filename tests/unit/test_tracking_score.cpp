// OTB scoring (success AUC over IoU thresholds, precision at 20 px) on boxes with known overlaps;
// the real sequences are scored through uav-track --truth in tests/cli/uav_track_truth.sh.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>

#include "uav/vision/tracking_score.hpp"

namespace uav::vision {
namespace {

TEST(TrackingScore, ExactOverlapsGiveTheStepFunctionsArea) {
  // Four frames: perfect, half overlap (IoU 1/3), lost, and 25 px off with no overlap.
  const std::vector<cv::Rect2d> truth(4, cv::Rect2d(0, 0, 10, 10));
  const std::vector<std::optional<cv::Rect2d>> reported = {cv::Rect2d(0, 0, 10, 10), cv::Rect2d(5, 0, 10, 10),
                                                           std::nullopt, cv::Rect2d(25, 0, 10, 10)};
  const TrackingScore s = ScoreTracking(reported, truth);
  EXPECT_EQ(s.frames, 4);
  // Thresholds 0, 0.05, ..., 1: frame 1 exceeds all but 1.0 (20 of 21), frame 2 (IoU 1/3)
  // exceeds 0..0.30 (7 of 21): (20 + 7) / 21 / 4.
  EXPECT_NEAR(s.success_auc, (20.0 + 7.0) / 21.0 / 4.0, 1e-12);
  EXPECT_NEAR(s.precision_20px, 2.0 / 4.0, 1e-12);  // centres 0 and 5 px off; the lost frame and 25 px miss
  EXPECT_NEAR(s.mean_iou, (1.0 + 1.0 / 3.0) / 4.0, 1e-12);
  // Frames the tracker never reached count as lost; frames without a true box are not scored.
  std::vector<cv::Rect2d> absent = truth;
  absent[2] = cv::Rect2d();
  EXPECT_EQ(ScoreTracking({cv::Rect2d(0, 0, 10, 10)}, absent).frames, 3);
  EXPECT_NEAR(ScoreTracking({cv::Rect2d(0, 0, 10, 10)}, absent).success_auc, 20.0 / 21.0 / 3.0, 1e-12);
}

TEST(TrackingScore, OtbFilesReadWithAnySeparatorAndBadLinesAreNamed) {
  const std::string path = (std::filesystem::temp_directory_path() / "uav_test_otb.txt").string();
  std::ofstream(path) << "70,51,107,87\n71\t52\t100\t80\r\n72 53 0 0\n";
  const auto boxes = ReadOtbBoxes(path);
  ASSERT_EQ(boxes.size(), 3u);
  EXPECT_EQ(boxes[1], cv::Rect2d(71, 52, 100, 80));
  EXPECT_EQ(boxes[2].area(), 0.0);
  std::ofstream(path) << "70,51,107,87\n70,51,nan,87\n";
  try {
    ReadOtbBoxes(path);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(path + ":2: expected x,y,w,h"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace uav::vision
