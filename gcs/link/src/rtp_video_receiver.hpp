#pragma once
// Video from a MAVLink vehicle as QGroundControl takes it: RTP/H.264 on a UDP port (5600),
// depayloaded and decoded by GStreamer (rtph264depay, avdec_h264) through OpenCV on a thread of
// its own; the newest picture waits for the GCS's frame, older ones are dropped.
#include <atomic>
#include <cstdint>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>

#include "uav/gcs/video_tracking.hpp"

namespace uav::gcs {

class RtpVideoReceiver {
 public:
  explicit RtpVideoReceiver(int port);
  ~RtpVideoReceiver();
  // The newest picture since the last call; false when none has come.
  bool Take(VideoPixels* out);

 private:
  // Shared with the thread, which may outlive this object: a GStreamer read blocks until a
  // frame comes, so the thread is let go (detached) and stops at its next frame.
  struct State {
    std::mutex mutex;
    std::optional<VideoPixels> newest;
    std::atomic<bool> stop{false};
  };
  std::shared_ptr<State> state_;
};

}  // namespace uav::gcs
