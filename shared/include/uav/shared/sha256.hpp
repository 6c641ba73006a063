#pragma once
// SHA-256 (FIPS 180-4), for verifying downloaded files end to end.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

namespace uav {

class Sha256 {
 public:
  Sha256();
  void Update(const void* data, size_t size);
  std::array<uint8_t, 32> Final();  // the object must not be updated after this

  static std::string Hex(const std::array<uint8_t, 32>& digest);
  static std::string HexOf(const void* data, size_t size);

 private:
  void Block(const uint8_t* p);
  std::array<uint32_t, 8> h_;
  std::array<uint8_t, 64> buffer_{};
  size_t buffered_ = 0;
  uint64_t length_ = 0;  // bytes
};

// CRC-32 (IEEE 802.3), to reject a damaged chunk before it reaches the file.
uint32_t Crc32(const void* data, size_t size);

}  // namespace uav
