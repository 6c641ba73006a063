#pragma once
// The command-line tools' image folders: the image files of a folder in name order, which is how
// recorded sequences pair up and play back.
#include <string>
#include <vector>

namespace uav {

// Regular files ending (any case) in .png .jpg .jpeg .pgm .ppm .bmp .tif .tiff, sorted by path.
// Empty when `dir` is not a folder or holds none.
std::vector<std::string> ImageFilesIn(const std::string& dir);

}  // namespace uav
