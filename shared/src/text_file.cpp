#include "uav/shared/text_file.hpp"

#include <fstream>
#include <sstream>
#include <stdexcept>

namespace uav {

std::string ReadTextFile(const std::string& path, const std::string& what) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open " + what + " '" + path + "'");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace uav
