#include "rtp_video_receiver.hpp"

#include <cstdio>
#include <string>

#include <opencv2/videoio.hpp>

#include "uav/shared/time.hpp"

namespace uav::gcs {

RtpVideoReceiver::RtpVideoReceiver(int port) : state_(std::make_shared<State>()) {
  const std::string pipeline =
      "udpsrc port=" + std::to_string(port) +
      " caps=\"application/x-rtp,media=video,clock-rate=90000,encoding-name=H264,payload=96\""
      " ! rtpjitterbuffer latency=50 ! rtph264depay ! avdec_h264 ! videoconvert ! video/x-raw,format=BGR"
      " ! appsink drop=true max-buffers=1 sync=false";
  thread_ = std::thread([state = state_, pipeline, port] {
    struct Finished {  // however the thread ends
      State& s;
      ~Finished() {
        std::lock_guard<std::mutex> lock(s.mutex);
        s.finished = true;
        s.finished_cv.notify_all();
      }
    } finished{*state};
    cv::VideoCapture capture(pipeline, cv::CAP_GSTREAMER);
    if (!capture.isOpened()) {
      std::fprintf(stderr, "uav-gcs: RTP/H.264 video on UDP %d cannot be received (GStreamer's udpsrc, rtph264depay, "
                           "avdec_h264: gstreamer1.0-plugins-good and gstreamer1.0-libav)\n", port);
      return;
    }
    cv::Mat bgr;
    while (!state->stop && capture.read(bgr)) {
      if (bgr.empty() || bgr.type() != CV_8UC3) continue;
      VideoPixels p;
      p.camera = "rtp:" + std::to_string(port);
      p.utime = WallTimeMicros();
      p.width = bgr.cols, p.height = bgr.rows;
      p.rgba.resize(static_cast<std::size_t>(bgr.cols) * bgr.rows * 4);
      // By hand rather than cv::cvtColor: nothing of OpenCV's per-thread state is touched after
      // the read, so a thread let go at exit cannot meet it torn down.
      uint8_t* out = p.rgba.data();
      for (int r = 0; r < bgr.rows; ++r) {
        const uint8_t* in = bgr.ptr<uint8_t>(r);
        for (int c = 0; c < bgr.cols; ++c, in += 3, out += 4) out[0] = in[2], out[1] = in[1], out[2] = in[0], out[3] = 255;
      }
      std::lock_guard<std::mutex> lock(state->mutex);
      state->newest = std::move(p);
    }
  });
}

RtpVideoReceiver::~RtpVideoReceiver() {
  state_->stop = true;
  std::unique_lock<std::mutex> lock(state_->mutex);
  if (state_->finished_cv.wait_for(lock, std::chrono::milliseconds(kJoinWaitMs), [this] { return state_->finished; })) {
    lock.unlock();
    thread_.join();
  } else {
    thread_.detach();
  }
}

bool RtpVideoReceiver::Take(VideoPixels* out) {
  std::lock_guard<std::mutex> lock(state_->mutex);
  if (!state_->newest) return false;
  *out = std::move(*state_->newest);
  state_->newest.reset();
  return true;
}

}  // namespace uav::gcs
