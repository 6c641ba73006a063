#include "uav/runtime/recorded_sensors.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/image_files.hpp"
#include "uav/shared/text_file.hpp"
#include "uav/vision/kitti_odometry.hpp"

namespace uav::runtime {
namespace {

namespace fs = std::filesystem;

double MedianRate(const std::vector<RecordedFrame>& frames) {
  if (frames.size() < 2) return 1.0;
  std::vector<int64_t> dt;
  for (std::size_t i = 1; i < frames.size(); ++i) dt.push_back(frames[i].t_us - frames[i - 1].t_us);
  std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
  return 1e6 / static_cast<double>(dt[dt.size() / 2]);
}

// Times must increase: a repeated or backward time is a broken recording, refused before a run.
void CheckIncreasing(const std::vector<RecordedFrame>& frames, const std::string& what) {
  for (std::size_t i = 1; i < frames.size(); ++i)
    if (frames[i].t_us <= frames[i - 1].t_us)
      throw std::runtime_error(what + ": frame " + std::to_string(i) + " (" + fs::path(frames[i].left).filename().string() +
                               ") is at " + std::to_string(frames[i].t_us) + " us, not after frame " + std::to_string(i - 1) +
                               " at " + std::to_string(frames[i - 1].t_us) + " us (times repeat or go backwards)");
}

// An image as the workers take it: 8-bit BGR.
cv::Mat ToBgr(const cv::Mat& m) {
  if (m.empty() || m.channels() == 3) return m;
  cv::Mat bgr;
  cv::cvtColor(m, bgr, m.channels() == 4 ? cv::COLOR_BGRA2BGR : cv::COLOR_GRAY2BGR);
  return bgr;
}

hal::CameraInfo InfoOf(const std::string& name, const CameraIntrinsics& k, const Eigen::Isometry3d& T_BC, double rate_hz) {
  hal::CameraInfo info;
  info.name = name;
  info.intrinsics = k;
  info.T_BC = T_BC;
  info.rate_hz = rate_hz;
  info.preview_rate_hz = std::min(rate_hz, 5.0);
  return info;
}

std::string SizeProblem(const cv::Mat& image, const CameraIntrinsics& k) {
  if (image.cols == k.width && image.rows == k.height) return "";
  return "image is " + std::to_string(image.cols) + " x " + std::to_string(image.rows) + " px but the calibration is " +
         std::to_string(k.width) + " x " + std::to_string(k.height);
}

// The numbers of "key: [a, b, ...]" in a EuRoC sensor.yaml (lists may span lines).
std::vector<double> YamlList(const std::string& text, const std::string& key, const std::string& file) {
  const std::regex re("(^|\\n)\\s*" + key + "\\s*:\\s*\\[([^\\]]*)\\]");
  std::smatch m;
  if (!std::regex_search(text, m, re)) throw std::runtime_error(file + ": no '" + key + ": [...]'");
  std::vector<double> v;
  std::string list = m[2].str();
  std::replace(list.begin(), list.end(), ',', ' ');
  std::istringstream in(list);
  double x;
  while (in >> x) v.push_back(x);
  if (!in.eof()) throw std::runtime_error(file + ": '" + key + "' holds something that is not a number");
  return v;
}

// The "data:" list inside the T_BS block of a EuRoC sensor.yaml.
Eigen::Isometry3d YamlTransform(const std::string& text, const std::string& key, const std::string& file) {
  const std::size_t at = text.find(key + ":");
  if (at == std::string::npos) throw std::runtime_error(file + ": no '" + key + "'");
  const std::vector<double> d = YamlList(text.substr(at), "data", file);
  if (d.size() != 16) throw std::runtime_error(file + ": " + key + " needs 16 numbers, has " + std::to_string(d.size()));
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) M(i / 4, i % 4) = d[static_cast<std::size_t>(i)];
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = M.topLeftCorner<3, 3>();
  T.translation() = M.topRightCorner<3, 1>();
  if (!T.matrix().allFinite() || std::abs(T.linear().determinant() - 1.0) > 1e-3)
    throw std::runtime_error(file + ": " + key + " is not a rigid transform");
  return T;
}

// The numeric rows of an ASL CSV file (comma-separated, '#' comments), each with its line number
// and its first `columns` numbers. Throws std::runtime_error naming the file and line of a row
// with fewer finite numbers than that (`expected` says what they are).
std::vector<std::pair<int, std::vector<double>>> CsvRows(const std::string& path, const char* what, int columns,
                                                         const char* expected) {
  std::istringstream csv(ReadTextFile(path, what));
  std::vector<std::pair<int, std::vector<double>>> rows;
  std::string line;
  for (int n = 1; std::getline(csv, line); ++n) {
    if (line.empty() || line[0] == '#' || line == "\r") continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream l(line);
    std::vector<double> v(static_cast<std::size_t>(columns));
    for (double& x : v)
      if (!(l >> x) || !std::isfinite(x))
        throw std::runtime_error(path + " line " + std::to_string(n) + ": expected " + expected);
    rows.emplace_back(n, std::move(v));
  }
  return rows;
}

struct EurocCamera {
  CameraIntrinsics k;
  Eigen::Isometry3d T_BS;
  std::vector<std::pair<int64_t, std::string>> images;  // ns time, path
};

EurocCamera ReadEurocCamera(const fs::path& dir) {
  EurocCamera c;
  const std::string yaml_path = (dir / "sensor.yaml").string();
  if (!fs::exists(yaml_path)) throw std::runtime_error("EuRoC camera '" + dir.string() + "': no sensor.yaml");
  const std::string yaml = ReadTextFile(yaml_path, "camera calibration");
  if (yaml.find("pinhole") == std::string::npos) throw std::runtime_error(yaml_path + ": camera_model must be pinhole");
  const std::vector<double> res = YamlList(yaml, "resolution", yaml_path);
  const std::vector<double> in = YamlList(yaml, "intrinsics", yaml_path);
  const std::vector<double> dist = YamlList(yaml, "distortion_coefficients", yaml_path);
  if (res.size() != 2 || in.size() != 4 || dist.size() < 4 || dist.size() > 5)
    throw std::runtime_error(yaml_path + ": resolution needs 2 numbers, intrinsics 4 (fu fv cu cv), distortion_coefficients 4 or 5");
  c.k.width = static_cast<int>(res[0]);
  c.k.height = static_cast<int>(res[1]);
  c.k.fx = in[0], c.k.fy = in[1], c.k.cx = in[2], c.k.cy = in[3];
  for (std::size_t i = 0; i < dist.size(); ++i) c.k.distortion[i] = dist[i];
  try {
    ValidateIntrinsics(c.k);
  } catch (const std::exception& e) {
    throw std::runtime_error(yaml_path + ": " + e.what());
  }
  c.T_BS = YamlTransform(yaml, "T_BS", yaml_path);
  const std::string csv_path = (dir / "data.csv").string();
  if (!fs::exists(csv_path)) throw std::runtime_error("EuRoC camera '" + dir.string() + "': no data.csv");
  std::istringstream csv(ReadTextFile(csv_path, "image list"));
  std::string line;
  int n = 0;
  while (std::getline(csv, line)) {
    ++n;
    if (line.empty() || line[0] == '#') continue;
    const std::size_t comma = line.find(',');
    std::string name = comma == std::string::npos ? "" : line.substr(comma + 1);
    while (!name.empty() && (name.back() == '\r' || name.back() == ' ')) name.pop_back();
    while (!name.empty() && name.front() == ' ') name.erase(name.begin());
    int64_t t = 0;
    try {
      std::size_t used = 0;
      t = std::stoll(line.substr(0, comma), &used);
      if (used != comma) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw std::runtime_error(csv_path + " line " + std::to_string(n) + ": expected 'timestamp_ns,filename', got '" + line + "'");
    }
    if (name.empty()) throw std::runtime_error(csv_path + " line " + std::to_string(n) + ": no file name");
    c.images.emplace_back(t, (dir / "data" / name).string());
  }
  if (c.images.empty()) throw std::runtime_error(csv_path + ": no images listed");
  return c;
}

}  // namespace

