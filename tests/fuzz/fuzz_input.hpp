#pragma once
// Shared by the fuzz harnesses: the libFuzzer entry point each defines, and a scratch file for
// readers that take a path (a per-process name, rewritten for every input).
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace uav::fuzz {

inline std::string ScratchFile(const uint8_t* data, size_t size, const std::string& name) {
  const std::string path = "/tmp/uav_fuzz_" + std::to_string(::getpid()) + "_" + name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  return path;
}

}  // namespace uav::fuzz
