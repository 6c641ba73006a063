#pragma once
// Scoring a tracker against ground-truth boxes, OTB's one-pass evaluation (Wu, Lim and Yang):
// per frame the overlap (intersection over union) of the reported and true boxes, 0 when the
// tracker reports the target lost or reports nothing; success AUC = the mean over IoU
// thresholds 0, 0.05, ..., 1 of the share of frames whose overlap exceeds the threshold;
// precision at 20 px = the share of frames whose box centre is within 20 px of the truth's.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core/types.hpp>

namespace uav::vision {

// OTB's groundtruth_rect.txt: one "x,y,w,h" per frame (commas, tabs or spaces), pixels, top-left
// corner. Throws std::runtime_error naming the file and line of a bad entry; a box without
// area (w or h <= 0: the target absent) is kept as an empty rectangle and not scored.
std::vector<cv::Rect2d> ReadOtbBoxes(const std::string& path);

struct TrackingScore {
  int frames = 0;                 // frames scored (with a true box of positive area)
  double success_auc = 0.0;       // 0..1
  double precision_20px = 0.0;    // 0..1
  double mean_iou = 0.0;
};

// `reported[i]`: the tracker's box in frame i, nullopt when lost, skipped or not reached.
// Frames beyond `reported` count as lost; `truth` decides how many frames there are.
TrackingScore ScoreTracking(const std::vector<std::optional<cv::Rect2d>>& reported,
                            const std::vector<cv::Rect2d>& truth);

}  // namespace uav::vision