Eigen::Isometry3d CameraMount(const Eigen::Vector3d& p_B, double pitch_rad) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()).toRotationMatrix() * RotationBCForward();
  T.translation() = p_B;
  return T;
}

RecordedTruth::RecordedTruth(std::vector<RecordedPose> poses) : poses_(std::move(poses)) {
  std::sort(poses_.begin(), poses_.end(), [](const RecordedPose& a, const RecordedPose& b) { return a.t_us < b.t_us; });
}

Eigen::Isometry3d RecordedTruth::At(int64_t t_us) const {
  if (poses_.empty()) return Eigen::Isometry3d::Identity();
  if (t_us <= poses_.front().t_us) return poses_.front().T_NB;
  if (t_us >= poses_.back().t_us) return poses_.back().T_NB;
  const auto b = std::upper_bound(poses_.begin(), poses_.end(), t_us, [](int64_t t, const RecordedPose& p) { return t < p.t_us; });
  const auto a = b - 1;
  const double s = static_cast<double>(t_us - a->t_us) / static_cast<double>(b->t_us - a->t_us);
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(a->T_NB.linear()).slerp(s, Eigen::Quaterniond(b->T_NB.linear())).toRotationMatrix();
  T.translation() = (1 - s) * a->T_NB.translation() + s * b->T_NB.translation();
  return T;
}

