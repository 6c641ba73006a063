#pragma once
// Video from a MAVLink vehicle as QGroundControl takes it: RTP/H.264 on a UDP port (5600),
// depayloaded and decoded by GStreamer (rtph264depay, avdec_h264) through OpenCV on a thread of
// its own; the newest picture waits for the GCS's frame, older ones are dropped.
#include <atomic>
#include <condition_variable>
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
  // Shared with the thread, which may outlive this object: a GStreamer read blocks until a frame
  // comes. While frames come the thread stops at the next one and is joined; when none comes (the
  // vehicle stopped streaming) it is let go, blocked, after kJoinWait.
  struct State {
    std::mutex mutex;
    std::condition_variable finished_cv;
    bool finished = false;
    std::optional<VideoPixels> newest;
    std::atomic<bool> stop{false};
  };
  static constexpr int kJoinWaitMs = 500;
  std::shared_ptr<State> state_;
  std::thread thread_;
};

}  // namespace uav::gcs
