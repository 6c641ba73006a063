#pragma once
#include <string>

namespace uav {

// Whole contents of a text file. Throws std::runtime_error "cannot open WHAT 'PATH'".
std::string ReadTextFile(const std::string& path, const std::string& what);

}  // namespace uav
