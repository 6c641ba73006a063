// uav-sysid LOG.csv: identifies the vehicle's model from a flight log with chirps (thesis 2.4.5,
// 2.5) and prints the parameters and trim values as JSON; draws measured against model output
// (as the thesis's Fig. 2.19-2.31) into a PNG.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/sysid/system_identification.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

void DrawFit(cv::Mat& canvas, const cv::Rect& box, const uav::sysid::ModelFit& f) {
  cv::rectangle(canvas, box, cv::Scalar(200, 200, 200), 1);
  if (f.t.empty()) return;
  double lo = 1e300, hi = -1e300;
  for (std::size_t i = 0; i < f.t.size(); ++i)
    lo = std::min({lo, f.measured[i], f.predicted[i]}), hi = std::max({hi, f.measured[i], f.predicted[i]});
  if (hi - lo < 1e-12) hi = lo + 1;
  const double t0 = f.t.front(), t1 = std::max(f.t.back(), t0 + 1e-6);
  auto at = [&](double t, double v) {
    return cv::Point2d(box.x + 50 + (t - t0) / (t1 - t0) * (box.width - 60),
                       box.y + box.height - 20 - (v - lo) / (hi - lo) * (box.height - 50));
  };
  auto line = [&](const std::vector<double>& v, const cv::Scalar& colour) {
    std::vector<cv::Point> pts;
    for (std::size_t i = 0; i < v.size(); ++i) pts.push_back(at(f.t[i], v[i]));
    cv::polylines(canvas, pts, false, colour, 1, cv::LINE_AA);
  };
  line(f.measured, cv::Scalar(200, 120, 30));   // measured: blue
  line(f.predicted, cv::Scalar(30, 30, 220));   // model: red
  char title[256];
  std::string params;
  for (const auto& [k, v] : f.params) {
    char b[64];
    std::snprintf(b, sizeof b, "%s %.4g  ", k.c_str(), v);
    params += b;
  }
  std::snprintf(title, sizeof title, "%s (%s): %s  fit %.1f %%   blue measured %s, red model", f.model.c_str(),
                f.equation.c_str(), params.c_str(), f.fit_percent, f.output_name.c_str());
  cv::putText(canvas, title, {box.x + 8, box.y + 18}, cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  char axis[64];
  std::snprintf(axis, sizeof axis, "%.3g", hi);
  cv::putText(canvas, axis, {box.x + 4, box.y + 34}, cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(80, 80, 80), 1);
  std::snprintf(axis, sizeof axis, "%.3g", lo);
  cv::putText(canvas, axis, {box.x + 4, box.y + box.height - 20}, cv::FONT_HERSHEY_SIMPLEX, 0.35, cv::Scalar(80, 80, 80), 1);
  std::snprintf(axis, sizeof axis, "t %.1f .. %.1f s", t0, t1);
  cv::putText(canvas, axis, {box.x + box.width - 140, box.y + box.height - 5}, cv::FONT_HERSHEY_SIMPLEX, 0.35,
              cv::Scalar(80, 80, 80), 1);
}

// Writes through a temporary name, then renames: a reader never sees half a file.
void WriteAtomically(const std::string& path, const std::function<bool(const std::string&)>& write) {
  // The temporary keeps the extension (OpenCV picks the format by it).
  const std::filesystem::path p(path);
  const std::string tmp = (p.parent_path() / (p.stem().string() + ".partial" + p.extension().string())).string();
  if (!write(tmp)) throw std::runtime_error("cannot write '" + path + "'");
  std::filesystem::rename(tmp, path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-sysid: identify the vehicle model from a flight log with chirps (thesis 2.4.5, 2.5)"};
  std::string log_path, params_path = uav::ResourcePath("vehicles/x650.params");
  std::string plot_path, json_path;
  cli.add_option("LOG", log_path, "flight log CSV (LOG_DIR/flight_<utime>.csv)")->required();
  cli.add_option("--params", params_path, "vehicle file with the ground-measured mass, inertia and K_v (Table 2.2)")
      ->capture_default_str();
  uav::OutputFile(cli.add_option("--plot", plot_path, "PNG of measured against model output (default: LOG with _sysid.png)"));
  uav::OutputFile(cli.add_option("--json", json_path, "also write the JSON here"));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    const auto known = uav::sysid::KnownParams::FromParameters(uav::ParameterSet::LoadFile(params_path, uav::VehicleParameterSchema()));
    std::fprintf(stderr, "uav-sysid: reading %s\n", log_path.c_str());
    const auto log = uav::sysid::LogTable::ReadCsv(log_path);
    std::fprintf(stderr, "uav-sysid: %zu rows, identifying\n", log.rows());
    const auto id = uav::sysid::Identify(log, known);
    const std::string json = uav::sysid::ToJson(id);
    std::printf("%s\n", json.c_str());
    if (!json_path.empty())
      WriteAtomically(json_path, [&](const std::string& p) { return static_cast<bool>(std::ofstream(p) << json << "\n"); });
    if (plot_path.empty()) plot_path = std::filesystem::path(log_path).replace_extension("").string() + "_sysid.png";
    if (!id.fits.empty()) {
      const int w = 1200, h = 260;
      cv::Mat canvas(h * static_cast<int>(id.fits.size()), w, CV_8UC3, cv::Scalar(255, 255, 255));
      for (std::size_t i = 0; i < id.fits.size(); ++i)
        DrawFit(canvas, cv::Rect(0, static_cast<int>(i) * h, w, h - 4), id.fits[i]);
      WriteAtomically(plot_path, [&](const std::string& p) { return cv::imwrite(p, canvas, {}); });
      std::fprintf(stderr, "uav-sysid: plot %s\n", plot_path.c_str());
    }
    return id.fits.empty() && !id.trim.found ? 1 : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-sysid: %s\n", e.what());
    return 2;
  }
}
