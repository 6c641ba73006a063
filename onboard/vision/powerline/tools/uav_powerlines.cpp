// uav-powerlines IMAGE... --out DIR [--mode any|horizontal]: the power-line detector on photos.
// For each image: DIR/<name>_lines.png (the input's size, 255 on the wires drawn 2 px wide, 0
// elsewhere) and DIR/<name>.json (each wire's quadratic, frame and end points). An image that
// cannot be used is named with the reason on stderr and nothing is written for it; the others
// are processed. Exit 0 when every image was processed, 1 when some were not, 2 on bad options.
#include <chrono>
#include <cstdio>
#include <filesystem>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/shared/image_files.hpp"
#include "uav/shared/progress_bar.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/power_line_detector.hpp"
#include "uav/shared/decimal.hpp"

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
    });
  }
  return j.dump(2) + "\n";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-powerlines: power-line detection in photos (thesis 3.6)"};
  std::vector<std::string> images;
  std::string out_dir, mode = "any";
  cli.add_option("images", images, "input images (JPEG, PNG, ...)")->required();
  cli.add_option("--out", out_dir, "output directory (created if missing)")->required();
  cli.add_option("--mode", mode, "any: wires at any angle; horizontal: the thesis's forward-camera mode")
      ->check(CLI::IsMember({"any", "horizontal"}))
      ->capture_default_str();
  uav::RequireDecimalNumbers(cli);
  CLI11_PARSE(cli, argc, argv);

  uav::vision::PowerLineParams params;
  params.mode = mode == "horizontal" ? uav::vision::PowerLineParams::Mode::kHorizontal
                                     : uav::vision::PowerLineParams::Mode::kAny;
  const uav::vision::PowerLineDetector detector(params);
  std::error_code ec;
  std::filesystem::create_directories(out_dir, ec);
  if (ec || !std::filesystem::is_directory(out_dir)) {
    std::fprintf(stderr, "uav-powerlines: cannot use '%s' as the output directory\n", out_dir.c_str());
    return 2;
  }
  int failed = 0, total_wires = 0;
  uav::ProgressBar progress(images.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const std::string& path = images[i];
    progress.Update(i, std::filesystem::path(path).filename().string());
    const std::string stem = std::filesystem::path(path).stem().string();
    try {
      if (const std::string problem = uav::ImageFileProblem(path); !problem.empty()) throw std::invalid_argument(problem);
      const cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
      if (image.empty()) throw std::invalid_argument("cannot read it as an image");
      const auto t0 = std::chrono::steady_clock::now();
      const auto wires = detector.Detect(image);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::vector<uint8_t> png;
      cv::imencode(".png", uav::vision::DrawWireMask(image.size(), wires, 2), png);
      uav::WriteFileAtomically((std::filesystem::path(out_dir) / (stem + "_lines.png")).string(),
                               std::string(png.begin(), png.end()));
      uav::WriteFileAtomically((std::filesystem::path(out_dir) / (stem + ".json")).string(), Json(wires, image, path, ms));
      total_wires += static_cast<int>(wires.size());
    } catch (const std::exception& e) {
      std::fprintf(stderr, "\nuav-powerlines: %s: %s; nothing written for it\n", path.c_str(), e.what());
      ++failed;
    }
  }
  progress.Finish(images.size());
  std::printf("uav-powerlines: %zu image(s), %d wire(s), %d image(s) not processed, output in %s\n", images.size(),
              total_wires, failed, out_dir.c_str());
  return failed ? 1 : 0;
}
