#pragma once
// Helpers for the GCS tests: typed inputs built from the few values a test cares about.
#include <initializer_list>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>

#include <opencv2/imgcodecs.hpp>

#include "uav/gcs/gcs_model.hpp"

namespace uav::gcs {

// A real JPEG (encoded by OpenCV) of one colour, for video frames and map tiles.
inline std::vector<uint8_t> Jpeg(int w, int h) {
  cv::Mat img(h, w, CV_8UC3, cv::Scalar(30, 120, 200));
  std::vector<uint8_t> out;
  cv::imencode(".jpg", img, out);
  return out;
}

inline HeartbeatInfo Hb(int task, bool armed) { return {*TaskFromWire(task), armed, FlightMode::kAuto}; }

// A state at vehicle time t [s] with the named values set (alt, x, y, armed, task); the rest default.
inline VehicleState StateOf(double t, std::initializer_list<std::pair<const char*, double>> values) {
  VehicleState s;
  s.utime = static_cast<int64_t>(t * 1e6 + (t >= 0 ? 0.5 : -0.5));
  for (const auto& [name, v] : values) {
    const std::string n = name;
    if (n == "alt") s.p_N.z() = -v;
    else if (n == "x") s.p_N.x() = v;
    else if (n == "y") s.p_N.y() = v;
    else if (n == "armed") s.armed = v > 0.5;
    else if (n == "task") s.task = *TaskFromWire(static_cast<int>(v));
    else throw std::invalid_argument("StateOf: no setter for " + n);
  }
  return s;
}

inline SignalRef Sig(const char* key) {
  const auto s = FindSignal(key);
  if (!s) throw std::invalid_argument(std::string("no signal ") + key);
  return *s;
}

inline std::set<std::string> Keys(const std::set<SignalRef>& signals) {
  std::set<std::string> out;
  for (SignalRef s : signals) out.insert(Key(s));
  return out;
}

}  // namespace uav::gcs
