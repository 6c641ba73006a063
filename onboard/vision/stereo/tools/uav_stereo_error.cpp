// uav-stereo-error [--material M] [--depths 2,3,4] [--out table.json] [--plot depth_error.png]
// Thesis 3.2 in the simulator, with three matchers side by side: SAD block matching (OpenCV's
// StereoBM, as the thesis's correlation stereo), SGBM with OpenCV's parabola sub-pixel step, and
// ours (SGBM refined on the images, DisparityMatcher's default).
// - Tables 3.1 and 3.2 (3.2.1, correlation accuracy): a textured plane faces the rig at known
//   depths; every pixel's disparity is compared with the renderer's exact one. The accuracy is
//   the standard deviation of the error over the matched pixels (within 1 px of the truth: the
//   estimation error of 3.2.2); pixels off by more are counted apart as mismatches. Table 3.1
//   varies the resolution at an 11 px window, Table 3.2 the window at 320x240.
// - Pixel locking: a plane slanted 50 degrees to the line of sight spans every fractional
//   disparity; reported are the share of estimates whose fractional part lies within 1/8 px of
//   a whole pixel (25 % when unbiased) and the largest mean error over eight bins of the true
//   fractional part.
// - Figs. 3.6-3.7: a textured board and a tree trunk 1.5-8 m ahead of the vehicle's rig (640x480,
//   matched at 320x240, 5 px window); the median error of the object's depths, and their
//   per-pixel spread beside Eq. 3.7's. --plot draws the curves.
// Prints Markdown and writes JSON with --out.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/disparity.hpp"
#include "uav/world/renderer.hpp"

