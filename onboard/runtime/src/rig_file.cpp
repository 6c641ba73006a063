#include "uav/runtime/rig_file.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>

#include <nlohmann/json.hpp>
#include <opencv2/core/persistence.hpp>

#include "uav/runtime/live_camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::runtime {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr double kPi = 3.14159265358979323846;

// The workers a rig file can name, and whether each takes a stereo pair.
const std::map<std::string, bool>& Workers() {
  static const std::map<std::string, bool> w = {{"odometry", true}, {"obstacles", true}, {"wires", true}, {"active_stereo", true},
                                                {"survey", false},  {"tracking", false}, {"depth", false}};
  return w;
}

struct Reader {
  std::string file;
  [[noreturn]] void Fail(const std::string& where, const std::string& what) const {
    throw std::runtime_error("rig file '" + file + "': " + where + ": " + what);
  }
  void Only(const json& j, const std::string& where, const std::set<std::string>& allowed) const {
    if (!j.is_object()) Fail(where, "must be an object");
    for (const auto& [key, value] : j.items())
      if (!allowed.count(key)) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Fail(where, "unknown field '" + key + "' (known: " + list + ")");
      }
  }
  std::string String(const json& j, const std::string& key, const std::string& where, bool required = true) const {
    if (!j.contains(key)) {
      if (required) Fail(where, "needs \"" + key + "\"");
      return "";
    }
    if (!j[key].is_string() || j[key].get<std::string>().empty()) Fail(where + "." + key, "must be a non-empty string");
    return j[key].get<std::string>();
  }
  double Number(const json& j, const std::string& key, const std::string& where, double fallback, double lo, double hi) const {
    if (!j.contains(key)) return fallback;
    if (!j[key].is_number() || !std::isfinite(j[key].get<double>()) || j[key].get<double>() < lo || j[key].get<double>() > hi)
      Fail(where + "." + key, "must be a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return j[key].get<double>();
  }
};

std::string Resolve(const std::string& dir, const std::string& path) {
  if (path.empty() || fs::path(path).is_absolute() || dir.empty()) return path;
  return (fs::path(dir) / path).lexically_normal().string();
}

}  // namespace

CameraIntrinsics ReadCalibration(const std::string& path) {
  if (!fs::exists(path)) throw std::runtime_error("calibration '" + path + "': no such file");
  CameraIntrinsics k;
  const std::string ext = fs::path(path).extension().string();
  try {
    if (ext == ".camera") {
      k = IntrinsicsFromParameters(ParameterSet::LoadFile(path, CameraParameterSchema()));
    } else {
      // OpenCV's calibration output (samples/cpp/calibration.cpp, camera_calibration.cpp).
      cv::FileStorage fs(path, cv::FileStorage::READ);
      if (!fs.isOpened()) throw std::runtime_error("cannot read it as OpenCV YAML/XML");
      cv::Mat K, D;
      fs["camera_matrix"] >> K;
      fs["distortion_coefficients"] >> D;
      int w = 0, h = 0;
      fs["image_width"] >> w;
      fs["image_height"] >> h;
      if (K.rows != 3 || K.cols != 3) throw std::runtime_error("no 3x3 camera_matrix");
      if (w <= 0 || h <= 0) throw std::runtime_error("no image_width and image_height");
      K.convertTo(K, CV_64F);
      k.width = w, k.height = h;
      k.fx = K.at<double>(0, 0), k.fy = K.at<double>(1, 1), k.cx = K.at<double>(0, 2), k.cy = K.at<double>(1, 2);
      if (!D.empty()) {
        D.convertTo(D, CV_64F);
        if (D.total() < 4 || (D.total() > 5 && D.total() != 8 && D.total() != 12 && D.total() != 14))
          throw std::runtime_error("distortion_coefficients must hold 4, 5 or more numbers, holds " + std::to_string(D.total()));
        for (std::size_t i = 0; i < 5 && i < D.total(); ++i) k.distortion[i] = D.at<double>(static_cast<int>(i));
      }
    }
    ValidateIntrinsics(k);
  } catch (const std::exception& e) {
    throw std::runtime_error("calibration '" + path + "': " + e.what());
  }
  return k;
}

