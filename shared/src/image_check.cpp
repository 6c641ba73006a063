// libjpeg's strict reading of a JPEG (image_files.hpp), in this one translation unit.
#include <csetjmp>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include <jpeglib.h>

#include "uav/shared/image_files.hpp"

namespace uav {
namespace {

struct JpegError {
  jpeg_error_mgr manager;
  std::jmp_buf jump;
  char first_warning[JMSG_LENGTH_MAX];
};
// libjpeg's errors end in a jump back (its documented way), not in exit().
[[noreturn]] void OnError(j_common_ptr info) { std::longjmp(reinterpret_cast<JpegError*>(info->err)->jump, 1); }
// Warnings (msg_level -1) are counted and the first kept; trace messages are dropped.
void OnMessage(j_common_ptr info, int level) {
  auto* e = reinterpret_cast<JpegError*>(info->err);
  if (level >= 0) return;
  if (e->manager.num_warnings++ == 0) e->manager.format_message(info, e->first_warning);
}

// "" or the problem. No object with a destructor lives across the setjmp.
std::string JpegProblem(const uint8_t* data, std::size_t size) {
  jpeg_decompress_struct info;
  JpegError error;
  error.first_warning[0] = '\0';
  info.err = jpeg_std_error(&error.manager);
  error.manager.error_exit = OnError;
  error.manager.emit_message = OnMessage;
  if (setjmp(error.jump)) {
    char message[JMSG_LENGTH_MAX];
    error.manager.format_message(reinterpret_cast<j_common_ptr>(&info), message);
    jpeg_destroy_decompress(&info);
    return std::string("corrupt JPEG (") + message + ")";
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  info.scale_num = 1;
  info.scale_denom = 8;
  info.dct_method = JDCT_IFAST;
  jpeg_start_decompress(&info);
  // libjpeg's own pool: nothing here to leak if a later call jumps back.
  JSAMPARRAY line = (*info.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&info), JPOOL_IMAGE,
                                              info.output_width * static_cast<JDIMENSION>(info.output_components), 1);
  while (info.output_scanline < info.output_height) jpeg_read_scanlines(&info, line, 1);
  jpeg_finish_decompress(&info);
  const bool warned = error.manager.num_warnings > 0;
  const std::string warning = error.first_warning;
  jpeg_destroy_decompress(&info);
  return warned ? "corrupt JPEG (" + warning + ")" : "";
}

// A PNG ends in its IEND chunk; a file cut short does not.
std::string PngProblem(const uint8_t* data, std::size_t size) {
  static const uint8_t kEnd[8] = {0, 0, 0, 0, 'I', 'E', 'N', 'D'};
  for (std::size_t i = size >= 12 ? size - 12 : 0; i + 8 <= size; ++i)
    if (std::memcmp(data + i, kEnd, 8) == 0) return "";
  return "truncated PNG (no IEND chunk at its end)";
}

}  // namespace

std::string EncodedImageProblem(const uint8_t* data, std::size_t size) {
  if (size == 0) return "empty file";
  if (size >= 3 && data[0] == 0xFF && data[1] == 0xD8 && data[2] == 0xFF) return JpegProblem(data, size);
  static const uint8_t kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  if (size >= 8 && std::memcmp(data, kPng, 8) == 0) return PngProblem(data, size);
  return "";
}

std::string ImageFileProblem(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return "missing or unreadable";
  const std::vector<uint8_t> bytes(std::istreambuf_iterator<char>(file), {});
  return EncodedImageProblem(bytes.data(), bytes.size());
}

}  // namespace uav