int RecordedFrameAt(const std::vector<RecordedFrame>& frames, int64_t start_utime, int64_t utime) {
  if (frames.empty()) return -1;
  const int64_t t0 = frames.front().t_us;
  const int64_t period = frames.size() > 1 ? (frames.back().t_us - t0) / static_cast<int64_t>(frames.size() - 1) : 0;
  const int64_t t = utime - start_utime + t0 + period / 4;
  const auto it = std::upper_bound(frames.begin(), frames.end(), t, [](int64_t x, const RecordedFrame& f) { return x < f.t_us; });
  return static_cast<int>(it - frames.begin()) - 1;
}

StereoRecording ReadKittiRecording(const std::string& dir, const Eigen::Isometry3d& T_BL) {
  const vision::KittiSequence seq = vision::ReadKittiSequence(dir);
  StereoRecording r;
  r.dir = dir;
  r.layout = "KITTI";
  const vision::RectifiedGeometry& g = seq.geometry;
  r.left.width = r.right.width = g.width;
  r.left.height = r.right.height = g.height;
  r.left.fx = r.left.fy = r.right.fx = r.right.fy = g.f_px;
  r.left.cx = r.right.cx = g.cx;
  r.left.cy = r.right.cy = g.cy;
  r.T_BL = T_BL;
  Eigen::Isometry3d T_LR = Eigen::Isometry3d::Identity();
  T_LR.translation() = Eigen::Vector3d(g.baseline_m, 0, 0);
  r.T_BR = T_BL * T_LR;
  for (std::size_t i = 0; i < seq.left.size(); ++i)
    r.frames.push_back({static_cast<int64_t>(std::llround(seq.times_s[i] * 1e6)), seq.left[i], seq.right[i]});
  CheckIncreasing(r.frames, "KITTI sequence '" + dir + "'");
  r.rate_hz = MedianRate(r.frames);
  // Ground truth: poses.txt beside the images, or KITTI's own ../poses/<sequence>.txt.
  fs::path poses = fs::path(dir) / "poses.txt";
  if (!fs::exists(poses)) poses = fs::path(dir).parent_path().parent_path() / "poses" / (fs::path(dir).filename().string() + ".txt");
  if (fs::exists(poses)) {
    const std::vector<Eigen::Isometry3d> T_C0C = vision::ReadKittiPoses(poses.string());
    if (T_C0C.size() != r.frames.size())
      throw std::runtime_error(poses.string() + " has " + std::to_string(T_C0C.size()) + " poses for " +
                               std::to_string(r.frames.size()) + " frames");
    // The body starts at the origin of N, level and heading north: T_NB_i = T_BL T_C0Ci T_BL^-1.
    std::vector<RecordedPose> truth;
    for (std::size_t i = 0; i < T_C0C.size(); ++i) truth.push_back({r.frames[i].t_us, T_BL * T_C0C[i] * T_BL.inverse()});
    r.truth = RecordedTruth(std::move(truth));
  }
  return r;
}

