// uav-monodepth CAPTURE_DIR --out grid.csv [--poses POSES.csv] [--overlay DIR]
// Monocular depth from motion (thesis 3.4) on a capture folder written by the vehicle (images,
// captures.csv with the navigation solution per image, session.json with the camera): the 4x3
// depth grid per frame, one CSV row per cell. A frame whose navigation columns are not finite
// has its cells unknown with the reason, never a made-up depth.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/capture_folder.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/mono_depth.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

std::string Quoted(const std::string& s) {
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

// The frame with its features (green converged, grey not yet) and the grid: each cell's depth
// and state (red obstacle, green free, grey unknown).
cv::Mat Overlay(const cv::Mat& image, const uav::vision::DepthGrid& g, const std::vector<uav::vision::DepthFeature>& features) {
  cv::Mat out = image.clone();
  for (const auto& f : features)
    cv::circle(out, f.px, 2, f.converged ? cv::Scalar(60, 220, 60) : cv::Scalar(160, 160, 160), cv::FILLED);
  const int w = out.cols / g.cols, h = out.rows / g.rows;
  for (int r = 0; r < g.rows; ++r)
    for (int c = 0; c < g.cols; ++c) {
      const auto& cell = g.at(r, c);
      const cv::Scalar colour = cell.state == uav::vision::CellState::kObstacle ? cv::Scalar(40, 40, 230)
                                : cell.state == uav::vision::CellState::kFree   ? cv::Scalar(60, 200, 60)
                                                                                 : cv::Scalar(150, 150, 150);
      cv::rectangle(out, cv::Rect(c * w, r * h, w, h), colour, 1);
      char text[48];
      if (cell.state == uav::vision::CellState::kUnknown) std::snprintf(text, sizeof text, "?");
      else std::snprintf(text, sizeof text, "%.1f m (%d)", cell.depth_m, cell.features);
      cv::putText(out, text, cv::Point(c * w + 6, r * h + 22), cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
      cv::putText(out, text, cv::Point(c * w + 6, r * h + 22), cv::FONT_HERSHEY_SIMPLEX, 0.55, colour, 1, cv::LINE_AA);
    }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-monodepth: depth from motion (thesis 3.4) on a capture folder, as a 4x3 grid per frame"};
  std::string dir, out, poses_path, overlay_dir;
  cli.add_option("CAPTURE_DIR", dir, "folder of captures (images, captures.csv, session.json)")->required();
  uav::OutputFile(cli.add_option("--out", out, "CSV: frame,utime,file,row,col,state,depth_m,sigma_m,features,confidence,reason"))->required();
  cli.add_option("--poses", poses_path, "poses CSV (default CAPTURE_DIR/captures.csv)");
  cli.add_option("--overlay", overlay_dir, "write every frame with its features and grid drawn here");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    if (poses_path.empty()) poses_path = dir + "/captures.csv";
    const uav::CaptureSession session = uav::ReadCaptureSession(dir + "/session.json");
    const std::vector<uav::CaptureRow> rows = uav::ReadCaptureRows(poses_path);
    if (rows.empty()) throw std::invalid_argument(poses_path + ": no captures");
    if (!overlay_dir.empty()) std::filesystem::create_directories(overlay_dir);
    uav::vision::MonoDepthEstimator estimator(session.camera, uav::vision::MonoDepthParams{});
    std::ostringstream csv;
    csv << "frame,utime,file,row,col,state,depth_m,sigma_m,features,confidence,reason\n";
    std::vector<double> ms;
    int healthy = 0, known_cells = 0, first_all_known = -1;
    std::vector<std::string> skipped;  // named and left out, as a camera's dropped frame
    uav::ProgressBar progress(rows.size());
    for (size_t i = 0; i < rows.size(); ++i) {
      const uav::CaptureRow& c = rows[i];
      const std::string path = dir + "/" + c.file;
      std::string problem = uav::ImageFileProblem(path);
      cv::Mat image;
      if (problem.empty() && (image = cv::imread(path, cv::IMREAD_COLOR)).empty()) problem = "not an image OpenCV reads";
      if (!problem.empty()) {
        skipped.push_back(path + ": " + problem);
        std::fprintf(stderr, "\nuav-monodepth: skipped %s: %s\n", path.c_str(), problem.c_str());
        continue;
      }
      std::optional<Eigen::Isometry3d> T_NC;
      if (c.T_NB_estimate) T_NC = *c.T_NB_estimate * session.T_BC;
      const auto t0 = std::chrono::steady_clock::now();
      uav::vision::DepthGrid g = estimator.Update(image, c.utime, T_NC);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      if (!c.T_NB_estimate) g.reason = "no navigation sample: " + c.problem;
      healthy += g.healthy;
      int known = 0;
      for (int r = 0; r < g.rows; ++r)
        for (int col = 0; col < g.cols; ++col) {
          const auto& cell = g.at(r, col);
          known += cell.state != uav::vision::CellState::kUnknown;
          char num[128];
          std::snprintf(num, sizeof num, "%.3f,%.3f,%d,%.3f", cell.depth_m, cell.sigma_m, cell.features, cell.confidence);
          csv << i << ',' << c.utime << ',' << c.file << ',' << r << ',' << col << ',' << uav::Name(cell.state) << ','
              << num << ',' << Quoted(g.healthy ? cell.reason : g.reason) << '\n';
        }
      known_cells += known;
      if (known == g.rows * g.cols && first_all_known < 0) first_all_known = static_cast<int>(i);
      if (!overlay_dir.empty()) {
        char name[32];
        std::snprintf(name, sizeof name, "/depth_%06zu.jpg", i);
        cv::imwrite(overlay_dir + name, Overlay(image, g, estimator.features()));
      }
      progress.Update(i + 1);
    }
    progress.Finish(rows.size());
    if (ms.empty()) throw std::invalid_argument(dir + ": no frame could be read (" + std::to_string(skipped.size()) + " skipped)");
    uav::WriteFileAtomically(out, csv.str());
    std::sort(ms.begin(), ms.end());
    const int cells = estimator.params().grid_cols * estimator.params().grid_rows;
    std::string skipped_json;
    for (const std::string& s : skipped) skipped_json += (skipped_json.empty() ? "" : ", ") + uav::JsonString(s);
    std::printf("{\"frames\": %zu, \"healthy_frames\": %d, \"known_cell_fraction\": %.3f, \"first_frame_all_known\": %d, "
                "\"ms_per_frame_median\": %.2f, \"ms_per_frame_max\": %.2f, \"skipped\": [%s]}\n",
                ms.size(), healthy, static_cast<double>(known_cells) / (cells * ms.size()), first_all_known,
                ms[ms.size() / 2], ms.back(), skipped_json.c_str());
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-monodepth: %s\n", e.what());
    return 2;
  }
}