RigFile::~RigFile() = default;

std::unique_ptr<RigFile> RigFile::Load(const std::string& path, int64_t start_utime) {
  const std::string text = ReadTextFile(path, "rig file");
  return Parse(text, fs::path(path).parent_path().string(), path, start_utime);
}

std::unique_ptr<RigFile> RigFile::Parse(const std::string& text, const std::string& dir, const std::string& name,
                                        int64_t start_utime) {
  const Reader rd{name};
  json root;
  try {
    root = json::parse(text);
  } catch (const json::exception& e) {
    rd.Fail("$", std::string("not JSON: ") + e.what());
  }
  rd.Only(root, "$", {"cameras", "workers", "pose", "comment"});
  if (!root.contains("cameras") || !root["cameras"].is_object() || root["cameras"].empty())
    rd.Fail("$", "needs \"cameras\": an object naming at least one camera");
  if (!root.contains("workers") || !root["workers"].is_object() || root["workers"].empty())
    rd.Fail("$", "needs \"workers\": which camera feeds which worker (odometry, obstacles, wires, active_stereo, survey, tracking, depth)");
  std::unique_ptr<RigFile> rig(new RigFile());
  std::map<std::string, hal::Camera*> mono;
  std::map<std::string, hal::GimbalCamera*> gimbal;
  std::map<std::string, hal::StereoCamera*> stereo;
  std::map<std::string, std::string> described;
  int64_t end = -1;
  bool any_live = false;
  for (const auto& [cam_name, c] : root["cameras"].items()) {
    const std::string where = "cameras." + cam_name;
    if (!c.is_object()) rd.Fail(where, "must be an object");
    rd.Only(c, where, {"type", "path", "source", "calibration", "mount", "rate_hz", "times", "comment"});
    const std::string type = rd.String(c, "type", where);
    Eigen::Vector3d p_B = Eigen::Vector3d::Zero();
    double pitch_deg = type == "kitti" || type == "euroc" ? 0.0 : -90.0;
    if (c.contains("mount")) {
      const json& m = c["mount"];
      rd.Only(m, where + ".mount", {"xyz_m", "pitch_deg"});
      if (m.contains("xyz_m")) {
        if (!m["xyz_m"].is_array() || m["xyz_m"].size() != 3) rd.Fail(where + ".mount.xyz_m", "must be [x, y, z] in metres (body: forward, right, down)");
        for (int i = 0; i < 3; ++i) {
          if (!m["xyz_m"][i].is_number() || std::abs(m["xyz_m"][i].get<double>()) > 100)
            rd.Fail(where + ".mount.xyz_m", "must hold three numbers within 100 m");
          p_B[i] = m["xyz_m"][i].get<double>();
        }
      }
      pitch_deg = rd.Number(m, "pitch_deg", where + ".mount", pitch_deg, -90.0, 30.0);
    }
    const Eigen::Isometry3d T_BC = CameraMount(p_B, pitch_deg * kPi / 180.0);
    char rate_text[64];
    try {
      if (type == "kitti" || type == "euroc") {
        rd.Only(c, where, {"type", "path", "mount", "comment"});
        const std::string path = Resolve(dir, rd.String(c, "path", where));
        StereoRecording rec = type == "kitti" ? ReadKittiRecording(path, T_BC) : ReadEurocRecording(path);
        const bool has_truth = !rec.truth.empty(), has_imu = !rec.imu.empty();
        std::snprintf(rate_text, sizeof rate_text, "%.1f", rec.rate_hz);
        described[cam_name] = rec.layout + " sequence " + path + ", " + std::to_string(rec.frames.size()) + " pairs at " + rate_text +
                              " Hz" + (has_truth ? ", ground truth" : "") +
                              (has_imu ? ", IMU (" + std::to_string(rec.imu.size()) + " samples)" : "");
        auto cam = std::make_unique<RecordedStereoCamera>(cam_name, std::move(rec), start_utime);
        end = std::max(end, cam->end_utime() + static_cast<int64_t>(0.5e6 / cam->left().rate_hz));
        if (has_imu && !rig->imu_) {
          rig->imu_ = &cam->recording().imu;
          rig->imu_offset_us_ = cam->recording().frames.front().t_us - start_utime;
        }
        if (has_truth && !rig->truth_) {
          rig->truth_ = &cam->recording().truth;
          rig->truth_offset_us_ = cam->recording().frames.front().t_us - start_utime;
        }
        stereo[cam_name] = cam.get();
        rig->stereo_.push_back(std::move(cam));
      } else if (type == "video" || type == "photos") {
        RecordedCamera::Options o;
        o.name = cam_name;
        o.path = Resolve(dir, rd.String(c, "path", where));
        if ((type == "photos") != fs::is_directory(o.path))
          rd.Fail(where + ".path", type == "photos" ? "'" + o.path + "' is not a folder of photos" : "'" + o.path + "' is not a video file");
        o.intrinsics = ReadCalibration(Resolve(dir, rd.String(c, "calibration", where)));
        o.T_BC = T_BC;
        o.rate_hz = rd.Number(c, "rate_hz", where, 0.0, 0.0, 1000.0);
        o.times_path = Resolve(dir, rd.String(c, "times", where, false));
        o.start_utime = start_utime;
        auto cam = std::make_unique<RecordedCamera>(o);
        std::snprintf(rate_text, sizeof rate_text, "%.1f", cam->info().rate_hz);
        described[cam_name] = std::string(type == "video" ? "video " : "photos in ") + o.path + ", " + std::to_string(cam->frames()) +
                              " frames at " + rate_text + " Hz";
        end = std::max(end, cam->end_utime() + static_cast<int64_t>(0.5e6 / cam->info().rate_hz));
        mono[cam_name] = cam.get();
        gimbal[cam_name] = cam.get();
        rig->mono_.push_back(std::move(cam));
      } else if (type == "live") {
        LiveCamera::Options o;
        o.name = cam_name;
        o.source = rd.String(c, "source", where);
        // A file beside the rig file (a recorded stream read as a live one) is found from there.
        if (fs::exists(Resolve(dir, o.source))) o.source = Resolve(dir, o.source);
        o.intrinsics = ReadCalibration(Resolve(dir, rd.String(c, "calibration", where)));
        o.T_BC = T_BC;
        o.rate_hz = rd.Number(c, "rate_hz", where, 30.0, 0.1, 240.0);
        auto cam = std::make_unique<LiveCamera>(o);
        std::snprintf(rate_text, sizeof rate_text, "%.1f", o.rate_hz);
        described[cam_name] = "live '" + o.source + "' at " + rate_text + " Hz";
        any_live = true;
        mono[cam_name] = cam.get();
        gimbal[cam_name] = cam.get();
        rig->mono_.push_back(std::move(cam));
      } else {
        rd.Fail(where + ".type", "'" + type + "' is not a camera type (kitti, euroc, video, photos, live)");
      }
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      if (what.rfind("rig file", 0) == 0) throw;
      rd.Fail(where, what);
    }
  }
  std::map<std::string, std::vector<std::string>> uses;
  std::string depth;
  for (const auto& [worker, cam] : root["workers"].items()) {
    const std::string where = "workers." + worker;
    const auto kind = Workers().find(worker);
    if (kind == Workers().end()) rd.Fail(where, "not a worker (odometry, obstacles, wires, active_stereo, survey, tracking, depth)");
    if (!cam.is_string()) rd.Fail(where, "must name a camera");
    const std::string cam_name = cam.get<std::string>();
    if (worker == "depth") {
      if (cam_name != "survey" && cam_name != "tracking") rd.Fail(where, "must be \"survey\" or \"tracking\" (depth from motion on that worker's frames)");
      depth = cam_name;
      continue;
    }
    if (!stereo.count(cam_name) && !mono.count(cam_name)) rd.Fail(where, "names '" + cam_name + "', which \"cameras\" does not declare");
    if (kind->second != static_cast<bool>(stereo.count(cam_name)))
      rd.Fail(where, "'" + cam_name + "' is a " + (stereo.count(cam_name) ? "stereo pair" : "mono camera") + "; " + worker + " needs a " +
                         (kind->second ? "stereo pair" : "mono camera"));
    uses[cam_name].push_back(worker);
    if (worker == "odometry") rig->rig_.odometry = stereo[cam_name];
    if (worker == "obstacles") rig->rig_.obstacles = stereo[cam_name];
    if (worker == "wires") rig->rig_.wires = stereo[cam_name];
    if (worker == "active_stereo") rig->rig_.active_stereo = stereo[cam_name];
    if (worker == "survey") rig->rig_.survey = mono[cam_name];
    if (worker == "tracking") rig->rig_.tracking = gimbal[cam_name];
  }
  if (depth == "survey" && !rig->rig_.survey) rd.Fail("workers.depth", "\"survey\" but no camera feeds the survey worker");
  if (depth == "tracking" && !rig->rig_.tracking) rd.Fail("workers.depth", "\"tracking\" but no camera feeds the tracking worker");
  rig->rig_.depth = depth == "survey" ? SensorRig::DepthCamera::kSurvey
                    : depth == "tracking" ? SensorRig::DepthCamera::kTracking
                                          : SensorRig::DepthCamera::kNone;
  for (const auto& s : rig->stereo_) rig->rig_.stereo_pairs.push_back(s.get());
  for (const auto& [cam_name, text] : described) {
    if (!uses.count(cam_name)) rd.Fail("cameras." + cam_name, "no worker uses it (\"workers\")");
    std::string line = cam_name + ": " + text + "; ";
    for (std::size_t i = 0; i < uses[cam_name].size(); ++i) line += (i ? ", " : "") + uses[cam_name][i];
    rig->lines_.push_back(line);
  }
  const std::string pose = root.contains("pose") ? rd.String(root, "pose", "$")
                           : rig->truth_            ? "truth"
                           : rig->imu_ && rig->rig_.odometry ? "imu"
                           : rig->rig_.odometry     ? "odometry"
                                                    : "fixed";
  if (pose == "truth") {
    if (!rig->truth_) rd.Fail("pose", "\"truth\" but no recording here has ground truth");
    rig->pose_source_ = PoseSource::kTruth;
  } else if (pose == "imu") {
    if (!rig->imu_) rd.Fail("pose", "\"imu\" but no recording here has an IMU (EuRoC's imu0/)");
    if (!rig->rig_.odometry) rd.Fail("pose", "\"imu\" takes the position from the odometry, and no stereo pair feeds it");
    rig->pose_source_ = PoseSource::kImuOdometry;
  } else if (pose == "odometry") {
    if (!rig->rig_.odometry) rd.Fail("pose", "\"odometry\" but no stereo pair feeds the odometry worker");
    rig->pose_source_ = PoseSource::kOdometry;
  } else if (pose == "fixed") {
    rig->pose_source_ = PoseSource::kFixed;
  } else {
    rd.Fail("pose", "'" + pose + "' must be \"truth\", \"imu\", \"odometry\" or \"fixed\"");
  }
  rig->end_utime_ = any_live ? -1 : end;
  return rig;
}

Eigen::Isometry3d RigFile::TruthAt(int64_t utime) const {
  return truth_ ? truth_->At(utime + truth_offset_us_) : Eigen::Isometry3d::Identity();
}

std::string RigFile::Describe() const {
  std::string out;
  for (const std::string& l : lines_) out += l + "\n";
  return out;
}

}  // namespace uav::runtime
