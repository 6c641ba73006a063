#include "uav/runtime/preview_stream.hpp"

#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

namespace uav::runtime {

PreviewStream::PreviewStream(std::string camera, double rate_hz, int width_px, int jpeg_quality)
    : camera_(std::move(camera)), rate_hz_(rate_hz), width_px_(width_px), jpeg_quality_(jpeg_quality) {}

bool PreviewStream::Due(int64_t utime) {
  if (!(rate_hz_ > 0)) return false;
  if (next_utime_ >= 0 && utime < next_utime_ - 1000) return false;
  const int64_t period = static_cast<int64_t>(std::llround(1e6 / rate_hz_));
  next_utime_ = next_utime_ < 0 || utime - next_utime_ > period ? utime + period : next_utime_ + period;
  return true;
}

VideoFrame PreviewStream::Encode(int64_t utime, const cv::Mat& image) const {
  VideoFrame preview;
  preview.utime = utime;
  preview.camera = camera_;
  preview.source_width = image.cols;
  preview.source_height = image.rows;
  cv::Mat small;
  const double scale = static_cast<double>(width_px_) / image.cols;
  cv::resize(image, small, cv::Size(), scale, scale, cv::INTER_AREA);
  preview.width = small.cols;
  preview.height = small.rows;
  cv::imencode(".jpg", small, preview.jpeg, {cv::IMWRITE_JPEG_QUALITY, jpeg_quality_});
  return preview;
}

}  // namespace uav::runtime
