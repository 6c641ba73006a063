#pragma once
// Message signing, the MAVLink 2 model: a secret 32-byte key shared by the vehicle and its GCSs,
// a tag over each message that changes what the vehicle does, and a 48-bit timestamp in 10 us
// units that must increase per link, so that a recorded message cannot be played again.
//   tag = HMAC-SHA256(key, vehicle_id || 0x00 || link_id (1 byte) || timestamp (6 bytes LE) || bytes)
// where `bytes` is the LCM encoding of the message with the tag's 32 bytes zeroed (the header
// with the vehicle id, the source and the timestamp are inside it too).
// Plain data in, verdicts out: the link translators (messages) sit on either side.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <utility>

namespace uav {

using SigningTag = std::array<uint8_t, 32>;

// HMAC (RFC 2104) over SHA-256 (FIPS 198-1).
SigningTag HmacSha256(const uint8_t* key, size_t key_size, const void* data, size_t size);

struct SigningKey {
  std::array<uint8_t, 32> bytes{};
  // Reads a key file: exactly 32 bytes, a regular file that neither its group nor others may
  // read or write (mode 0600 or 0400). Throws std::runtime_error naming the file and the fault.
  static SigningKey LoadFile(const std::string& path);
  // Writes 32 random bytes (the kernel's getrandom) to a new file of mode 0600. Refuses to
  // overwrite an existing file. Throws std::runtime_error naming the file.
  static SigningKey Generate(const std::string& path);
  // SHA-256 of a passphrase: the key QGroundControl and Mission Planner make from the passphrase
  // an operator types (MAVLink 2 signing). Throws std::invalid_argument for an empty one.
  static SigningKey FromPassphrase(const std::string& passphrase);
  // Writes the key to a new file of mode 0600 (refuses to overwrite; nothing is left on failure).
  void Save(const std::string& path) const;
  // A name to compare keys by without showing them: 16 hex digits of SHA-256(key).
  std::string Id() const;
};

// [10 us] since 2015-01-01T00:00:00Z of the wall-clock time `unix_us` (MAVLink 2's epoch).
int64_t SigningTimestamp(int64_t unix_us);
constexpr int64_t kSigningTimestampMax = (int64_t{1} << 48) - 1;

// The fields of a signature_t, as plain data.
struct Signature {
  int link_id = 0;         // 0..255
  int64_t timestamp = 0;   // [10 us] since the epoch above
  SigningTag tag{};
};

// Computes the tag over a message's bytes (with its tag zeroed).
SigningTag SignatureTag(const SigningKey& key, const std::string& vehicle_id, int link_id, int64_t timestamp,
                        const void* bytes, size_t size);

// The GCS's side: one per link. Timestamps are the wall clock, made strictly increasing.
class MessageSigner {
 public:
  MessageSigner(const SigningKey& key, int link_id);
  // The next signature's link and timestamp (tag empty): the caller encodes the message with it
  // and calls Tag().
  Signature Next(int64_t unix_us);
  SigningTag Tag(const std::string& vehicle_id, const Signature& s, const void* bytes, size_t size) const;
  const std::string& key_id() const { return key_id_; }

 private:
  SigningKey key_;
  std::string key_id_;
  int link_id_;
  int64_t last_ = 0;
};

enum class SignatureVerdict { kAccepted, kUnsigned, kWrongVehicle, kBadTag, kReplay, kStale };
const char* SignatureVerdictName(SignatureVerdict v);  // "accepted", "unsigned", "bad tag", ...

struct SignatureVerifierParams {
  // [10 us] how old a new link's first timestamp may be against the newest this vehicle knows
  // (MAVLink 2: one minute).
  int64_t window = 6'000'000;
};

// The vehicle's side. Accepts a tag made with its key over a message addressed to it whose
// timestamp is newer than the last accepted on that (source, link); a link not yet seen must be
// no older than the window against the newest timestamp known (the wall clock or any accepted
// one), and never older than the floor: the newest timestamp accepted before a restart, or the
// process's start, so that a message recorded before the restart is refused after it.
class SignatureVerifier {
 public:
  SignatureVerifier(const SigningKey& key, std::string vehicle_id, int64_t floor,
                    SignatureVerifierParams params = {});
  // `signed_message`: the signature's version was VERSION_HMAC_SHA256. `bytes`: the message
  // encoded with the tag zeroed. `now`: this vehicle's wall clock as a SigningTimestamp.
  SignatureVerdict Verify(bool signed_message, const std::string& addressed_to, const std::string& source,
                          const Signature& s, const void* bytes, size_t size, int64_t now);
  // The newest timestamp accepted on any link (or the floor): what to persist for a restart.
  int64_t newest() const { return newest_; }

 private:
  SigningKey key_;
  std::string vehicle_id_;
  SignatureVerifierParams params_;
  int64_t floor_;
  int64_t newest_;
  std::map<std::pair<std::string, int>, int64_t> last_;  // (source, link) -> last accepted timestamp
};

}  // namespace uav
