#pragma once
// MAVLink's frames, written from the specification (mavlink.io: "Packet Serialization" and
// "Message Signing"): MAVLink 2 (0xFD) and MAVLink 1 (0xFE) framing, the checksum
// (CRC-16/MCRF4XX over the frame after the start byte, then the message's CRC_EXTRA), MAVLink
// 2's payload truncation (trailing zero bytes are not sent; a receiver pads them back) and
// signing (SHA-256 of the 32-byte secret key, the frame from its length byte to the checksum,
// the link id and the 48-bit timestamp; its first 6 bytes are the signature). The messages'
// layouts sit above this (which id, which CRC_EXTRA, which length).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <tuple>
#include <optional>
#include <string>
#include <vector>

namespace uav::mavlink {

constexpr uint8_t kStxV1 = 0xFE;
constexpr uint8_t kStxV2 = 0xFD;
constexpr uint8_t kIncompatSigned = 0x01;  // MAVLINK_IFLAG_SIGNED

// CRC-16/MCRF4XX (MAVLink's "X.25" checksum): initial 0xFFFF, reflected polynomial 0x1021.
uint16_t Crc16(const uint8_t* data, std::size_t size, uint16_t crc = 0xFFFF);

using SecretKey = std::array<uint8_t, 32>;

struct Signature {
  uint8_t link_id = 0;
  uint64_t timestamp = 0;  // 10 us units since 2015-01-01 00:00 GMT, 48 bits
  std::array<uint8_t, 6> value{};
};

struct Frame {
  int version = 2;  // 1 or 2
  uint8_t incompat_flags = 0, compat_flags = 0;
  uint8_t seq = 0, sysid = 0, compid = 0;
  uint32_t msgid = 0;            // 24 bits (MAVLink 1: 8)
  std::vector<uint8_t> payload;  // decoded: padded back to the message's length with zeros
  std::optional<Signature> signature;
  std::vector<uint8_t> raw;  // as received (Parser), for Verify
};

// The bytes of `frame` on the wire. MAVLink 2 payloads lose their trailing zeros (at least one
// byte is kept); with `key` the frame is signed with `link_id` and `timestamp`. Throws
// std::invalid_argument for a payload over 255 bytes, a MAVLink 1 id over 255, an id over 2^24
// or a timestamp over 48 bits.
std::vector<uint8_t> Encode(const Frame& frame, uint8_t crc_extra, const SecretKey* key = nullptr, uint8_t link_id = 0,
                            uint64_t timestamp = 0);

// The signature a frame should carry: SHA-256(key | the frame from byte 0 through the checksum
// | link id | timestamp), its first 6 bytes. `frame` is the encoded frame without signature.
std::array<uint8_t, 6> SignatureOf(const SecretKey& key, const uint8_t* frame, std::size_t size, uint8_t link_id,
                                   uint64_t timestamp);

// What a message id means to the receiver: its CRC_EXTRA and full payload length. nullopt: an
// id it does not know (the frame is counted and skipped: its checksum cannot be checked).
struct MessageInfo {
  uint8_t crc_extra = 0;
  uint8_t length = 0;  // with extensions: what the receiver pads a truncated payload to
};
using MessageLookup = std::function<std::optional<MessageInfo>(uint32_t msgid)>;

// Frames out of a byte stream (a serial line or UDP datagrams): bytes before a start marker and
// frames that fail their checksum are skipped and counted, so the parser finds the next frame.
// A signed frame's signature is checked by the caller (Verify), who holds the key and the
// timestamps seen.
class Parser {
 public:
  explicit Parser(MessageLookup lookup) : lookup_(std::move(lookup)) {}
  // Appends `size` bytes; returns the frames they complete, in order.
  std::vector<Frame> Push(const uint8_t* data, std::size_t size);
  // Takes one datagram, which holds whole frames: what is left of an incomplete or bogus frame at
  // its end is dropped (counted as skipped), never joined to the next datagram.
  std::vector<Frame> PushDatagram(const uint8_t* data, std::size_t size);
  struct Counts {
    int64_t frames = 0;          // good frames
    int64_t bad_checksum = 0;    // a start marker and a length, then a checksum that fails
    int64_t unknown_message = 0; // ids the lookup does not know
    int64_t skipped_bytes = 0;   // not in any frame
    int64_t bad_flags = 0;       // MAVLink 2 incompatibility flags this parser does not know
  };
  const Counts& counts() const { return counts_; }

 private:
  MessageLookup lookup_;
  std::vector<uint8_t> buffer_;
  Counts counts_;
};

// Whether a signed frame's signature is the key's (Frame::raw, signature included). A replayed
// or stale timestamp is the caller's to refuse: it keeps the newest per link.
bool Verify(const SecretKey& key, const std::vector<uint8_t>& raw);

// The receiving side of signing (mavlink.io "Message Signing", accepting packets): a frame is
// accepted when its signature is the key's and its timestamp is newer than the last accepted on
// its stream (system id, component id, link id); a stream not seen before must be no more than a
// minute behind this side's timestamp, which is the newest of the wall clock and every timestamp
// accepted. Unsigned frames are refused unless `insecure`.
class SignedStreams {
 public:
  enum class Verdict { kAccepted, kUnsigned, kBadSignature, kReplay, kStale };
  static const char* Name(Verdict v);  // "accepted", "unsigned", "bad signature", "replayed", "stale"
  SignedStreams(const SecretKey& key, bool insecure) : key_(key), insecure_(insecure) {}
  // `now`: this side's wall clock as a signing timestamp (uav::SigningTimestamp).
  Verdict Check(const Frame& f, uint64_t now);
  // The timestamp for the next frame this side signs: the newest known, plus one (strictly
  // increasing, as the specification asks of a sender).
  uint64_t NextTimestamp(uint64_t now);
  static constexpr uint64_t kNewStreamWindow = 6'000'000;  // [10 us] one minute

 private:
  SecretKey key_;
  bool insecure_;
  uint64_t newest_ = 0;
  uint64_t sent_ = 0;
  std::map<std::tuple<uint8_t, uint8_t, uint8_t>, uint64_t> last_;
};

}  // namespace uav::mavlink
