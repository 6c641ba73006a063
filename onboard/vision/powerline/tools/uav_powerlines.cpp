// uav-powerlines IMAGE|FOLDER... [--out DIR] [--truth DIR] [--overlay DIR] [--mode any|horizontal]
// [--segments edlines|lsd] [--min-probability P]: the power-line detector on photos. With --out, for each image: DIR/<name>_lines.png (the input's size, 255 on
// the wires drawn 2 px wide, 0 elsewhere) and DIR/<name>.json (each wire's quadratic, frame,
// end points and width). With --truth, each image is scored against TRUTH/<name>.png (non-zero
// on a wire) the way power-line benchmarks score boundaries: a pixel matches within 0.0075 of the
// image diagonal, counts summed over the set; beside it the LSD-only baseline (every LSD segment
// of 30 px or more, drawn 2 px wide). With --overlay, DIR/<name>_overlay.jpg shows the image with
// the detected wires in red over the true ones in green. An image that cannot be used (or has no usable truth) is
// named with the reason on stderr and nothing is written or scored for it; the others are
// processed. A JSON report goes to stdout. Exit 0 when every image was processed, 1 when some
// were not, 2 on bad options.
#include <chrono>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/power_line_detector.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

std::string Json(const std::vector<uav::vision::WireCurve>& wires, const cv::Mat& image, const std::string& source,
                 double ms) {
  nlohmann::json j;
  j["image"] = source;
  j["width"] = image.cols;
  j["height"] = image.rows;
  j["detect_ms"] = ms;
  j["wires"] = nlohmann::json::array();
  for (const auto& w : wires) {
    const Eigen::Vector2d a = w.first(), b = w.last();
    j["wires"].push_back({
        {"model", "v = b0 + b1 u + b2 u^2 in the wire frame: p = origin + u * axis + v * normal (normal = (-axis_y, axis_x))"},
        {"b", {w.b(0), w.b(1), w.b(2)}},
        {"origin_px", {w.origin_px.x(), w.origin_px.y()}},
        {"axis", {w.axis.x(), w.axis.y()}},
        {"u_range", {w.u_min, w.u_max}},
        {"first_px", {a.x(), a.y()}},
        {"last_px", {b.x(), b.y()}},
        {"rms_px", w.rms_px},
        {"support", w.support},
        {"segments", w.segments},
        {"width_px", w.width_px},
        {"probability", w.probability},
    });
  }
  return j.dump(2) + "\n";
}


nlohmann::json ScoreJson(const uav::vision::MaskScore& s) {
  return {{"precision", s.precision}, {"recall", s.recall}, {"f1", 100.0 * s.f1}};
}

