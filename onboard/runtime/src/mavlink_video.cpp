#include "mavlink_video.hpp"

#include <iostream>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

namespace uav::runtime {

MavlinkVideo::MavlinkVideo(std::string host, int port) : host_(std::move(host)), port_(port), thread_([this] { Run(); }) {}

MavlinkVideo::~MavlinkVideo() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void MavlinkVideo::Push(const VideoFrame& f) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_ = f;
  }
  wake_.notify_all();
}

int MavlinkVideo::width() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return width_;
}
int MavlinkVideo::height() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return height_;
}
int64_t MavlinkVideo::frames_sent() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return sent_;
}

void MavlinkVideo::Run() {
  cv::VideoWriter writer;
  bool failed = false;
  for (;;) {
    VideoFrame f;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || waiting_.has_value(); });
      if (stop_) return;
      f = std::move(*waiting_);
      waiting_.reset();
    }
    if (failed) continue;
    cv::Mat image = cv::imdecode(f.jpeg, cv::IMREAD_COLOR);
    if (image.empty()) continue;
    if (!writer.isOpened()) {
      // Even sizes for the encoder's 4:2:0; key frames every second so that a GCS joining late
      // shows video within one; the stream's parameters in every key frame (config-interval).
      image = image(cv::Rect(0, 0, image.cols & ~1, image.rows & ~1)).clone();
      const std::string pipeline =
          "appsrc ! videoconvert ! video/x-raw,format=I420 ! x264enc tune=zerolatency speed-preset=ultrafast bitrate=" +
          std::to_string(kBitrateKbps) + " key-int-max=" + std::to_string(static_cast<int>(kFrameRate)) +
          " ! video/x-h264,profile=constrained-baseline ! rtph264pay config-interval=1 pt=96 ! udpsink host=" + host_ +
          " port=" + std::to_string(port_) + " sync=false async=false";
      writer.open(pipeline, cv::CAP_GSTREAMER, 0, kFrameRate, image.size(), true);
      if (!writer.isOpened()) {
        std::cerr << "uav-onboard: MAVLink video: GStreamer cannot open '" << pipeline
                  << "' (gstreamer1.0-plugins-ugly has x264enc)\n";
        failed = true;
        continue;
      }
      std::lock_guard<std::mutex> lock(mutex_);
      width_ = image.cols, height_ = image.rows;
    }
    if (image.cols != width_ || image.rows != height_) image = image(cv::Rect(0, 0, width_, height_)).clone();
    writer.write(image);
    std::lock_guard<std::mutex> lock(mutex_);
    ++sent_;
  }
}

}  // namespace uav::runtime
