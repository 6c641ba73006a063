#pragma once
// Part of an image file, decoded without the rest where the format allows (internal to the
// stitcher: the final render takes a strip of each kept frame).
#include <cstdint>
#include <vector>

#include <opencv2/core/mat.hpp>

namespace uav::vision {

// The pixels of `file` inside `region` (pixels of the whole image), 8-bit BGR, as stored (EXIF
// orientation is not applied); *origin is the whole image's pixel at the result's (0, 0). The
// result covers region & the image, and a JPEG's a little more (its columns widen to the
// format's 8- or 16-px blocks). A JPEG is decoded by libjpeg-turbo straight into BGR, the rows
// above the region skipped (entropy decoding only), the columns beside it cropped and the rows
// below never read. Any other file, or a JPEG libjpeg cannot decode so, is decoded whole by
// OpenCV and cut. Empty when the file is not an image or the region misses it.
cv::Mat DecodeRegion(const std::vector<uint8_t>& file, const cv::Rect& region, cv::Point* origin);

}  // namespace uav::vision
