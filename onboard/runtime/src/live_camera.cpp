#include "uav/runtime/live_camera.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <stdexcept>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/shared/decimal.hpp"

namespace uav::runtime {
namespace {

int64_t SteadyMicros() {
  return std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::unique_ptr<cv::VideoCapture> Open(const std::string& source) {
  auto cap = std::make_unique<cv::VideoCapture>();
  // A bare number is a device index; a pipeline (with '!') goes to GStreamer; the rest (a
  // device path, a URL, a file) to whichever backend takes it.
  if (const auto index = ParseDecimal(source); index && *index >= 0 && *index < 64 && *index == std::floor(*index))
    cap->open(static_cast<int>(*index));
  else if (source.find('!') != std::string::npos)
    cap->open(source, cv::CAP_GSTREAMER);
  else
    cap->open(source);
  if (!cap->isOpened()) return nullptr;
  return cap;
}

// Why a frame is garbage ("" : it is not).
std::string GarbageIn(const cv::Mat& frame, const CameraIntrinsics& k) {
  if (frame.empty()) return "an empty frame";
  if (frame.depth() != CV_8U || (frame.channels() != 1 && frame.channels() != 3))
    return "a frame of another type (" + std::to_string(frame.channels()) + " channels, not 8-bit)";
  if (frame.cols != k.width || frame.rows != k.height)
    return "a " + std::to_string(frame.cols) + " x " + std::to_string(frame.rows) + " px frame, the calibration is " +
           std::to_string(k.width) + " x " + std::to_string(k.height);
  cv::Scalar mean, stddev;
  cv::meanStdDev(frame, mean, stddev);
  if (stddev[0] < 0.5 && (frame.channels() == 1 || (stddev[1] < 0.5 && stddev[2] < 0.5)))
    return "a frame of one grey level (" + std::to_string(static_cast<int>(mean[0])) + "): a covered lens or a dead sensor";
  return "";
}

}  // namespace

LiveCamera::LiveCamera(const Options& o, double first_frame_s) : options_(o) {
  ValidateIntrinsics(o.intrinsics);
  if (!(o.rate_hz > 0 && o.rate_hz <= 240)) throw std::runtime_error("live camera '" + o.name + "': rate must be in (0, 240] Hz");
  info_.name = o.name;
  info_.intrinsics = o.intrinsics;
  info_.T_BC = o.T_BC;
  info_.rate_hz = o.rate_hz;
  info_.preview_rate_hz = std::min(o.rate_hz, 5.0);
  pitch_rad_ = std::asin(std::clamp(-(o.T_BC.linear() * Eigen::Vector3d::UnitZ()).z(), -1.0, 1.0));
  if (!Open(o.source)) throw std::runtime_error("live camera '" + o.name + "': cannot open '" + o.source + "'");
  reader_ = std::thread([this] { ReadLoop(); });
  // The rig refuses to start on a camera that gives nothing.
  const int64_t deadline = SteadyMicros() + static_cast<int64_t>(first_frame_s * 1e6);
  while (SteadyMicros() < deadline) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!newest_.empty()) return;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::string why = problem();
  stop_ = true;
  reader_.join();
  throw std::runtime_error("live camera '" + o.name + "' ('" + o.source + "'): no usable frame in " +
                           std::to_string(static_cast<int>(first_frame_s)) + " s" + (why.empty() ? "" : ": " + why));
}

LiveCamera::~LiveCamera() {
  stop_ = true;
  if (reader_.joinable()) reader_.join();
}

void LiveCamera::ReadLoop() {
  std::unique_ptr<cv::VideoCapture> cap;
  int64_t last_open_try = -1;
  while (!stop_) {
    if (!cap) {
      // Reopened a second after it failed, and each second after: a USB camera unplugged and
      // plugged back comes back.
      const int64_t now = SteadyMicros();
      if (last_open_try >= 0 && now - last_open_try < 1'000'000) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        continue;
      }
      last_open_try = now;
      cap = Open(options_.source);
      if (!cap) {
        std::lock_guard<std::mutex> lock(mutex_);
        device_problem_ = "cannot open '" + options_.source + "'";
        continue;
      }
    }
    cv::Mat frame;
    if (!cap->read(frame)) {
      std::lock_guard<std::mutex> lock(mutex_);
      device_problem_ = "the device stopped delivering frames (reopening)";
      cap.reset();
      last_open_try = SteadyMicros();
      continue;
    }
    const int64_t arrived = SteadyMicros();
    const double driver_ms = cap->get(cv::CAP_PROP_POS_MSEC);
    const std::string garbage = GarbageIn(frame, options_.intrinsics);
    std::lock_guard<std::mutex> lock(mutex_);
    if (!garbage.empty()) {
      ++rejected_;
      device_problem_ = "the device delivers " + garbage;
      continue;
    }
    if (driver_ms > 0 && last_driver_ms_ > 0 && driver_ms <= last_driver_ms_) {
      ++rejected_;
      device_problem_ = "the driver's timestamps repeat or go backwards (" + std::to_string(driver_ms) + " ms after " +
                        std::to_string(last_driver_ms_) + " ms): frame dropped";
      continue;
    }
    last_driver_ms_ = driver_ms;
    device_problem_.clear();
    if (frame.channels() == 1) cv::cvtColor(frame, newest_, cv::COLOR_GRAY2BGR);
    else newest_ = frame;
    newest_wall_us_ = arrived;
    ++frames_;
  }
}

std::string LiveCamera::problem() const {
  std::lock_guard<std::mutex> lock(mutex_);
  if (!device_problem_.empty()) return device_problem_;
  if (newest_wall_us_ < 0) return "no frame yet";
  const double age_s = (SteadyMicros() - newest_wall_us_) * 1e-6;
  if (age_s > options_.stall_s) return "stalled: no new frame for " + std::to_string(age_s).substr(0, 4) + " s";
  return "";
}

hal::CameraFrame LiveCamera::Capture(int64_t) {
  // A live camera gives what it saw last, stamped by the worker at its exposure time; a frame
  // older than the stall limit is not given at all.
  hal::CameraFrame out;
  if (!problem().empty()) return out;
  std::lock_guard<std::mutex> lock(mutex_);
  out.image = newest_.clone();
  return out;
}

}  // namespace uav::runtime