StereoRecording ReadEurocRecording(const std::string& dir_in) {
  fs::path dir = dir_in;
  if (fs::exists(dir / "mav0")) dir /= "mav0";
  const EurocCamera left = ReadEurocCamera(dir / "cam0");
  const EurocCamera right = ReadEurocCamera(dir / "cam1");
  StereoRecording r;
  r.dir = dir.string();
  r.layout = "EuRoC";
  r.left = left.k;
  r.right = right.k;
  r.T_BL = left.T_BS;
  r.T_BR = right.T_BS;
  // Pairs by time: EuRoC's cameras are triggered together, so each left image has a right one
  // at the same nanosecond.
  std::size_t j = 0;
  for (const auto& [t, path] : left.images) {
    while (j < right.images.size() && right.images[j].first < t) ++j;
    if (j >= right.images.size() || right.images[j].first != t)
      throw std::runtime_error(r.dir + "/cam1: no right image at " + std::to_string(t) + " ns (left " +
                               fs::path(path).filename().string() + ")");
    r.frames.push_back({t / 1000, path, right.images[j].second});
  }
  CheckIncreasing(r.frames, "EuRoC cam0 '" + r.dir + "'");
  r.rate_hz = MedianRate(r.frames);
  const fs::path imu = dir / "imu0" / "data.csv";
  if (fs::exists(imu)) {
    Eigen::Matrix3d R_BS = Eigen::Matrix3d::Identity();
    if (fs::exists(dir / "imu0" / "sensor.yaml"))
      R_BS = YamlTransform(ReadTextFile((dir / "imu0" / "sensor.yaml").string(), "IMU calibration"), "T_BS",
                           (dir / "imu0" / "sensor.yaml").string())
                 .linear();
    for (const auto& [n, v] : CsvRows(imu.string(), "IMU samples", 7, "timestamp, w_RS_S and a_RS_S")) {
      const int64_t t_us = static_cast<int64_t>(v[0] / 1000);
      if (!r.imu.empty() && t_us <= r.imu.back().t_us)
        throw std::runtime_error(imu.string() + " line " + std::to_string(n) + ": the time repeats or goes backwards");
      r.imu.push_back({t_us, R_BS * Eigen::Vector3d(v[1], v[2], v[3]), R_BS * Eigen::Vector3d(v[4], v[5], v[6])});
    }
  }
  const fs::path gt = dir / "state_groundtruth_estimate0" / "data.csv";
  if (fs::exists(gt)) {
    // timestamp, p_RS_R (x y z), q_RS (w x y z), ...: the IMU S in the world R (z up).
    Eigen::Matrix3d R_NR = Eigen::Vector3d(1, -1, -1).asDiagonal();
    std::vector<RecordedPose> truth;
    for (const auto& [n, v] : CsvRows(gt.string(), "ground truth", 8, "timestamp, position and quaternion")) {
      RecordedPose p;
      p.t_us = static_cast<int64_t>(v[0] / 1000);
      p.T_NB.linear() = R_NR * Eigen::Quaterniond(v[4], v[5], v[6], v[7]).normalized().toRotationMatrix();
      p.T_NB.translation() = R_NR * Eigen::Vector3d(v[1], v[2], v[3]);
      truth.push_back(p);
    }
    // N's origin where the body starts.
    if (!truth.empty()) {
      const RecordedTruth all(truth);
      const Eigen::Vector3d p0 = all.At(r.frames.front().t_us).translation();
      for (RecordedPose& p : truth) p.T_NB.translation() -= p0;
      r.truth = RecordedTruth(std::move(truth));
    }
  }
  return r;
}

std::string StereoLayoutOf(const std::string& dir) {
  const fs::path d = dir;
  if (fs::exists(d / "image_0") && fs::exists(d / "image_1") && fs::exists(d / "calib.txt")) return "KITTI";
  if (fs::exists(d / "cam0" / "data.csv") || fs::exists(d / "mav0" / "cam0" / "data.csv")) return "EuRoC";
  return "";
}

