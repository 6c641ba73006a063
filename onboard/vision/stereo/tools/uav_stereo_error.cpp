// uav-stereo-error [--material M] [--depths 2,3,4] [--out table.json]: reproduces thesis Tables
// 3.1 and 3.2 (3.2.1, stereo correlation accuracy) in the simulator. A textured plane faces the
// rig at known depths; the disparity of every pixel is compared with the renderer's exact one.
// The correlation accuracy is the standard deviation of the disparity error over the matched
// pixels (those within 1 px of the truth: the estimation error of 3.2.2); pixels off by more are
// counted apart as mismatches (correlation errors). Table 3.1 varies the resolution at an 11 px
// window, Table 3.2 the window at 320x240. Prints both as Markdown and writes JSON with --out.
#include <cmath>
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/disparity.hpp"
#include "uav/world/renderer.hpp"
#include "uav/shared/decimal.hpp"

namespace {

struct Accuracy {
  double sigma_px = 0.0;       // std of the error over matched pixels
  double mismatch_fraction = 0.0;
  long matched = 0;
};

Accuracy Measure(const std::string& material, const std::vector<double>& depths, int width, int block) {
  uav::world::Scene scene(11);
  scene.SetSky(false);
  uav::world::CameraSetup camera;
  camera.name = "stereo";
  // The simulator's stereo camera (66 deg field of view) at this resolution.
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
  const uav::world::StereoSetup setup = uav::world::MakeStereoSetup(camera, T_B_rig, 0.12, {});
  uav::vision::DisparityParams params;
  params.downscale = 1;
  params.block_size = block;
  params.texture_threshold = 0.0;
  params.num_disparities = 16 * static_cast<int>(std::ceil(513.5 * scale * 0.12 / depths.front() * 1.5 / 16.0 + 1));
  const uav::vision::DisparityMatcher matcher(params);
  double sum = 0, sum2 = 0;
  long matched = 0, total = 0;
  for (std::size_t i = 0; i < depths.size(); ++i) {
    uav::world::Scene s(11 + i);
    s.SetSky(false);
    s.AddBox("wall", Eigen::Vector3d(depths[i] + 0.05, 0, -1.5), Eigen::Vector3d(0.1, 60, 40), 0.0, material);
    const uav::world::StereoRenderer renderer(s, setup);
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.translation() = Eigen::Vector3d(0, 0, -1.5);
    const uav::world::StereoFrame f = renderer.Render(T_NB, 1000000);
    const uav::vision::DisparityMap d = matcher.Compute(f.left.image, f.right.image);
    for (int v = 0; v < d.d16.rows; ++v)
      for (int u = params.num_disparities; u < d.d16.cols; ++u) {
        const float truth = f.disparity.at<float>(v, u);
        if (!(truth > 0)) continue;
        ++total;
        const int16_t e16 = d.d16.at<int16_t>(v, u);
        if (e16 <= 0) continue;
        const double error = e16 / 16.0 - truth;
        if (std::abs(error) > 1.0) continue;
        sum += error;
        sum2 += error * error;
        ++matched;
      }
  }
  Accuracy a;
  a.matched = matched;
  if (matched > 1) {
    const double mean = sum / matched;
    a.sigma_px = std::sqrt(std::max(0.0, sum2 / matched - mean * mean));
  }
  a.mismatch_fraction = total > 0 ? 1.0 - static_cast<double>(matched) / total : 1.0;
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-stereo-error: disparity standard deviation against resolution and window (thesis Tables 3.1-3.2)"};
  std::string material = "gravel", out;
  std::vector<double> depths{2.0, 3.0, 4.0};
  cli.add_option("--material", material, "texture of the plane (a scene material name)")->capture_default_str();
  cli.add_option("--depths", depths, "plane depths [m]")->delimiter(',')->capture_default_str();
  cli.add_option("--out", out, "write the tables as JSON here");
  uav::RequireDecimalNumbers(cli);
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
  try {
    std::printf("Table 3.1: correlation accuracy against resolution (11 px window)\n\n");
    std::printf("| Resolution | thesis [px] | ours [px] | mismatched |\n|---|---|---|---|\n");
    int k = 0;
    for (int width : {160, 320, 640}) {
      const Accuracy a = Measure(material, depths, width, 11);
      std::printf("| %dx%d | %.2f | %.3f | %.1f %% |\n", width, width * 3 / 4, thesis_resolution[k], a.sigma_px,
                  100 * a.mismatch_fraction);
      std::fflush(stdout);
      j["resolution"].push_back({{"width", width}, {"height", width * 3 / 4}, {"thesis_px", thesis_resolution[k++]},
                                 {"sigma_px", a.sigma_px}, {"mismatch_fraction", a.mismatch_fraction}});
    }
    std::printf("\nTable 3.2: correlation accuracy against the matching window (320x240)\n\n");
    std::printf("| Window | thesis [px] | ours [px] | mismatched |\n|---|---|---|---|\n");
    k = 0;
    for (int block : {5, 7, 9, 11, 13, 15}) {
      const Accuracy a = Measure(material, depths, 320, block);
      std::printf("| %d | %.2f | %.3f | %.1f %% |\n", block, thesis_window[k], a.sigma_px, 100 * a.mismatch_fraction);
      std::fflush(stdout);
      j["window"].push_back({{"block", block}, {"thesis_px", thesis_window[k++]}, {"sigma_px", a.sigma_px},
                             {"mismatch_fraction", a.mismatch_fraction}});
    }
    if (!out.empty()) uav::WriteFileAtomically(out, j.dump(2) + "\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-stereo-error: %s\n", e.what());
    return 1;
  }
  return 0;
}
