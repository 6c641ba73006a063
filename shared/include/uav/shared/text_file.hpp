#pragma once
#include <string>

namespace uav {

// Whole contents of a text file. Throws std::runtime_error "cannot open WHAT 'PATH'".
std::string ReadTextFile(const std::string& path, const std::string& what);

// Writes `contents` to a temporary file beside `path`, flushes it to disk and renames it over
// `path`: readers see the old file or the whole new one, never half of it. Throws
// std::runtime_error naming the path when any step fails (the temporary is removed).
void WriteFileAtomically(const std::string& path, const std::string& contents);

// `s` as a JSON string literal, quoted and escaped (the CLIs' one-line JSON reports).
std::string JsonString(const std::string& s);

}  // namespace uav
