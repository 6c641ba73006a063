#pragma once
// The GCS video preview of one camera: when a frame is due (at the camera's preview rate) and
// its JPEG. Every camera worker that can stream to the video panel uses it.
#include <cstdint>
#include <string>

#include <opencv2/core/mat.hpp>

#include "uav/runtime/blackboard.hpp"

namespace uav::runtime {

class PreviewStream {
 public:
  // rate_hz 0: this camera does not stream.
  PreviewStream(std::string camera, double rate_hz, int width_px = 320, int jpeg_quality = 70);
  // Whether the frame taken at utime goes out. A schedule (not "time since the last one") keeps
  // the average rate when it does not divide the frame rate.
  bool Due(int64_t utime);
  VideoFrame Encode(int64_t utime, const cv::Mat& image) const;

 private:
  std::string camera_;
  double rate_hz_;
  int width_px_, jpeg_quality_;
  int64_t next_utime_ = -1;
};

}  // namespace uav::runtime
