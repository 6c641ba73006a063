// libjpeg lives in this one translation unit.
#include "image_region.hpp"

#include <algorithm>
#include <csetjmp>
#include <cstdio>

#include <jpeglib.h>
#include <opencv2/imgcodecs.hpp>

namespace uav::vision {

namespace {

struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
};
// libjpeg's errors end in a jump back to DecodeJpegRegion (its documented way), not in exit().
[[noreturn]] void OnJpegError(j_common_ptr info) { std::longjmp(reinterpret_cast<JpegError*>(info->err)->jump, 1); }
void Silent(j_common_ptr) {}

// Decodes the JPEG's pixels in `region` into `out` (rows of `out_step` bytes, room for
// `out_width` pixels) and sets *decoded to the part written (in whole-image pixels). False on
// any libjpeg error or when the part would not fit. No object with a destructor lives across
// the setjmp, so the jump back leaks nothing.
bool DecodeJpegRegion(const uint8_t* data, size_t size, const cv::Rect& region, uint8_t* out, size_t out_step,
                      int out_width, cv::Rect* decoded) {
  jpeg_decompress_struct info;
  JpegError error;
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = OnJpegError;
  error.manager.output_message = Silent;
  if (setjmp(error.jump)) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  if (info.num_components != 1 && info.num_components != 3) {  // CMYK and the like: OpenCV's path
    jpeg_destroy_decompress(&info);
    return false;
  }
  info.out_color_space = JCS_EXT_BGR;
  jpeg_start_decompress(&info);
  const int x0 = std::max(region.x, 0), y0 = std::max(region.y, 0);
  const int x1 = std::min(region.x + region.width, static_cast<int>(info.output_width));
  const int y1 = std::min(region.y + region.height, static_cast<int>(info.output_height));
  if (x1 <= x0 || y1 <= y0) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  JDIMENSION x = static_cast<JDIMENSION>(x0), width = static_cast<JDIMENSION>(x1 - x0);
  jpeg_crop_scanline(&info, &x, &width);
  if (static_cast<int>(width) > out_width) {
    jpeg_destroy_decompress(&info);
    return false;
  }
  if (y0 > 0) jpeg_skip_scanlines(&info, static_cast<JDIMENSION>(y0));
  for (int row = 0; row < y1 - y0; ++row) {
    JSAMPROW line = out + row * out_step;
    jpeg_read_scanlines(&info, &line, 1);
  }
  jpeg_destroy_decompress(&info);  // the rows below the region are never decoded
  *decoded = cv::Rect(static_cast<int>(x), y0, static_cast<int>(width), y1 - y0);
  return true;
}

}  // namespace

cv::Mat DecodeRegion(const std::vector<uint8_t>& file, const cv::Rect& region, cv::Point* origin) {
  const bool jpeg = file.size() > 2 && file[0] == 0xFF && file[1] == 0xD8;
  if (jpeg && region.width > 0 && region.height > 0) {
    // Cropping widens the columns to whole blocks: at most 16 px more on each side.
    cv::Mat buffer(region.height, region.width + 32, CV_8UC3);
    cv::Rect decoded;
    if (DecodeJpegRegion(file.data(), file.size(), region, buffer.data, buffer.step, buffer.cols, &decoded)) {
      *origin = decoded.tl();
      return buffer(cv::Rect(0, 0, decoded.width, decoded.height));
    }
  }
  if (file.empty()) return cv::Mat();
  const cv::Mat whole = cv::imdecode(file, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
  const cv::Rect part = region & cv::Rect(0, 0, whole.cols, whole.rows);
  if (part.empty()) return cv::Mat();
  *origin = part.tl();
  return whole(part);
}

}  // namespace uav::vision
