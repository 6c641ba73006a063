#pragma once
// Real recordings for the runtime's tests: the KITTI development sequence of ../shared/data
// (UAV_SHARED_DATA), copies of parts of it in the layouts the recorded back-ends read (KITTI,
// EuRoC/ASL, a photo folder), a small video, and temporary folders that clean up after
// themselves.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/shared/camera_intrinsics.hpp"

namespace uav::runtime {

inline std::string KittiDir() { return std::string(UAV_SHARED_DATA) + "/kitti_vo"; }

class TempDir {
 public:
  explicit TempDir(const std::string& name)
      : path_((std::filesystem::temp_directory_path() / ("uav_runtime_" + name + "_" + std::to_string(::getpid()))).string()) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

inline std::string FrameName(int i) {
  char name[16];
  std::snprintf(name, sizeof name, "%06d.png", i);
  return name;
}

// The first `frames` pairs of the KITTI sequence, with calib.txt and their poses, in dir/seq.
inline std::string CopyKitti(const std::string& dir, int frames) {
  namespace fs = std::filesystem;
  const std::string seq = dir + "/seq";
  fs::create_directories(seq + "/image_0");
  fs::create_directories(seq + "/image_1");
  for (int i = 0; i < frames; ++i)
    for (const char* side : {"/image_0/", "/image_1/"}) fs::copy_file(KittiDir() + side + FrameName(i), seq + side + FrameName(i));
  fs::copy_file(KittiDir() + "/calib.txt", seq + "/calib.txt");
  std::ifstream in(KittiDir() + "/poses.txt");
  std::ofstream out(seq + "/poses.txt");
  std::string line;
  for (int i = 0; i < frames && std::getline(in, line); ++i) out << line << "\n";
  return seq;
}

// The first `frames` left images as a photo folder dir/photos.
inline std::string CopyKittiLeft(const std::string& dir, int frames) {
  namespace fs = std::filesystem;
  const std::string photos = dir + "/photos";
  fs::create_directories(photos);
  for (int i = 0; i < frames; ++i) fs::copy_file(KittiDir() + "/image_0/" + FrameName(i), photos + "/" + FrameName(i));
  return photos;
}

inline CameraIntrinsics KittiIntrinsics() {
  CameraIntrinsics k;
  k.width = 1226, k.height = 370;
  k.fx = k.fy = 707.0912;
  k.cx = 601.8873, k.cy = 183.1104;
  return k;
}

inline CameraIntrinsics SmallIntrinsics() {
  CameraIntrinsics k;
  k.width = 320, k.height = 240;
  k.fx = k.fy = 300;
  k.cx = 159.5, k.cy = 119.5;
  return k;
}

// EuRoC's nanosecond timestamps, at KITTI's 10 Hz (the drive at its own speed).
inline int64_t EurocTime(int i) { return 1403636579763555584LL + i * 100'000'000LL; }

// KITTI's left camera poses as the body's in N (the camera looks along the body's x, the body
// starts at the origin, level, heading north), and the time of frame i (10 Hz).
inline std::vector<Eigen::Isometry3d> KittiBodyPoses_N() {
  std::vector<Eigen::Isometry3d> T;
  std::ifstream in(KittiDir() + "/poses.txt");
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();
  T_BC.linear() << 0, 0, 1, 1, 0, 0, 0, 1, 0;
  for (std::string line; std::getline(in, line);) {
    std::istringstream l(line);
    Eigen::Matrix<double, 3, 4> P;
    for (int i = 0; i < 12; ++i) l >> P(i / 4, i % 4);
    Eigen::Isometry3d T_C0C = Eigen::Isometry3d::Identity();
    T_C0C.linear() = P.leftCols<3>();
    T_C0C.translation() = P.col(3);
    T.push_back(T_BC * T_C0C * T_BC.inverse());
  }
  return T;
}

// What an IMU on that body measures at 200 Hz (EuRoC's imu0/data.csv, ns) when frame i is at
// EurocTime(i): the rate of the rotation between the truth's frames and the specific force of
// the velocity's change between them (a_N minus gravity, in B), each held over its 0.1 s.
inline void WriteKittiImu(const std::string& path, int frames) {
  const std::vector<Eigen::Isometry3d> T = KittiBodyPoses_N();
  std::ofstream csv(path);
  csv.precision(12);
  csv << "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y,w_RS_S_z,a_RS_S_x [m s^-2],a_RS_S_y,a_RS_S_z\n";
  const double dt = 0.1;
  for (int i = 0; i + 1 < frames; ++i) {
    const Eigen::AngleAxisd d(T[i].linear().transpose() * T[i + 1].linear());
    const Eigen::Vector3d w_B = d.axis() * d.angle() / dt;
    const Eigen::Vector3d v0 = i > 0 ? Eigen::Vector3d((T[i].translation() - T[i - 1].translation()) / dt)
                                     : Eigen::Vector3d((T[1].translation() - T[0].translation()) / dt);
    const Eigen::Vector3d v1 = (T[i + 1].translation() - T[i].translation()) / dt;
    const Eigen::Vector3d f_N = (v1 - v0) / dt - Eigen::Vector3d(0, 0, 9.80665);
    for (int k = 0; k < 20; ++k) {
      // The attitude within the step, for the specific force in B.
      const Eigen::Matrix3d R = T[i].linear() * Eigen::AngleAxisd(d.angle() * k / 20.0, d.axis()).toRotationMatrix();
      const Eigen::Vector3d f_B = R.transpose() * f_N;
      csv << EurocTime(i) + k * 5'000'000LL << "," << w_B.x() << "," << w_B.y() << "," << w_B.z() << "," << f_B.x() << ","
          << f_B.y() << "," << f_B.z() << "\n";
    }
  }
}

// A EuRoC/ASL folder (dir/mav0) of the first `frames` KITTI pairs: cam0/ cam1/ with data.csv and
// sensor.yaml (the given resolution), and a ground truth that moves 0.1 m a frame along the
// z-up world's y (with `imu`: KITTI's own truth, and the IMU it implies in imu0/). Returns the
// mav0 path.
inline std::string MakeEuroc(const std::string& dir, int frames, int width = 1226, int height = 370, bool imu = false) {
  namespace fs = std::filesystem;
  const std::string mav0 = dir + "/mav0";
  const char* sides[] = {"/image_0/", "/image_1/"};
  for (int c = 0; c < 2; ++c) {
    const std::string cam = mav0 + "/cam" + std::to_string(c);
    fs::create_directories(cam + "/data");
    std::ofstream csv(cam + "/data.csv");
    csv << "#timestamp [ns],filename\n";
    for (int i = 0; i < frames; ++i) {
      fs::copy_file(KittiDir() + sides[c] + FrameName(i), cam + "/data/" + std::to_string(EurocTime(i)) + ".png");
      csv << EurocTime(i) << "," << EurocTime(i) << ".png\n";
    }
    // The camera looks along the IMU's x; the right one 0.537 m to its right.
    std::ofstream yaml(cam + "/sensor.yaml");
    yaml << "sensor_type: camera\ncomment: made from KITTI frames\nT_BS:\n  cols: 4\n  rows: 4\n  data: [0, 0, 1, 0.1,\n"
         << "         1, 0, 0, " << (c == 0 ? 0.0 : 0.537) << ",\n         0, 1, 0, 0,\n         0, 0, 0, 1]\n"
         << "rate_hz: 10\nresolution: [" << width << ", " << height << "]\ncamera_model: pinhole\n"
         << "intrinsics: [707.0912, 707.0912, 601.8873, 183.1104] #fu, fv, cu, cv\n"
         << "distortion_model: radial-tangential\ndistortion_coefficients: [0.0, 0.0, 0.0, 0.0]\n";
  }
  fs::create_directories(mav0 + "/state_groundtruth_estimate0");
  std::ofstream gt(mav0 + "/state_groundtruth_estimate0/data.csv");
  gt.precision(12);
  gt << "#timestamp, p_RS_R_x [m], p_RS_R_y [m], p_RS_R_z [m], q_RS_w [], q_RS_x [], q_RS_y [], q_RS_z []\n";
  if (!imu) {
    for (int i = 0; i < frames; ++i) gt << EurocTime(i) << ",4.0," << 2.0 + 0.1 * i << ",1.0,1,0,0,0\n";
    return mav0;
  }
  // The world R is z-up: a half turn about x from N.
  const std::vector<Eigen::Isometry3d> T = KittiBodyPoses_N();
  const Eigen::Matrix3d D = Eigen::Vector3d(1, -1, -1).asDiagonal();
  for (int i = 0; i < frames; ++i) {
    const Eigen::Vector3d p = D * T[i].translation();
    const Eigen::Quaterniond q(D * T[i].linear());
    gt << EurocTime(i) << "," << p.x() << "," << p.y() << "," << p.z() << "," << q.w() << "," << q.x() << "," << q.y() << ","
       << q.z() << "\n";
  }
  fs::create_directories(mav0 + "/imu0");
  WriteKittiImu(mav0 + "/imu0/data.csv", frames);
  return mav0;
}

// A video whose frame k is a uniform grey 20 + 25 k with a white square (so that no frame is
// blank), MJPG in AVI (OpenCV writes it without any codec library).
inline void WriteLevelsVideo(const std::string& path, int frames, double fps) {
  cv::VideoWriter w(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), fps, cv::Size(320, 240));
  for (int k = 0; k < frames; ++k) {
    cv::Mat m(240, 320, CV_8UC3, cv::Scalar::all(20 + 25 * k));
    cv::rectangle(m, cv::Rect(10, 10, 4, 4), cv::Scalar::all(255), cv::FILLED);
    w.write(m);
  }
}

}  // namespace uav::runtime