RecordedStereoCamera::RecordedStereoCamera(const std::string& name, StereoRecording recording, int64_t start_utime)
    : rec_(std::move(recording)), start_utime_(start_utime) {
  left_ = InfoOf(name, rec_.left, rec_.T_BL, rec_.rate_hz);
  right_ = InfoOf(name + " right", rec_.right, rec_.T_BR, rec_.rate_hz);
  const cv::Mat first = cv::imread(rec_.frames.front().left, cv::IMREAD_UNCHANGED);
  if (first.empty()) throw std::runtime_error(rec_.frames.front().left + ": cannot read it as an image");
  if (const std::string p = SizeProblem(first, rec_.left); !p.empty())
    throw std::runtime_error(rec_.layout + " sequence '" + rec_.dir + "': " + p);
}

int64_t RecordedStereoCamera::end_utime() const { return start_utime_ + rec_.frames.back().t_us - rec_.frames.front().t_us; }

std::string RecordedStereoCamera::problem() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return problem_;
}

hal::StereoImages RecordedStereoCamera::Capture(int64_t utime, hal::Emitter) {
  hal::StereoImages out;
  const int i = RecordedFrameAt(rec_.frames, start_utime_, utime);
  std::string problem;
  if (i < 0) {
    problem = "the recording has not started";
  } else if (i + 1 == static_cast<int>(rec_.frames.size()) && utime > end_utime() + static_cast<int64_t>(2e6 / rec_.rate_hz)) {
    problem = "the recording ended (" + std::to_string(rec_.frames.size()) + " pairs)";
  } else {
    const RecordedFrame& f = rec_.frames[static_cast<std::size_t>(i)];
    {
      std::lock_guard<std::mutex> reading(read_mutex_);
      if (read_index_ != i) {
        read_left_ = ToBgr(cv::imread(f.left, cv::IMREAD_UNCHANGED));
        read_right_ = ToBgr(cv::imread(f.right, cv::IMREAD_UNCHANGED));
        read_index_ = i;
      }
      // Each worker its own copy: none of them can change another's.
      out.left = read_left_.clone();
      out.right = read_right_.clone();
    }
    out.left_utime = out.right_utime = start_utime_ + f.t_us - rec_.frames.front().t_us;
    for (const auto& [image, path, k] : {std::tie(out.left, f.left, rec_.left), std::tie(out.right, f.right, rec_.right)}) {
      std::string p = image.empty() ? "cannot read it as an image" : SizeProblem(image, k);
      if (!p.empty() && problem.empty()) problem = fs::path(path).filename().string() + ": " + p;
    }
    if (!problem.empty()) out.left.release(), out.right.release();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  problem_ = problem;
  return out;
}

RecordedCamera::RecordedCamera(const Options& o) : options_(o) {
  const fs::path path = o.path;
  auto fail = [&](const std::string& what) { throw std::runtime_error("recorded camera '" + o.path + "': " + what); };
  std::vector<double> times_s;
  if (!o.times_path.empty()) {
    const std::string text = ReadTextFile(o.times_path, "frame times");
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::replace(line.begin(), line.end(), ',', ' ');
      std::istringstream l(line);
      double t;
      if (!(l >> t) || !std::isfinite(t)) fail(o.times_path + ": '" + line + "' does not start with a time");
      // EuRoC's data.csv holds nanoseconds; a times file, seconds.
      times_s.push_back(t > 1e12 ? t * 1e-9 : t);
    }
  }
  if (fs::is_directory(path)) {
    const std::vector<std::string> images = ImageFilesIn(o.path);
    if (images.empty()) fail("no images (.png/.jpg/.pgm) in the folder");
    bool named_by_time = times_s.empty() && o.rate_hz <= 0;
    if (named_by_time)
      for (const std::string& f : images)
        if (!std::regex_match(fs::path(f).stem().string(), std::regex("[0-9]{10,20}"))) named_by_time = false;
    if (times_s.empty() && !named_by_time && o.rate_hz <= 0)
      fail("no frame times: give a times file (seconds, one a line), name the photos by their time in ns, or give a rate");
    if (!times_s.empty() && times_s.size() != images.size())
      fail(std::to_string(times_s.size()) + " times for " + std::to_string(images.size()) + " photos");
    for (std::size_t i = 0; i < images.size(); ++i) {
      const int64_t t = !times_s.empty() ? static_cast<int64_t>(std::llround(times_s[i] * 1e6))
                        : named_by_time  ? std::stoll(fs::path(images[i]).stem().string()) / 1000
                                         : static_cast<int64_t>(std::llround(i * 1e6 / o.rate_hz));
      frames_.push_back({t, images[i], ""});
    }
  } else {
    if (!fs::exists(path)) fail("no such file or folder");
    video_ = std::make_unique<cv::VideoCapture>(o.path);
    if (!video_->isOpened()) fail("cannot open it as a video");
    const int count = static_cast<int>(video_->get(cv::CAP_PROP_FRAME_COUNT));
    const double fps = o.rate_hz > 0 ? o.rate_hz : video_->get(cv::CAP_PROP_FPS);
    if (!times_s.empty()) {
      for (std::size_t i = 0; i < times_s.size(); ++i) frames_.push_back({static_cast<int64_t>(std::llround(times_s[i] * 1e6)), "", ""});
    } else {
      if (!(fps > 0 && fps < 1000)) fail("the video gives no frame rate: give one, or a times file");
      if (count <= 0) fail("the video gives no frame count: give a times file");
      for (int i = 0; i < count; ++i) frames_.push_back({static_cast<int64_t>(std::llround(i * 1e6 / fps)), "", ""});
    }
  }
  CheckIncreasing(frames_, "recorded camera '" + o.path + "'");
  info_ = InfoOf(o.name, o.intrinsics, o.T_BC, MedianRate(frames_));
  pitch_rad_ = std::asin(std::clamp(-(o.T_BC.linear() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0));
  // The first frame must be what the calibration describes.
  const cv::Mat first = video_ ? ReadVideoFrame(0) : cv::imread(frames_.front().left, cv::IMREAD_UNCHANGED);
  if (first.empty()) fail("cannot read its first frame");
  if (const std::string p = SizeProblem(first, o.intrinsics); !p.empty()) fail(p);
}

RecordedCamera::~RecordedCamera() = default;

int64_t RecordedCamera::end_utime() const { return options_.start_utime + frames_.back().t_us - frames_.front().t_us; }

std::string RecordedCamera::problem() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return problem_;
}

