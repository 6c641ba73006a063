#pragma once
// The KITTI odometry benchmark's formats and metric: a sequence folder (image_0/ left and
// image_1/ right rectified grey images, calib.txt with the projection matrices P0 and P1,
// optional times.txt), pose files (one 3x4 row-major [R|t] per line: camera i in camera 0's
// frame) and the segment errors of the KITTI devkit (evaluate_odometry.cpp): for every 10th
// frame and every length of 100, 200, ..., 800 m, the translation and rotation error of the
// relative pose over that distance, divided by the distance.
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "uav/vision/stereo_rectifier.hpp"

namespace uav::vision {

struct KittiSequence {
  std::string dir;
  RectifiedGeometry geometry;
  std::vector<std::string> left, right;  // image paths, in order
  std::vector<double> times_s;           // per frame (10 Hz assumed when times.txt is absent)
};

// Throws std::runtime_error naming the folder and what is missing or bad (no images, a count
// that differs between image_0 and image_1, a calib.txt without P0/P1 or with a non-positive
// baseline, times.txt of another length or not increasing).
KittiSequence ReadKittiSequence(const std::string& dir);

// One pose per line, 12 numbers. Throws std::runtime_error naming the file and line.
std::vector<Eigen::Isometry3d> ReadKittiPoses(const std::string& path);
// Writes through a temporary name, then renames (a reader never sees half a file).
void WriteKittiPoses(const std::string& path, const std::vector<Eigen::Isometry3d>& poses);

struct KittiErrors {
  int segments = 0;                 // segment-length pairs evaluated
  double translation_pct = 0.0;     // mean translation error [% of distance]
  double rotation_deg_per_m = 0.0;  // mean rotation error [deg/m]
  struct PerLength {
    double length_m;
    int segments;
    double translation_pct, rotation_deg_per_m;
  };
  std::vector<PerLength> per_length;  // lengths with at least one segment
};

// KITTI's segment metric for equally long pose lists (est[i] and gt[i] at the same frame). With
// a trajectory shorter than 100 m no segment fits and `segments` is 0. `lengths_m` defaults to
// KITTI's 100..800 m; shorter ones evaluate short test flights.
KittiErrors EvaluateKittiOdometry(const std::vector<Eigen::Isometry3d>& gt, const std::vector<Eigen::Isometry3d>& est,
                                  std::vector<double> lengths_m = {100, 200, 300, 400, 500, 600, 700, 800});

}  // namespace uav::vision
