#pragma once
// Stereo calibration from chessboard pairs (thesis 3.3: the rig's intrinsics, distortion and
// relative pose, behind the rectification of 3.5), and the calibration file: OpenCV
// FileStorage YAML or XML (chosen by the extension) with image_width, image_height, K1, D1,
// K2, D2 and R, T in OpenCV's convention (p_R = R p_L + T, metres), plus rms_px.
#include <string>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct ChessboardSpec {
  int cols = 9;          // inner corners along a row
  int rows = 6;          // inner corners along a column
  double square_m = 0.025;
  void Validate() const;  // throws std::invalid_argument naming the field
};

struct StereoCalibration {
  StereoRig rig;
  double rms_px = 0.0;              // stereo reprojection error
  std::vector<int> used_pairs;      // indices of pairs where both images showed the whole board
};

// Calibrates from pairs of images of the same size (8-bit grey or BGR). Pairs where either
// image does not show the whole board are skipped; at least 3 must remain. Throws
// std::invalid_argument naming what is wrong (sizes, too few boards, a failed fit).
StereoCalibration CalibrateStereo(const std::vector<cv::Mat>& left, const std::vector<cv::Mat>& right,
                                  const ChessboardSpec& board);

// Writes through a temporary name (.yml, .yaml or .json). Throws std::runtime_error naming the path.
void WriteStereoCalibration(const std::string& path, const StereoCalibration& calibration);
// Throws std::runtime_error naming the file and the missing or bad entry (a missing file, a
// non-finite or wrongly sized matrix, intrinsics out of range).
StereoCalibration ReadStereoCalibration(const std::string& path);

}  // namespace uav::vision
