#include "rtp_video_receiver.hpp"

#include <cstdio>
#include <string>

#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "uav/shared/time.hpp"

namespace uav::gcs {

RtpVideoReceiver::RtpVideoReceiver(int port) : state_(std::make_shared<State>()) {
  const std::string pipeline =
      "udpsrc port=" + std::to_string(port) +
      " caps=\"application/x-rtp,media=video,clock-rate=90000,encoding-name=H264,payload=96\""
      " ! rtpjitterbuffer latency=50 ! rtph264depay ! avdec_h264 ! videoconvert ! video/x-raw,format=BGR"
      " ! appsink drop=true max-buffers=1 sync=false";
  std::thread([state = state_, pipeline, port] {
    cv::VideoCapture capture(pipeline, cv::CAP_GSTREAMER);
    if (!capture.isOpened()) {
      std::fprintf(stderr, "uav-gcs: RTP/H.264 video on UDP %d cannot be received (GStreamer's udpsrc, rtph264depay, "
                           "avdec_h264: gstreamer1.0-plugins-good and gstreamer1.0-libav)\n", port);
      return;
    }
    cv::Mat bgr, rgba;
    while (!state->stop && capture.read(bgr)) {
      if (bgr.empty()) continue;
      cv::cvtColor(bgr, rgba, cv::COLOR_BGR2RGBA);
      VideoPixels p;
      p.camera = "rtp:" + std::to_string(port);
      p.utime = WallTimeMicros();
      p.width = rgba.cols, p.height = rgba.rows;
      p.rgba.assign(rgba.data, rgba.data + rgba.total() * 4);
      std::lock_guard<std::mutex> lock(state->mutex);
      state->newest = std::move(p);
    }
  }).detach();
}

RtpVideoReceiver::~RtpVideoReceiver() { state_->stop = true; }

bool RtpVideoReceiver::Take(VideoPixels* out) {
  std::lock_guard<std::mutex> lock(state_->mutex);
  if (!state_->newest) return false;
  *out = std::move(*state_->newest);
  state_->newest.reset();
  return true;
}

}  // namespace uav::gcs
