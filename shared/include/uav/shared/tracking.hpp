#pragma once
// Target tracking (thesis 3.7) as plain data: the operator's selection as the vehicle receives it
// (track_target_t), the tracker's report (track_status_t), and the target placed on the ground
// for follow. Decoded once, here. Image coordinates are normalised to 0..1 over the camera's
// full image, x right and y down from the top-left corner.
#include <array>
#include <cstdint>
#include <string>

#include <Eigen/Core>

namespace uav {

// The operator's selection (track_target_t), as the GCS sends it and the vehicle receives it.
struct TrackTarget {
  enum Method { kDrag = 0, kFourClicks = 1, kCancel = 2 };
  std::string vehicle_id;  // whom it is for
  std::string source;      // GCS instance
  int64_t target_seq = 0;
  int64_t frame_utime = 0;  // [us] vehicle clock of the frame it was picked in
  std::string camera;
  Method method = Method::kDrag;
  double x = 0, y = 0, width = 0, height = 0;  // axis-aligned, top-left and size
  std::array<Eigen::Vector2d, 4> corners{};    // the four clicks (or the rectangle's corners)
};

// What the vehicle's tracker reports (track_status_t) about the selection target_seq.
struct TrackStatus {
  enum State { kIdle = 0, kTracking = 1, kLost = 2, kRejected = 3 };
  int64_t utime = 0;  // [us] frame time
  int64_t target_seq = 0;
  std::string camera, tracker;
  State state = State::kIdle;
  double center_x = 0, center_y = 0, width = 0, height = 0, angle_rad = 0;
  double window_x = 0, window_y = 0, window_width = 0, window_height = 0;
  double confidence = 0;
  std::string reason;
};

// Where the tracked target is, for follow: the box centre's ray met with the ground (d = 0 in
// the home frame), from the navigation estimate and the gimbal's pitch.
struct TrackedTarget {
  bool locked = false;             // tracking now (not lost, not idle)
  int64_t utime = 0;               // [us] frame time of the newest lock
  int64_t last_seen_utime = -1;    // [us] newest frame it was locked in; < 0: never
  bool on_ground = false;          // the ray met the ground (p_N valid)
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // [m] target on the ground, local NED
  double bearing_rad = 0.0;        // [rad] from north to the target, about d
  double image_x = 0.5, image_y = 0.5;  // box centre, normalised
  double gimbal_pitch_rad = 0.0;   // [rad] the camera's pitch when it was seen (0 ahead, -pi/2 down)
};

}  // namespace uav
