// uav-render: renders a scene file from a vehicle pose with the scene's cameras and writes the
// image and its ground truth (depth, object ids; disparity for the stereo pair) as PNG files.
#include <chrono>
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/world/renderer.hpp"
#include "uav/shared/decimal.hpp"
#include "uav/shared/program.hpp"

namespace {

std::vector<double> ParseList(const std::string& text, const char* what, size_t lo, size_t hi) {
  std::vector<double> v;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    char* end = nullptr;
    const double x = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || *end != '\0' || !std::isfinite(x))
      throw std::invalid_argument(std::string(what) + ": '" + item + "' is not a number");
    v.push_back(x);
  }
  if (v.size() < lo || v.size() > hi)
    throw std::invalid_argument(std::string(what) + " needs " + std::to_string(lo) + ".." + std::to_string(hi) + " values");
  return v;
}

cv::Mat Colourise(const cv::Mat& values, double lo, double hi) {
  cv::Mat scaled, out;
  values.convertTo(scaled, CV_8U, 255.0 / (hi - lo), -lo * 255.0 / (hi - lo));
  cv::applyColorMap(scaled, out, cv::COLORMAP_TURBO);
  out.setTo(cv::Scalar(0, 0, 0), values <= 0);
  return out;
}

cv::Mat IdImage(const cv::Mat& ids) {
  cv::Mat out(ids.size(), CV_8UC3);
  for (int v = 0; v < ids.rows; ++v)
    for (int u = 0; u < ids.cols; ++u) {
      const uint32_t id = ids.at<uint16_t>(v, u);
      const uint32_t h = id * 2654435761u;
      out.at<cv::Vec3b>(v, u) = id == 0 ? cv::Vec3b(0, 0, 0) : cv::Vec3b(h >> 24, (h >> 16) & 255, (h >> 8) & 255);
    }
  return out;
}

void Write(const std::string& path, const cv::Mat& image) {
  if (!cv::imwrite(path, image)) throw std::runtime_error("cannot write '" + path + "'");
  std::printf("  wrote %s\n", path.c_str());
}

void WriteFrame(const std::string& prefix, const uav::world::Frame& f) {
  Write(prefix + ".png", f.image);
  double max_depth = 0;
  cv::minMaxLoc(f.depth, nullptr, &max_depth);
  Write(prefix + "_depth.png", Colourise(f.depth, 0, std::max(1.0, max_depth)));
  Write(prefix + "_ids.png", IdImage(f.object_id));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-render: render a scene file with its cameras, plus ground truth"};
  std::string scene_path, pose_text = "0,0,-10,0", camera = "downward", out = "render";
  double time_s = 0;
  cli.add_option("scene", scene_path, "scene file (resources/scenes/*.scene.json)")->required();
  cli.add_option("--pose", pose_text, "vehicle pose N,E,D[,yaw[,pitch[,roll]]] (m, deg)")->capture_default_str();
  cli.add_option("--camera", camera, "downward or stereo")->check(CLI::IsMember({"downward", "stereo"}))->capture_default_str();
  cli.add_option("--time", time_s, "simulated time (s): clouds drift, noise changes")->check(CLI::Range(0.0, 1e7));
  uav::OutputFile(cli.add_option("--out", out, "output prefix"), "_left.png")->capture_default_str();
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    const auto pose = ParseList(pose_text, "--pose", 3, 6);
    const uav::world::Scene scene = uav::world::Scene::LoadFile(scene_path);
    uav::EulerAngles e;
    e.psi = (pose.size() > 3 ? pose[3] : 0) * M_PI / 180;
    e.theta = (pose.size() > 4 ? pose[4] : 0) * M_PI / 180;
    e.phi = (pose.size() > 5 ? pose[5] : 0) * M_PI / 180;
    Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
    T_NB.linear() = uav::RotationNBFromEuler(e);
    T_NB.translation() = Eigen::Vector3d(pose[0], pose[1], pose[2]);
    const int64_t utime = static_cast<int64_t>(time_s * 1e6);
    const auto t0 = std::chrono::steady_clock::now();
    if (camera == "downward") {
      if (!scene.downward_camera()) throw std::runtime_error(scene_path + ": the scene declares no downward camera");
      const uav::world::Renderer r(scene, *scene.downward_camera());
      const auto f = r.Render(T_NB * scene.downward_camera()->T_BC, utime);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      std::printf("uav-render: %s, downward camera, %.1f ms, exposure gain %.2f\n", scene.name().c_str(), ms, f.exposure_gain);
      WriteFrame(out, f);
    } else {
      if (!scene.stereo_camera()) throw std::runtime_error(scene_path + ": the scene declares no stereo camera");
      const uav::world::StereoRenderer r(scene, *scene.stereo_camera());
      const auto f = r.Render(T_NB, utime);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      int visible = 0;
      for (const auto& d : f.left.laser_dots) visible += d.visible;
      std::printf("uav-render: %s, stereo pair, %.1f ms, %d laser dots visible in the left image\n",
                  scene.name().c_str(), ms, visible);
      WriteFrame(out + "_left", f.left);
      WriteFrame(out + "_right", f.right);
      double max_disp = 0;
      cv::minMaxLoc(f.disparity, nullptr, &max_disp);
      Write(out + "_disparity.png", Colourise(f.disparity, 0, std::max(1.0, max_disp)));
      // The true disparity in uav-stereo's format (16-bit, disparity x 16, 0 unknown), to score a
      // matcher with `uav-stereo --truth <out>_disparity16.png --truth-scale 16`.
      cv::Mat truth_x16;
      f.disparity.convertTo(truth_x16, CV_16U, 16.0);
      Write(out + "_disparity16.png", truth_x16);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "uav-render: %s\n", e.what());
    return 2;
  }
}
