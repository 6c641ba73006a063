// uav-vo SEQ_DIR [--method pnp|epnp|rigid] --out poses.txt [--max-features N] [--offset-prior PX] [--first N] [--frames N]
// Stereo visual odometry (thesis ch. 5) over a KITTI-layout sequence: image_0/ (left) and
// image_1/ (right) rectified images in name order, calib.txt with the projection matrices P0 and
// P1, optional times.txt (seconds; 10 Hz is assumed without it). Writes one KITTI pose line per
// frame (the left camera in the first frame's camera axes, 3x4 row-major [R|t]); an unhealthy
// frame repeats the last pose, as a vehicle's odometry would hold it, and is counted with its
// reason. A progress bar goes to stderr, a JSON report (frames, healthy frames, segments,
// reasons, ms per frame median and p95, frames per second) to stdout. uav-vo-eval scores the
// poses against ground truth.
// Exit 0 on success, 1 when the sequence cannot be used (named on stderr; nothing written), 2 on
// bad options.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <map>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/shared/progress_bar.hpp"
#include "uav/vision/kitti_odometry.hpp"
#include "uav/vision/stereo_vo.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/image_files.hpp"

int main(int argc, char** argv) {
  CLI::App cli{"uav-vo: stereo visual odometry over a KITTI-layout sequence (thesis ch. 5)"};
  std::string dir, out, method = "pnp";
  uav::vision::VoParams params;
  int first = 0, frames = 0;
  cli.add_option("sequence", dir, "folder with image_0/, image_1/, calib.txt [, times.txt]")->required();
  uav::OutputFile(cli.add_option("--out", out, "KITTI pose file to write"))->required();
  cli.add_option("--method", method, "motion estimate: pnp (P3P), epnp or rigid (3D-3D, Eq. 5.1-5.8)")
      ->check(CLI::IsMember({"pnp", "epnp", "rigid"}))
      ->capture_default_str();
  cli.add_option("--max-features", params.max_features, "features kept per keyframe")->capture_default_str();
  cli.add_option("--offset-prior", params.disparity_offset_prior_sigma_px,
                 "1 sigma [px] of the pair's disparity offset before it is learnt from the motion; 0: taken as 0")
      ->capture_default_str();
  cli.add_option("--first", first, "first frame to use")->check(CLI::NonNegativeNumber)->capture_default_str();
  cli.add_option("--frames", frames, "frames to use (0: all)")->check(CLI::NonNegativeNumber)->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  params.method = *uav::vision::ParseVoMethod(method);
  try {
    params.Validate();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-vo: %s\n", e.what());
    return 2;
  }
  try {
    const uav::vision::KittiSequence seq = uav::vision::ReadKittiSequence(dir);
    const int available = static_cast<int>(seq.left.size());
    if (first >= available)
      throw std::runtime_error("--first " + std::to_string(first) + " but the sequence has " + std::to_string(available) +
                               " frames");
    const int last = frames > 0 ? std::min(available, first + frames) : available;
    uav::vision::StereoVo vo(seq.geometry, params);
    std::vector<Eigen::Isometry3d> poses;
    std::vector<double> ms;
    std::map<std::string, int> reasons;
    int healthy = 0, segments = 0, last_segment = -1;
    std::vector<std::string> skipped;
    std::pair<double, double> offset{0, 0};
    uav::ProgressBar progress(last - first);
    for (int i = first; i < last; ++i) {
      uav::vision::RectifiedPair pair;
      std::string problem;
      for (const std::string* f : {&seq.left[i], &seq.right[i]}) {
        cv::Mat& m = f == &seq.left[i] ? pair.left : pair.right;
        std::string p = problem.empty() ? uav::ImageFileProblem(*f) : "";
        if (problem.empty() && p.empty() && (m = cv::imread(*f, cv::IMREAD_GRAYSCALE)).empty()) p = "cannot read it as an image";
        if (!p.empty()) problem = *f + ": " + p;
      }
      if (!problem.empty()) {  // a dropped frame: named, counted, the sequence goes on
        skipped.push_back(problem);
        std::fprintf(stderr, "\nuav-vo: skipped frame %d: %s\n", i, problem.c_str());
        // One pose per frame (KITTI's format): a dropped frame holds the last estimate.
        poses.push_back(poses.empty() ? Eigen::Isometry3d::Identity() : poses.back());
        progress.Update(i - first + 1);
        continue;
      }
      pair.left_utime = pair.right_utime = static_cast<int64_t>(seq.times_s[i] * 1e6);
      const auto t0 = std::chrono::steady_clock::now();
      const uav::vision::VoResult r = vo.Process(pair);
      ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      poses.push_back(r.T_WC);
      offset = {r.disparity_offset_px, r.disparity_offset_sigma_px};
      if (r.healthy) {
        ++healthy;
      } else {
        // The reason's kind, without its numbers, so that the report groups them.
        ++reasons[r.reason.substr(0, r.reason.find(" ("))];
      }
      if (r.segment != last_segment) ++segments, last_segment = r.segment;
      progress.Update(i - first + 1, r.healthy ? "" : r.reason);
    }
    progress.Finish(last - first);
    uav::vision::WriteKittiPoses(out, poses);
    if (ms.empty()) throw std::runtime_error(dir + ": no frame could be read");
    std::vector<double> sorted = ms;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2], p95 = sorted[std::min(sorted.size() - 1, sorted.size() * 95 / 100)];
    nlohmann::json report = {{"sequence", dir},
                             {"method", method},
                             {"frames", poses.size()},
                             {"healthy_frames", healthy},
                             {"segments", segments},
                             {"unhealthy_reasons", reasons},
                             {"skipped", skipped},
                             {"image_size", {seq.geometry.width, seq.geometry.height}},
                             {"ms_per_frame_median", median},
                             {"ms_per_frame_p95", p95},
                             {"frames_per_s", 1000.0 / median},
                             {"disparity_offset_px", offset.first},
                             {"disparity_offset_sigma_px", offset.second},
                             {"poses", out}};
    std::printf("%s\n", report.dump(2).c_str());
  } catch (const std::exception& e) {
    std::fprintf(stderr, "\nuav-vo: %s; nothing written\n", e.what());
    return 1;
  }
  return 0;
}
