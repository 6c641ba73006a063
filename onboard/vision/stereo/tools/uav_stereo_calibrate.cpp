// uav-stereo-calibrate --board COLSxROWS --square M --out rig.yml LEFT1 RIGHT1 [LEFT2 RIGHT2 ...]
// Stereo calibration from chessboard pairs (thesis 3.3): images alternate left, right. Pairs
// where either image does not show the whole board are skipped and named. Writes the
// calibration file uav-stereo --calib reads (OpenCV YAML, XML or JSON by the extension) through
// a temporary name, and prints the RMS reprojection error and the baseline.
// Exit 0 on success, 1 when the images cannot be used (named; nothing written), 2 on bad options.
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/vision/stereo_calibration.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/image_files.hpp"

int main(int argc, char** argv) {
  CLI::App cli{"uav-stereo-calibrate: stereo calibration from chessboard pairs"};
  std::string board_text = "9x6", out;
  double square_m = 0.025;
  std::vector<std::string> images;
  cli.add_option("--board", board_text, "inner corners, COLSxROWS")->capture_default_str();
  cli.add_option("--square", square_m, "square size [m]")->capture_default_str();
  uav::OutputFile(cli.add_option("--out", out, "calibration file (.yml, .yaml, .json)"))->required();
  cli.add_option("images", images, "LEFT RIGHT pairs")->required();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  uav::vision::ChessboardSpec board;
  board.square_m = square_m;
  if (std::sscanf(board_text.c_str(), "%dx%d", &board.cols, &board.rows) != 2) {
    std::fprintf(stderr, "uav-stereo-calibrate: --board must be COLSxROWS, got '%s'\n", board_text.c_str());
    return 2;
  }
  if (images.size() % 2 != 0) {
    std::fprintf(stderr, "uav-stereo-calibrate: images come in LEFT RIGHT pairs; %zu given\n", images.size());
    return 2;
  }
  try {
    std::vector<cv::Mat> left, right;
    std::vector<std::string> kept;  // the pairs read whole, as LEFT RIGHT
    for (std::size_t i = 0; i + 1 < images.size(); i += 2) {
      cv::Mat pair[2];
      std::string problem;
      for (int k = 0; k < 2 && problem.empty(); ++k) {
        problem = uav::ImageFileProblem(images[i + k]);
        if (problem.empty() && (pair[k] = cv::imread(images[i + k], cv::IMREAD_GRAYSCALE)).empty())
          problem = "cannot read it as an image";
        if (!problem.empty()) problem = images[i + k] + ": " + problem;
      }
      if (!problem.empty()) {  // one bad file costs its pair, not the calibration
        std::fprintf(stderr, "uav-stereo-calibrate: skipped pair %s %s: %s\n", images[i].c_str(), images[i + 1].c_str(),
                     problem.c_str());
        continue;
      }
      left.push_back(pair[0]);
      right.push_back(pair[1]);
      kept.push_back(images[i]);
      kept.push_back(images[i + 1]);
    }
    images = kept;
    const uav::vision::StereoCalibration c = uav::vision::CalibrateStereo(left, right, board);
    std::vector<bool> used(left.size(), false);
    for (int i : c.used_pairs) used[static_cast<std::size_t>(i)] = true;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (!used[i]) std::fprintf(stderr, "uav-stereo-calibrate: board not found in pair %s %s; skipped\n",
                                 images[2 * i].c_str(), images[2 * i + 1].c_str());
    uav::vision::WriteStereoCalibration(out, c);
    const Eigen::Vector3d t = c.rig.T_LR.translation();
    std::printf("uav-stereo-calibrate: %zu of %zu pairs, RMS %.3f px, baseline %.4f m (right camera at %.4f %.4f %.4f), "
                "fx %.1f px, written to %s\n",
                c.used_pairs.size(), left.size(), c.rms_px, t.norm(), t.x(), t.y(), t.z(), c.rig.left.fx, out.c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stereo-calibrate: %s\n", e.what());
    return 1;
  }
  return 0;
}
