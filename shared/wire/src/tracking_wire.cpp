#include "uav/wire/messages.hpp"

#include <cmath>
#include <stdexcept>

#include "uavmsg/track_status_t.hpp"
#include "uavmsg/track_target_t.hpp"

namespace uav {

static_assert(static_cast<int>(TrackTarget::Method::kDrag) == uavmsg::track_target_t::METHOD_DRAG &&
              static_cast<int>(TrackTarget::Method::kFourClicks) == uavmsg::track_target_t::METHOD_FOUR_CLICKS &&
              static_cast<int>(TrackTarget::Method::kCancel) == uavmsg::track_target_t::METHOD_CANCEL);
static_assert(static_cast<int>(TrackStatus::State::kIdle) == uavmsg::track_status_t::STATE_IDLE &&
              static_cast<int>(TrackStatus::State::kTracking) == uavmsg::track_status_t::STATE_TRACKING &&
              static_cast<int>(TrackStatus::State::kLost) == uavmsg::track_status_t::STATE_LOST &&
              static_cast<int>(TrackStatus::State::kRejected) == uavmsg::track_status_t::STATE_REJECTED);

TrackTarget FromMessage(const uavmsg::track_target_t& m) {
  TrackTarget r;
  r.vehicle_id = m.header.vehicle_id;
  r.source = m.source;
  r.target_seq = m.target_seq;
  r.frame_utime = m.frame_utime;
  r.camera = m.camera;
  if (m.method != uavmsg::track_target_t::METHOD_DRAG && m.method != uavmsg::track_target_t::METHOD_FOUR_CLICKS &&
      m.method != uavmsg::track_target_t::METHOD_CANCEL)
    throw std::invalid_argument("unknown selection method " + std::to_string(m.method));
  r.method = static_cast<TrackTarget::Method>(m.method);
  if (r.method == TrackTarget::Method::kCancel) return r;
  auto unit = [](double v, const char* name) {
    if (!std::isfinite(v)) throw std::invalid_argument(std::string(name) + " is not finite");
    if (v < 0.0 || v > 1.0) throw std::invalid_argument(std::string(name) + " " + std::to_string(v) + " is outside 0..1");
    return v;
  };
  r.x = unit(m.x, "x");
  r.y = unit(m.y, "y");
  r.width = unit(m.width, "width");
  r.height = unit(m.height, "height");
  if (r.x + r.width > 1.0 + 1e-9 || r.y + r.height > 1.0 + 1e-9) throw std::invalid_argument("the box reaches outside the image");
  for (int i = 0; i < 4; ++i)
    r.corners[static_cast<std::size_t>(i)] = Eigen::Vector2d(unit(m.corner_x[i], "corner x"), unit(m.corner_y[i], "corner y"));
  return r;
}

uavmsg::track_status_t ToMessage(const TrackStatus& r) {
  uavmsg::track_status_t m{};
  m.utime = r.utime;
  m.target_seq = r.target_seq;
  m.camera = r.camera;
  m.tracker = r.tracker;
  m.state = static_cast<int8_t>(r.state);
  m.center_x = r.center_x;
  m.center_y = r.center_y;
  m.width = r.width;
  m.height = r.height;
  m.angle_rad = r.angle_rad;
  m.window_x = r.window_x;
  m.window_y = r.window_y;
  m.window_width = r.window_width;
  m.window_height = r.window_height;
  m.confidence = r.confidence;
  m.reason = r.reason;
  return m;
}

TrackStatus FromMessage(const uavmsg::track_status_t& m) {
  // Checked before the cast: an enum holding a value it does not name is undefined.
  if (m.state < TrackStatus::kIdle || m.state > TrackStatus::kRejected)
    throw std::invalid_argument("unknown tracker state " + std::to_string(m.state));
  TrackStatus st;
  st.utime = m.utime;
  st.target_seq = m.target_seq;
  st.camera = m.camera;
  st.tracker = m.tracker;
  st.state = static_cast<TrackStatus::State>(m.state);
  st.center_x = m.center_x;
  st.center_y = m.center_y;
  st.width = m.width;
  st.height = m.height;
  st.angle_rad = m.angle_rad;
  st.window_x = m.window_x;
  st.window_y = m.window_y;
  st.window_width = m.window_width;
  st.window_height = m.window_height;
  st.confidence = m.confidence;
  st.reason = m.reason;
  return st;
}

uavmsg::track_target_t ToMessage(const TrackTarget& t) {
  uavmsg::track_target_t m{};
  m.source = t.source;
  m.target_seq = t.target_seq;
  m.frame_utime = t.frame_utime;
  m.camera = t.camera;
  m.method = static_cast<int8_t>(t.method);
  m.x = t.x;
  m.y = t.y;
  m.width = t.width;
  m.height = t.height;
  for (int i = 0; i < 4; ++i) {
    m.corner_x[i] = t.corners[static_cast<std::size_t>(i)][0];
    m.corner_y[i] = t.corners[static_cast<std::size_t>(i)][1];
  }
  return m;
}

}  // namespace uav