// The truth mask of `image_path` in `truth_dir` (<stem>.png, non-zero on a wire), checked.
cv::Mat TruthMask(const std::string& truth_dir, const std::string& image_path, const cv::Size& size) {
  const std::string path =
      (std::filesystem::path(truth_dir) / (std::filesystem::path(image_path).stem().string() + ".png")).string();
  if (const std::string problem = uav::ImageFileProblem(path); !problem.empty())
    throw std::invalid_argument("truth " + path + ": " + problem);
  const cv::Mat truth = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (truth.empty()) throw std::invalid_argument("truth " + path + ": cannot read it as an image");
  if (truth.size() != size)
    throw std::invalid_argument("truth " + path + " is " + std::to_string(truth.cols) + "x" +
                                std::to_string(truth.rows) + " px, the image " + std::to_string(size.width) + "x" +
                                std::to_string(size.height));
  return truth > 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-powerlines: power-line detection in photos (thesis 3.6)"};
  std::vector<std::string> inputs;
  std::string out_dir, truth_dir, overlay_dir, mode = "any", segments = "edlines";
  cli.add_option("images", inputs, "input images (JPEG, PNG, ...) or folders of them")->required();
  cli.add_option("--out", out_dir, "output directory for masks and wire files (created if missing)");
  cli.add_option("--truth", truth_dir, "folder of ground-truth masks <name>.png: score precision, recall and F1")
      ->check(CLI::ExistingDirectory);
  cli.add_option("--overlay", overlay_dir, "write each image with its wires drawn (red; the truth in green)");
  cli.add_option("--mode", mode, "any: wires at any angle; horizontal: the thesis's forward-camera mode")
      ->check(CLI::IsMember({"any", "horizontal"}))
      ->capture_default_str();
  cli.add_option("--segments", segments, "straight pieces of the edge map by EDLines or by OpenCV's LSD (the vehicle's pwl_segments)")
      ->check(CLI::IsMember({"edlines", "lsd"}))
      ->capture_default_str();
  double min_probability = uav::vision::PowerLineParams{}.min_wire_probability;
  cli.add_option("--min-probability", min_probability,
                 "the learned check: curves it gives a lower probability of being a wire are dropped (0: no check, "
                 "the vehicle's pwl_verify 0)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  if (out_dir.empty() && truth_dir.empty() && overlay_dir.empty()) {
    std::fprintf(stderr, "uav-powerlines: give --out DIR (write the wires), --truth DIR (score them) or --overlay DIR\n");
    return 2;
  }
  std::vector<std::string> images;
  for (const std::string& input : inputs) {
    if (std::filesystem::is_directory(input)) {
      const auto files = uav::ImageFilesIn(input);
      if (files.empty()) std::fprintf(stderr, "uav-powerlines: folder %s holds no images\n", input.c_str());
      images.insert(images.end(), files.begin(), files.end());
    } else {
      images.push_back(input);
    }
  }

  uav::vision::PowerLineParams params;
  params.mode = mode == "horizontal" ? uav::vision::PowerLineParams::Mode::kHorizontal
                                     : uav::vision::PowerLineParams::Mode::kAny;
  params.segments = segments == "lsd" ? uav::vision::PowerLineParams::Segments::kLsd
                                      : uav::vision::PowerLineParams::Segments::kEdLines;
  params.min_wire_probability = min_probability;
  const uav::vision::PowerLineDetector detector(params);
  for (const std::string& dir : {out_dir, overlay_dir}) {
    if (dir.empty()) continue;
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec || !std::filesystem::is_directory(dir)) {
      std::fprintf(stderr, "uav-powerlines: cannot use '%s' as an output directory\n", dir.c_str());
      return 2;
    }
  }
  constexpr double kToleranceOfDiagonal = 0.0075;  // the benchmark's match distance
  constexpr double kBaselineMinLengthPx = 30.0;    // the LSD-only baseline keeps segments this long
  int failed = 0, processed = 0, total_wires = 0, images_with_wires = 0;
  std::vector<double> times_ms;
  uav::vision::MaskTally ours, baseline;
  nlohmann::json per_image = nlohmann::json::array();  // each scored image's own figures, to find the hard ones
  uav::ProgressBar progress(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string& path = images[i];
    progress.Update(i, std::filesystem::path(path).filename().string());
    const std::string stem = std::filesystem::path(path).stem().string();
    try {
      if (const std::string problem = uav::ImageFileProblem(path); !problem.empty()) throw std::invalid_argument(problem);
      cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
      if (image.empty()) throw std::invalid_argument("cannot read it as an image");
      // A grey camera's frames (KITTI's, most aerial mono cameras') and a PNG with alpha are
      // taken as colour; other depths (16-bit, float) are named by the detector.
      if (image.depth() == CV_8U && image.channels() == 1) cv::cvtColor(image, image, cv::COLOR_GRAY2BGR);
      if (image.depth() == CV_8U && image.channels() == 4) cv::cvtColor(image, image, cv::COLOR_BGRA2BGR);
      const cv::Mat truth = truth_dir.empty() ? cv::Mat() : TruthMask(truth_dir, path, image.size());
      const auto t0 = std::chrono::steady_clock::now();
      const auto wires = detector.Detect(image);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      const cv::Mat mask = uav::vision::DrawWireMask(image.size(), wires, 2);
      if (!out_dir.empty()) {
        std::vector<uint8_t> png;
        cv::imencode(".png", mask, png);
        uav::WriteFileAtomically((std::filesystem::path(out_dir) / (stem + "_lines.png")).string(),
                                 std::string(png.begin(), png.end()));
        uav::WriteFileAtomically((std::filesystem::path(out_dir) / (stem + ".json")).string(),
                                 Json(wires, image, path, ms));
      }
      if (!overlay_dir.empty()) {
        cv::Mat shown = image.clone();
        if (!truth.empty()) shown.setTo(cv::Scalar(0, 255, 0), truth);
        shown.setTo(cv::Scalar(0, 0, 255), mask);
        std::vector<uint8_t> jpg;
        cv::imencode(".jpg", shown, jpg, {cv::IMWRITE_JPEG_QUALITY, 90});
        uav::WriteFileAtomically((std::filesystem::path(overlay_dir) / (stem + "_overlay.jpg")).string(),
                                 std::string(jpg.begin(), jpg.end()));
      }
      if (!truth.empty()) {
        const double tol = kToleranceOfDiagonal * std::hypot(image.cols, image.rows);
        ours.Add(mask, truth, tol);
        nlohmann::json scored = ScoreJson(uav::vision::ScoreMasks(mask, truth, tol));
        scored["image"] = std::filesystem::path(path).filename().string();
        scored["wires"] = wires.size();
        per_image.push_back(std::move(scored));
        std::vector<cv::Vec4f> long_segments;
        for (const cv::Vec4f& s : uav::vision::LsdSegments(image))
          if (std::hypot(s[2] - s[0], s[3] - s[1]) >= kBaselineMinLengthPx) long_segments.push_back(s);
        baseline.Add(uav::vision::DrawSegmentMask(image.size(), long_segments, 2), truth, tol);
      }
      total_wires += static_cast<int>(wires.size());
      images_with_wires += !wires.empty();
      times_ms.push_back(ms);
      ++processed;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "\nuav-powerlines: %s: %s; nothing written for it\n", path.c_str(), e.what());
      ++failed;
    }
  }
  progress.Finish(images.size());
  nlohmann::json report;
  report["segments"] = segments;
  report["min_probability"] = min_probability;
  report["images"] = images.size();
  report["processed"] = processed;
  report["not_processed"] = failed;
  report["wires"] = total_wires;
  report["wires_per_image"] = processed ? static_cast<double>(total_wires) / processed : 0.0;
  report["images_with_wires"] = images_with_wires;
  if (!times_ms.empty()) {
    std::nth_element(times_ms.begin(), times_ms.begin() + times_ms.size() / 2, times_ms.end());
    report["median_detect_ms"] = times_ms[times_ms.size() / 2];
  }
  if (!out_dir.empty()) report["out"] = out_dir;
  if (!truth_dir.empty()) {
    report["truth"] = {{"folder", truth_dir},
                       {"tolerance", "0.0075 x image diagonal, pixel counts summed over the set"},
                       {"ours", ScoreJson(ours.Score())},
                       {"lsd_baseline", ScoreJson(baseline.Score())},
                       {"lsd_baseline_is", "every LSD segment of 30 px or more, drawn 2 px wide"},
                       {"per_image", per_image}};
  }
  std::printf("%s\n", report.dump(2).c_str());
  return failed ? 1 : 0;
}
