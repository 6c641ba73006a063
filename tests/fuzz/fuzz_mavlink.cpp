// MAVLink bytes as the vehicle's endpoint receives them (shared/mavlink_frame, mavlink_messages):
// the input split into datagrams at its first byte's choice, parsed, every frame of a known
// message decoded into its struct and every signature checked against the stream rules.
#include "fuzz_input.hpp"
#include "uav/shared/mavlink_messages.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace uav::mavlink;
  if (size == 0) return 0;
  const std::size_t piece = 1 + data[0] % 64;  // datagram size: the parser keeps state across pushes
  Parser parser(Lookup());
  SecretKey key;
  key.fill(0x42);
  SignedStreams streams(key, data[0] & 0x80);
  for (std::size_t at = 1; at < size; at += piece) {
    const std::size_t n = std::min(piece, size - at);
    for (const Frame& f : parser.Push(data + at, n)) {
      const MessageLayout* layout = FindLayout(f.msgid);
      if (!layout) __builtin_trap();  // the parser passes known messages only
      std::vector<uint8_t> storage(4096);
      UnpackPayload(*layout, f.payload, storage.data());
      (void)streams.Check(f, 600'000'000'000);
      // Re-encoding what was decoded gives a frame the parser reads back the same.
      Frame again = f;
      again.payload = PackPayload(*layout, storage.data());
      const std::vector<uint8_t> bytes = Encode(again, layout->crc_extra);
      Parser check(Lookup());
      const std::vector<Frame> back = check.Push(bytes.data(), bytes.size());
      if (back.size() != 1 || back[0].payload != again.payload) __builtin_trap();
    }
  }
  return 0;
}
