#pragma once
// Video and target tracking: each vehicle's newest decoded preview frame, freezing a frame to
// pick a target on, the target sent (track_target_t) and what the vehicle's tracker reports.
#include <array>
#include <cstdint>
#include <deque>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uav/gcs/message_log.hpp"
#include "uav/gcs/telemetry.hpp"
#include "uav/shared/operator_messages.hpp"
#include "uav/shared/tracking.hpp"

namespace uav::gcs {

// Largest JPEG accepted in a video frame or map tile (video_frame_t / map_tile_t.MAX_JPEG_BYTES;
// gcs_link.cpp checks they agree).
inline constexpr std::size_t kMaxJpegBytes = 60000;

// The newest decoded frame of a vehicle's camera stream.
struct VideoFeed {
  int64_t frames = 0;    // accepted frames; panels redraw when it changes
  int64_t rejected = 0;  // frames that were not a decodable JPEG of the stated size
  std::deque<double> recent;  // receive times within the last second
  int64_t utime = 0;
  std::string camera;
  int width = 0, height = 0;
  int source_width = 0, source_height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4
  double Rate(double now) const;
};

// A decoded video picture (a MAVLink vehicle's RTP/H.264 stream arrives decoded).
struct VideoPixels {
  std::string camera;
  int64_t utime = 0;
  int width = 0, height = 0;
  std::vector<uint8_t> rgba;  // width * height * 4
};

// Per vehicle. A vehicle may stream several cameras; the panel shows one (the first seen until
// the operator picks another).
struct VehicleVideo {
  VideoFeed video;                   // of the chosen camera
  std::string camera;                // chosen camera; "" until the first frame
  std::vector<std::string> cameras;  // every camera seen streaming
  std::optional<TrackTarget> track_target;  // the last selection this GCS sent (with its target_seq)
  int64_t track_targets_sent = 0;
  std::optional<TrackStatus> track;         // what its tracker reports about the last selection
  double track_received = -1.0;             // [s] GCS clock of that report
  int64_t stale_track_statuses = 0;         // statuses about an earlier selection, ignored
};

class VideoTracking {
 public:
  static constexpr double kMinTargetSide = 0.005;  // of the image side, each way

  // Shows `camera` from now on (frames of the others are not decoded). Returns false when the
  // vehicle has not streamed it.
  static bool ChooseCamera(VehicleVideo& v, const std::string& camera);
  // Decodes the JPEG (frames of the chosen camera only); a frame that does not decode to its stated size is counted as rejected
  // (the first one is logged with the reason) and the previous frame stays on screen.
  static void OnVideoFrame(VehicleVideo& v, const std::string& vehicle_id, const VideoFrame& frame, double now,
                           MessageLog& log);
  static void OnVideoPixels(VehicleVideo& v, VideoPixels pixels, double now);
  // A status that is not finite, names an unknown state or lies far outside the image is logged
  // and dropped (returns false).
  static bool OnTrackStatus(VehicleVideo& v, const std::string& vehicle_id, const TrackStatus& status, double now,
                            MessageLog& log);
  // Freezes `v`'s video on its current frame (target selection picks on it), or goes back to
  // live. Returns false when there is no frame to freeze.
  bool Freeze(const VehicleVideo* v, const std::string& vehicle_id, bool freeze);
  void Unfreeze() { Freeze(nullptr, "", false); }
  // Sends the target to the vehicle. Returns false and sets error() when there is no vehicle,
  // a coordinate is not finite or outside 0..1, or the rectangle is smaller than kMinTargetSide.
  bool SelectTarget(VehicleVideo* v, const std::string& vehicle_id, const TrackTarget& target, double now,
                    MessageLog& log);
  std::vector<TrackTarget> TakeOutgoing() { return std::exchange(outgoing_, {}); }

  const std::optional<VideoFeed>& frozen() const { return frozen_; }
  const std::string& frozen_vehicle() const { return frozen_vehicle_; }
  const std::string& error() const { return error_; }

 private:
  std::optional<VideoFeed> frozen_;
  std::string frozen_vehicle_;
  std::string error_;
  int64_t next_target_seq_ = 1;
  std::vector<TrackTarget> outgoing_;
};

// Decodes a JPEG to RGBA of exactly `width` x `height`; on failure returns false and says why.
bool DecodeJpeg(const std::vector<uint8_t>& jpeg, int width, int height, std::vector<uint8_t>* rgba,
                std::string* problem);

}  // namespace uav::gcs