cv::Mat RecordedCamera::ReadVideoFrame(int index) {
  // A video is read forward; a frame behind the reader (not in a normal run) means a seek.
  if (index < video_next_) {
    video_->set(cv::CAP_PROP_POS_FRAMES, index);
    video_next_ = index;
  }
  cv::Mat frame;
  while (video_next_ <= index) {
    if (!video_->read(frame)) return {};
    ++video_next_;
  }
  return frame;
}

hal::CameraFrame RecordedCamera::Capture(int64_t utime) {
  std::lock_guard<std::mutex> reading(read_mutex_);  // one reader of the video at a time
  hal::CameraFrame out;
  const int i = RecordedFrameAt(frames_, options_.start_utime, utime);
  std::string problem;
  if (i < 0) {
    problem = "the recording has not started";
  } else if (i + 1 == static_cast<int>(frames_.size()) && utime > end_utime() + static_cast<int64_t>(2e6 / info_.rate_hz)) {
    problem = "the recording ended (" + std::to_string(frames_.size()) + " frames)";
  } else {
    const cv::Mat image = video_ ? ReadVideoFrame(i) : cv::imread(frames_[static_cast<std::size_t>(i)].left, cv::IMREAD_UNCHANGED);
    const std::string what = video_ ? "frame " + std::to_string(i) : fs::path(frames_[static_cast<std::size_t>(i)].left).filename().string();
    problem = image.empty() ? what + ": cannot read it" : SizeProblem(image, options_.intrinsics);
    if (problem.empty()) out.image = ToBgr(image);
    else if (!image.empty()) problem = what + ": " + problem;
  }
  std::lock_guard<std::mutex> lock(mutex_);
  problem_ = problem;
  return out;
}

}  // namespace uav::runtime
