#pragma once
// The vehicle's video for a MAVLink GCS: the frames the video camera previews, as H.264 in RTP
// over UDP (QGroundControl's default stream, port 5600), encoded by GStreamer (x264, tuned for
// latency) on a thread of its own so that the link thread never waits for the encoder. A frame
// that arrives while the previous one is being encoded replaces the one waiting (video is live).
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>

#include "uav/shared/operator_messages.hpp"

namespace uav::runtime {

class MavlinkVideo {
 public:
  MavlinkVideo(std::string host, int port);
  ~MavlinkVideo();
  void Push(const VideoFrame& f);
  // The stream as it is encoded (0 before the first frame).
  int width() const;
  int height() const;
  double frame_rate() const { return kFrameRate; }
  int bitrate_kbps() const { return kBitrateKbps; }
  int64_t frames_sent() const;
  static constexpr double kFrameRate = 10.0;
  static constexpr int kBitrateKbps = 1500;

 private:
  void Run();
  std::string host_;
  int port_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  std::optional<VideoFrame> waiting_;
  bool stop_ = false;
  int width_ = 0, height_ = 0;
  int64_t sent_ = 0;
  std::thread thread_;
};

}  // namespace uav::runtime
