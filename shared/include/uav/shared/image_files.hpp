#pragma once
// The command-line tools' image folders: the image files of a folder in name order, which is how
// recorded sequences pair up and play back.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace uav {

// Regular files ending (any case) in .png .jpg .jpeg .pgm .ppm .bmp .tif .tiff, sorted by path.
// Empty when `dir` is not a folder or holds none.
std::vector<std::string> ImageFilesIn(const std::string& dir);

// What is wrong with an encoded image, or "" when nothing is found. Decoders (OpenCV's
// imread/imdecode) turn a truncated or garbled JPEG into a picture with grey or smeared rows and
// only a warning on the terminal; every reader here checks first and skips the file, named:
//   empty; a JPEG that libjpeg cannot read, or reads only with a warning (premature end, corrupt
//   data, extraneous bytes: its message is given); a PNG without its end chunk (truncated).
// A JPEG's entropy-coded data is decoded in full (at 1/8 scale: every bit is read, little is
// reconstructed). Other formats are left to the decoder (an empty result is a failure).
std::string EncodedImageProblem(const uint8_t* data, std::size_t size);
// The same for a file: also "missing or unreadable".
std::string ImageFileProblem(const std::string& path);

}  // namespace uav
