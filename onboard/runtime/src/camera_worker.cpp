#include "uav/runtime/camera_worker.hpp"

#include "uav/runtime/mono_depth_worker.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"
#include "uav/shared/text_file.hpp"

namespace uav::runtime {

CameraWorker::CameraWorker(hal::Camera& camera_in, Blackboard& board, const Options& options)
    : VisionWorker(board),
      camera_(camera_in),
      options_(options),
      preview_(camera_in.info().name, camera_in.info().preview_rate_hz, options.preview_width, options.preview_quality) {
  const hal::CameraInfo& camera = camera_.info();
  if (!options_.capture_dir.empty()) {
    std::filesystem::create_directories(options_.capture_dir);
    const std::string path = options_.capture_dir + "/captures.csv";
    csv_ = std::fopen(path.c_str(), "w");
    if (!csv_) throw std::runtime_error("cannot write '" + path + "': " + std::strerror(errno));
    // One row per image: true pose (what the camera saw) and the flight stack's estimate
    // (what a stitcher onboard knows). Angles z-y-x (Eq. 5.51).
    std::fprintf(csv_,
                 "index,utime,file,north_m,east_m,down_m,roll_rad,pitch_rad,yaw_rad,"
                 "est_north_m,est_east_m,est_down_m,est_roll_rad,est_pitch_rad,est_yaw_rad,"
                 "fx_px,fy_px,cx_px,cy_px\n");
    std::fflush(csv_);
    // session.json makes the folder self-describing for uav-stitch: the NED origin and the
    // camera (size, lens, mount) the poses refer to.
    const CameraIntrinsics& k = camera.intrinsics;
    const Eigen::Matrix3d& R = camera.T_BC.linear();
    const Eigen::Vector3d& t = camera.T_BC.translation();
    char text[1024];
    std::snprintf(text, sizeof text,
                  "{\n  \"home\": {\"latitude_deg\": %.9f, \"longitude_deg\": %.9f, \"altitude_m\": %.3f},\n"
                  "  \"camera\": {\"name\": \"%s\", \"width\": %d, \"height\": %d, \"fx\": %.6f, \"fy\": %.6f, "
                  "\"cx\": %.6f, \"cy\": %.6f,\n             \"distortion\": [%.9g, %.9g, %.9g, %.9g, %.9g],\n"
                  "             \"R_BC\": [%.9f, %.9f, %.9f, %.9f, %.9f, %.9f, %.9f, %.9f, %.9f], \"p_B\": [%.6f, %.6f, %.6f]}\n}\n",
                  options_.home.latitude_deg, options_.home.longitude_deg, options_.home.altitude_m, camera.name.c_str(),
                  k.width, k.height, k.fx, k.fy, k.cx, k.cy, k.distortion[0], k.distortion[1], k.distortion[2],
                  k.distortion[3], k.distortion[4], R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2), R(2, 0), R(2, 1),
                  R(2, 2), t.x(), t.y(), t.z());
    WriteFileAtomically(options_.capture_dir + "/session.json", text);
  }
}

CameraWorker::~CameraWorker() {
  if (csv_) std::fclose(csv_);
}

void CameraWorker::Work(Outbox& out) {
  const int64_t utime = utime_;
  const BlackboardData& d = at_begin_;
  const hal::CameraFrame frame = TimedCapture([&] { return camera_.Capture(utime); });
  if (frame.image.empty()) return;  // the camera's problem shows in the sensing health
  Eigen::Isometry3d T_NB_estimate = Eigen::Isometry3d::Identity();
  T_NB_estimate.linear() = RotationNBFromEuler(d.estimate.euler);
  T_NB_estimate.translation() = d.estimate.p_N;

  if (EstimateMatchesFrame(d.estimate, utime))
    ShareFrame(out, d, camera_.info().name, utime, frame.image, d.estimate.T_NB() * camera_.info().T_BC);
  else
    ShareFrame(out, d, camera_.info().name, utime, frame.image, std::nullopt);
  if (preview_.Due(utime)) {
    out.Post([f = preview_.Encode(utime, frame.image)](Blackboard& b) { b.previews.Put(f.camera, f); });
    ++previews_;
  }

  // Survey capture by time or by distance, as the mission's camera item asked.
  bool due = false;
  if (d.capture_interval_s)
    due = last_capture_utime_ < 0 || (utime - last_capture_utime_) * 1e-6 >= *d.capture_interval_s - 1e-3;
  else if (d.capture_distance_m)
    due = last_capture_utime_ < 0 || (T_NB_estimate.translation() - last_capture_p_N_).norm() >= *d.capture_distance_m;
  else
    last_capture_utime_ = -1;  // the next capture run starts at once
  if (due) {
    // To the onboard stitcher (STITCH), with the pose the flight stack estimated.
    SurveyCapture c;
    c.utime = utime;
    c.width = frame.image.cols;
    c.height = frame.image.rows;
    c.bgr.assign(frame.image.data, frame.image.data + frame.image.total() * 3);
    c.T_NC_estimate = T_NB_estimate * camera_.info().T_BC;
    out.Post([c = std::move(c)](Blackboard& b) { b.captures.Push(c); });
    if (csv_) Record(utime, frame, d);
    ++captures_;
    last_capture_utime_ = utime;
    last_capture_p_N_ = T_NB_estimate.translation();
  }
}

void CameraWorker::Record(int64_t utime, const hal::CameraFrame& frame, const BlackboardData& d) {
  char name[32];
  std::snprintf(name, sizeof name, "IMG_%06d.jpg", captures_);
  std::vector<uint8_t> jpeg;
  cv::imencode(".jpg", frame.image, jpeg, {cv::IMWRITE_JPEG_QUALITY, options_.capture_quality});
  WriteFileAtomically(options_.capture_dir + "/" + name, std::string(jpeg.begin(), jpeg.end()));
  // Without ground truth (real hardware) the truth columns say nan.
  const EulerAngles e = frame.truth_T_NB ? EulerFromRotationNB(frame.truth_T_NB->linear()) : EulerAngles{NAN, NAN, NAN};
  const auto& est = d.estimate;
  const auto& k = camera_.info().intrinsics;
  const Eigen::Vector3d p = frame.truth_T_NB ? Eigen::Vector3d(frame.truth_T_NB->translation()) : Eigen::Vector3d::Constant(NAN);
  std::fprintf(csv_, "%d,%lld,%s,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.3f,%.3f,%.3f,%.3f\n",
               captures_, static_cast<long long>(utime), name, p.x(), p.y(), p.z(), e.phi, e.theta, e.psi,
               est.p_N.x(), est.p_N.y(), est.p_N.z(), est.euler.phi, est.euler.theta, est.euler.psi, k.fx, k.fy,
               k.cx, k.cy);
  std::fflush(csv_);
}

}  // namespace uav::runtime
