#pragma once
// A capture folder as uav-onboard writes it (CameraWorker): session.json (home, camera
// intrinsics and mount) and captures.csv (one row per image: file, time, true pose where there
// is one, and the navigation solution's estimate). Read by the tools that process captures
// offline (uav-stitch, uav-monodepth).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/shared/frames.hpp"
#include "uav/shared/geodesy.hpp"

namespace uav {

struct CaptureSession {
  GeodeticPoint home;                 // origin of the poses' local NED frame
  CameraIntrinsics camera;
  Eigen::Isometry3d T_BC = Eigen::Isometry3d::Identity();  // camera mount in the body
};

struct CaptureRow {
  int row = 0;        // line in the file (the header is line 1)
  std::string file;   // image, relative to the folder
  int64_t utime = 0;  // [us] vehicle clock
  // The navigation solution's body pose (est_* columns, NED, z-y-x Euler angles); nullopt when
  // a column is not a finite number, with `problem` naming it.
  std::optional<Eigen::Isometry3d> T_NB_estimate;
  std::string problem;
};

// Both throw std::invalid_argument naming the file, line and field that is wrong (a missing
// column, a row with too few fields, a bad utime, a session without a field).
CaptureSession ReadCaptureSession(const std::string& path);
std::vector<CaptureRow> ReadCaptureRows(const std::string& path);

}  // namespace uav