namespace {

using uav::vision::DisparityParams;
using uav::vision::MatcherKind;

struct Matcher {
  const char* name;
  MatcherKind kind;
  bool refined;
};
const std::array<Matcher, 3> kMatchers{{{"sad", MatcherKind::kBlockMatching, false},
                                        {"sgbm", MatcherKind::kSemiGlobal, false},
                                        {"ours", MatcherKind::kSemiGlobal, true}}};

// The simulator's stereo camera (66 deg field of view, 0.12 m baseline) at this width.
uav::world::StereoSetup Rig(int width) {
  uav::world::CameraSetup camera;
  camera.name = "stereo";
  const double scale = width / 640.0;
  camera.intrinsics.width = width;
  camera.intrinsics.height = width * 3 / 4;
  camera.intrinsics.fx = camera.intrinsics.fy = 513.5 * scale;
  camera.intrinsics.cx = 0.5 * (width - 1);
  camera.intrinsics.cy = 0.5 * (camera.intrinsics.height - 1);
  camera.noise_sigma = 1.0;
  camera.supersample = 2;
  Eigen::Isometry3d T_B_rig = Eigen::Isometry3d::Identity();
  T_B_rig.linear() = uav::RotationBCForward();
  return uav::world::MakeStereoSetup(camera, T_B_rig, 0.12, {});
}

DisparityParams ParamsFor(const Matcher& m, int block, int num_disparities, int downscale) {
  DisparityParams p;
  p.matcher = m.kind;
  p.subpixel_refinement = m.refined;
  p.downscale = downscale;
  p.block_size = block;
  p.num_disparities = num_disparities;
  p.texture_threshold = 0.0;
  return p;
}

// A frame of `scene` from 1.5 m above the ground, looking north.
uav::world::StereoFrame Render(const uav::world::Scene& scene, const uav::world::StereoSetup& setup) {
  const uav::world::StereoRenderer renderer(scene, setup);
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  T_NB.translation() = Eigen::Vector3d(0, 0, -1.5);
  return renderer.Render(T_NB, 1000000);
}

struct Accuracy {
  double sigma_px = 0.0;  // std of the error over matched pixels
  double mismatch_fraction = 0.0;
};

// Every pixel with a true disparity, right of the search band: f(estimate_px or <= 0, truth_px).
void ForEachPixel(const uav::vision::DisparityMap& d, const cv::Mat& truth, int band,
                  const std::function<void(double, double)>& f) {
  for (int v = 0; v < d.d16.rows; ++v)
    for (int u = band; u < d.d16.cols; ++u) {
      const float t = truth.at<float>(v, u);
      if (t > 0) f(d.d16.at<int16_t>(v, u) / 16.0, t);
    }
}

// Tables 3.1-3.2: a plane facing the rig at each depth.
std::array<Accuracy, 3> Tables(const std::string& material, const std::vector<double>& depths, int width, int block) {
  const uav::world::StereoSetup setup = Rig(width);
  const int num_disparities =
      16 * static_cast<int>(std::ceil(setup.left.intrinsics.fx * 0.12 / depths.front() * 1.5 / 16.0 + 1));
  std::array<double, 3> sum{}, sum2{};
  std::array<long, 3> matched{}, total{};
  for (std::size_t i = 0; i < depths.size(); ++i) {
    uav::world::Scene s(11 + i);
    s.SetSky(false);
    s.AddBox("wall", Eigen::Vector3d(depths[i] + 0.05, 0, -1.5), Eigen::Vector3d(0.1, 60, 40), 0.0, material);
    const uav::world::StereoFrame f = Render(s, setup);
    for (std::size_t k = 0; k < kMatchers.size(); ++k) {
      const uav::vision::DisparityMatcher matcher(ParamsFor(kMatchers[k], block, num_disparities, 1));
      ForEachPixel(matcher.Compute(f.left.image, f.right.image), f.disparity, num_disparities, [&](double e, double t) {
        ++total[k];
        if (e <= 0 || std::abs(e - t) > 1.0) return;
        sum[k] += e - t;
        sum2[k] += (e - t) * (e - t);
        ++matched[k];
      });
    }
  }
  std::array<Accuracy, 3> out;
  for (std::size_t k = 0; k < kMatchers.size(); ++k) {
    if (matched[k] > 1) {
      const double mean = sum[k] / matched[k];
      out[k].sigma_px = std::sqrt(std::max(0.0, sum2[k] / matched[k] - mean * mean));
    }
    out[k].mismatch_fraction = total[k] > 0 ? 1.0 - static_cast<double>(matched[k]) / total[k] : 1.0;
  }
  return out;
}

struct Locking {
  double near_whole_fraction = 0.0;  // estimates within 1/8 px of a whole pixel (0.25 unbiased)
  double max_bin_bias_px = 0.0;      // largest |mean error| over 8 bins of the true fraction
  double rms_px = 0.0;               // over matched pixels
  std::array<double, 16> fraction_histogram{};  // of the estimates' fractional parts, sums to 1
};

std::array<Locking, 3> PixelLocking(const std::string& material, int block) {
  const uav::world::StereoSetup setup = Rig(320);
  uav::world::Scene s(31);
  s.SetSky(false);
  // 50 degrees to the line of sight, from 2 to 6 m: disparities from about 15 down to 5 px.
  s.AddBox("wall", Eigen::Vector3d(4.0, 0, -1.5), Eigen::Vector3d(0.1, 60, 40), 40.0 * M_PI / 180.0, material);
  const uav::world::StereoFrame f = Render(s, setup);
  std::array<Locking, 3> out;
  for (std::size_t k = 0; k < kMatchers.size(); ++k) {
    const uav::vision::DisparityMatcher matcher(ParamsFor(kMatchers[k], block, 32, 1));
    std::array<double, 8> bin_sum{};
    std::array<long, 8> bin_n{};
    long n = 0, near_whole = 0;
    double sum2 = 0;
    Locking& l = out[k];
    ForEachPixel(matcher.Compute(f.left.image, f.right.image), f.disparity, 32, [&](double e, double t) {
      if (e <= 0 || std::abs(e - t) > 1.0) return;
      const double frac = e - std::floor(e);
      l.fraction_histogram[std::min(15, static_cast<int>(frac * 16))] += 1;
      if (frac < 0.125 || frac > 0.875) ++near_whole;
      const int bin = std::min(7, static_cast<int>((t - std::floor(t)) * 8));
      bin_sum[bin] += e - t;
      ++bin_n[bin];
      sum2 += (e - t) * (e - t);
      ++n;
    });
    if (n == 0) continue;
    for (double& h : l.fraction_histogram) h /= n;
    l.near_whole_fraction = static_cast<double>(near_whole) / n;
    l.rms_px = std::sqrt(sum2 / n);
    for (int b = 0; b < 8; ++b)
      if (bin_n[b] > 0) l.max_bin_bias_px = std::max(l.max_bin_bias_px, std::abs(bin_sum[b] / bin_n[b]));
  }
  return out;
}

double Median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
// 1.4826 x the median absolute deviation: the standard deviation of the bulk, not of the
// few pixels matched to the background at the object's outline.
double RobustSpread(const std::vector<double>& v) {
  const double m = Median(v);
  std::vector<double> dev;
  for (double x : v) dev.push_back(std::abs(x - m));
  return 1.4826 * Median(dev);
}

struct DepthPoint {
  double true_m = 0.0;          // median true depth over the object's pixels with an estimate
  double median_error_m = 0.0;  // median of the per-pixel depth error (estimate minus truth)
  double spread_m = 0.0;        // robust spread of the per-pixel depth error
  double model_spread_m = 0.0;  // Eq. 3.7 at the robust spread of the disparity error
  long pixels = 0;
};

// Figs. 3.6-3.7 on the vehicle's rig and matcher settings: depth of a board or a trunk.
std::vector<DepthPoint> DepthCurve(bool tree, const Matcher& m) {
  const uav::world::StereoSetup setup = Rig(640);
  DisparityParams p = ParamsFor(m, 5, 64, 2);
  p.texture_threshold = DisparityParams().texture_threshold;
  const uav::vision::DisparityMatcher matcher(p);
  const double fb = setup.left.intrinsics.fx * 0.12;  // [px m] at full resolution
  std::vector<DepthPoint> out;
  for (double z = 1.5; z <= 8.0 + 1e-9; z += 0.5) {
    uav::world::Scene s(41);
    s.SetSky(false);
    const int id = tree ? s.AddCylinder("trunk", Eigen::Vector3d(z, 0, 0), 0.15, 4.0, "bark")
                        : s.AddBox("board", Eigen::Vector3d(z + 0.01, 0, -1.5), Eigen::Vector3d(0.02, 1.0, 1.0), 0.0, "gravel");
    const uav::world::StereoFrame f = Render(s, setup);
    const uav::vision::DisparityMap d = matcher.Compute(f.left.image, f.right.image);
    const cv::Mat full = d.FullResolution16U(f.left.image.size());
    std::vector<double> true_m, error_m, disparity_error_px;
    for (int v = 0; v < full.rows; ++v)
      for (int u = 0; u < full.cols; ++u) {
        if (f.left.object_id.at<uint16_t>(v, u) != id || full.at<uint16_t>(v, u) == 0) continue;
        const double t = f.left.depth.at<float>(v, u), disparity = full.at<uint16_t>(v, u) / 16.0;
        true_m.push_back(t);
        error_m.push_back(fb / disparity - t);
        disparity_error_px.push_back(disparity - f.disparity.at<float>(v, u));
      }
    DepthPoint q;
    q.pixels = static_cast<long>(true_m.size());
    q.true_m = q.pixels > 1 ? Median(true_m) : z;
    if (q.pixels > 1) {
      q.median_error_m = Median(error_m);
      q.spread_m = RobustSpread(error_m);
      q.model_spread_m = q.true_m * q.true_m / fb * RobustSpread(disparity_error_px);  // Eq. 3.7
    }
    out.push_back(q);
  }
  return out;
}

// Absolute error of the mean depth against distance, both objects, SAD and ours.
void Plot(const std::string& path, const std::vector<std::vector<DepthPoint>>& curves, const std::vector<std::string>& names) {
  const cv::Scalar colours[] = {{40, 40, 220}, {40, 160, 40}, {60, 60, 60}, {200, 120, 30}};
  cv::Mat canvas(480, 720, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Rect box(70, 40, 620, 380);
  double y_max = 0.05;
  for (const auto& c : curves)
    for (const DepthPoint& q : c) y_max = std::max(y_max, std::abs(q.median_error_m));
  y_max = std::ceil(y_max * 20) / 20;
  const auto to_px = [&](double x, double y) {
    return cv::Point(box.x + static_cast<int>((x - 1.0) / 7.5 * box.width),
                     box.y + box.height - static_cast<int>(y / y_max * box.height));
  };
  cv::rectangle(canvas, box, cv::Scalar(0, 0, 0), 1);
  for (int z = 2; z <= 8; ++z) {
    cv::line(canvas, to_px(z, 0), to_px(z, y_max), cv::Scalar(225, 225, 225), 1);
    cv::putText(canvas, std::to_string(z), to_px(z, 0) + cv::Point(-4, 16), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1);
  }
  for (int k = 0; k <= 4; ++k) {
    char label[16];
    std::snprintf(label, sizeof label, "%.2f", y_max * k / 4);
    cv::putText(canvas, label, to_px(1.0, y_max * k / 4) + cv::Point(-50, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(0, 0, 0), 1);
  }
  for (std::size_t c = 0; c < curves.size(); ++c) {
    std::vector<cv::Point> line;
    for (const DepthPoint& q : curves[c])
      if (q.pixels > 1) line.push_back(to_px(q.true_m, std::abs(q.median_error_m)));
    cv::polylines(canvas, line, false, colours[c % 4], 2, cv::LINE_AA);
    for (const cv::Point& pt : line) cv::circle(canvas, pt, 3, colours[c % 4], cv::FILLED);
    cv::putText(canvas, names[c], {box.x + 10, box.y + 20 + 18 * static_cast<int>(c)}, cv::FONT_HERSHEY_SIMPLEX, 0.45,
                colours[c % 4], 1, cv::LINE_AA);
  }
  cv::putText(canvas, "|median depth error| [m] against distance [m] (thesis Figs. 3.6-3.7, simulated rig)", {70, 25},
              cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  std::vector<uint8_t> png;
  cv::imencode(".png", canvas, png);
  uav::WriteFileAtomically(path, std::string(png.begin(), png.end()));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-stereo-error: disparity accuracy, pixel locking and depth error (thesis 3.2, Tables 3.1-3.2, Figs. 3.6-3.7)"};
  std::string material = "gravel", out, plot;
  std::vector<double> depths{2.0, 3.0, 4.0};
  cli.add_option("--material", material, "texture of the planes (a scene material name)")->capture_default_str();
  cli.add_option("--depths", depths, "plane depths [m] for Tables 3.1-3.2")->delimiter(',')->capture_default_str();
  uav::OutputFile(cli.add_option("--out", out, "write everything as JSON here"));
  uav::OutputFile(cli.add_option("--plot", plot, "draw the depth error against distance (Figs. 3.6-3.7) as a PNG here"));
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  for (double z : depths)
    if (!(std::isfinite(z) && z >= 1.0 && z <= 50.0)) {
      std::fprintf(stderr, "uav-stereo-error: depth %g m is outside 1..50 m\n", z);
      return 2;
    }
  std::sort(depths.begin(), depths.end());
  nlohmann::json j;
  j["material"] = material;
  j["depths_m"] = depths;
  const double thesis_resolution[] = {0.10, 0.11, 0.10};
  const double thesis_window[] = {0.18, 0.18, 0.14, 0.11, 0.10, 0.10};
  const auto accuracy_json = [](const std::array<Accuracy, 3>& a) {
    nlohmann::json m;
    for (std::size_t k = 0; k < kMatchers.size(); ++k)
      m[kMatchers[k].name] = {{"sigma_px", a[k].sigma_px}, {"mismatch_fraction", a[k].mismatch_fraction}};
    return m;
  };
  try {
    std::printf("Table 3.1: correlation accuracy [px] against resolution (11 px window)\n\n");
    std::printf("| Resolution | thesis | SAD | SGBM | ours | mismatched (ours) |\n|---|---|---|---|---|---|\n");
    int k = 0;
    for (int width : {160, 320, 640}) {
      const std::array<Accuracy, 3> a = Tables(material, depths, width, 11);
      std::printf("| %dx%d | %.2f | %.3f | %.3f | %.3f | %.1f %% |\n", width, width * 3 / 4, thesis_resolution[k],
                  a[0].sigma_px, a[1].sigma_px, a[2].sigma_px, 100 * a[2].mismatch_fraction);
      std::fflush(stdout);
      j["resolution"].push_back(
          {{"width", width}, {"height", width * 3 / 4}, {"thesis_px", thesis_resolution[k++]}, {"matchers", accuracy_json(a)}});
    }
    std::printf("\nTable 3.2: correlation accuracy [px] against the matching window (320x240)\n\n");
    std::printf("| Window | thesis | SAD | SGBM | ours | mismatched (ours) |\n|---|---|---|---|---|---|\n");
    k = 0;
    for (int block : {5, 7, 9, 11, 13, 15}) {
      const std::array<Accuracy, 3> a = Tables(material, depths, 320, block);
      std::printf("| %d | %.2f | %.3f | %.3f | %.3f | %.1f %% |\n", block, thesis_window[k], a[0].sigma_px, a[1].sigma_px,
                  a[2].sigma_px, 100 * a[2].mismatch_fraction);
      std::fflush(stdout);
      j["window"].push_back({{"block", block}, {"thesis_px", thesis_window[k++]}, {"matchers", accuracy_json(a)}});
    }
    std::printf("\nPixel locking: a plane at 50 degrees, 320x240, 5 px window\n\n");
    std::printf("| matcher | within 1/8 px of a whole pixel (unbiased: 25 %%) | largest bias over the fraction | rms error |\n"
                "|---|---|---|---|\n");
    const std::array<Locking, 3> locking = PixelLocking(material, 5);
    for (std::size_t m = 0; m < kMatchers.size(); ++m) {
      const Locking& l = locking[m];
      std::printf("| %s | %.1f %% | %.3f px | %.3f px |\n", kMatchers[m].name, 100 * l.near_whole_fraction, l.max_bin_bias_px,
                  l.rms_px);
      j["pixel_locking"][kMatchers[m].name] = {{"near_whole_fraction", l.near_whole_fraction},
                                               {"max_bin_bias_px", l.max_bin_bias_px},
                                               {"rms_px", l.rms_px},
                                               {"fraction_histogram", l.fraction_histogram}};
    }
    std::printf("\nFigs. 3.6-3.7: median depth error [m] of a board and a trunk, the vehicle's rig (640x480 matched at 320x240)\n\n");
    std::printf("| distance | board SAD | board ours | trunk SAD | trunk ours | per-pixel spread, board ours (Eq. 3.7) |\n"
                "|---|---|---|---|---|---|\n");
    std::vector<std::vector<DepthPoint>> curves;
    std::vector<std::string> names;
    for (bool tree : {false, true})
      for (const Matcher* m : {&kMatchers[0], &kMatchers[2]}) {
        curves.push_back(DepthCurve(tree, *m));
        names.push_back(std::string(tree ? "trunk, " : "board, ") + (m->refined ? "ours" : "SAD"));
        nlohmann::json c;
        for (const DepthPoint& q : curves.back())
          c.push_back({{"true_m", q.true_m}, {"median_error_m", q.median_error_m}, {"spread_m", q.spread_m},
                       {"model_spread_m", q.model_spread_m}, {"pixels", q.pixels}});
        j["depth_error"][tree ? "trunk" : "board"][m->name] = c;
      }
    for (std::size_t i = 0; i < curves[0].size(); ++i) {
      const auto cell = [](const DepthPoint& q) {
        char buf[24];
        if (q.pixels > 1) std::snprintf(buf, sizeof buf, "%+.3f", q.median_error_m);
        else std::snprintf(buf, sizeof buf, "none");
        return std::string(buf);
      };
      std::printf("| %.1f m | %s | %s | %s | %s | %.3f (%.3f) m |\n", curves[1][i].true_m, cell(curves[0][i]).c_str(),
                  cell(curves[1][i]).c_str(), cell(curves[2][i]).c_str(), cell(curves[3][i]).c_str(), curves[1][i].spread_m,
                  curves[1][i].model_spread_m);
    }
    if (!plot.empty()) Plot(plot, curves, names);
    if (!out.empty()) uav::WriteFileAtomically(out, j.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stereo-error: %s\n", e.what());
    return 1;
  }
  return 0;
}
