#include "uav/shared/signing.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "uav/shared/sha256.hpp"

namespace uav {

SigningTag HmacSha256(const uint8_t* key, size_t key_size, const void* data, size_t size) {
  // RFC 2104: keys longer than the block are hashed first; then H((K ^ opad) || H((K ^ ipad) || m)).
  constexpr size_t kBlock = 64;
  std::array<uint8_t, kBlock> k{};
  if (key_size > kBlock) {
    Sha256 h;
    h.Update(key, key_size);
    const auto d = h.Final();
    std::memcpy(k.data(), d.data(), d.size());
  } else if (key_size > 0) {
    std::memcpy(k.data(), key, key_size);
  }
  std::array<uint8_t, kBlock> pad;
  for (size_t i = 0; i < kBlock; ++i) pad[i] = k[i] ^ 0x36;
  Sha256 inner;
  inner.Update(pad.data(), pad.size());
  inner.Update(data, size);
  const auto inner_digest = inner.Final();
  for (size_t i = 0; i < kBlock; ++i) pad[i] = k[i] ^ 0x5c;
  Sha256 outer;
  outer.Update(pad.data(), pad.size());
  outer.Update(inner_digest.data(), inner_digest.size());
  return outer.Final();
}

SigningKey SigningKey::LoadFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOFOLLOW);
  if (fd < 0) throw std::runtime_error("cannot open signing key '" + path + "': " + std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw std::runtime_error("signing key '" + path + "' is not a regular file");
  }
  if (st.st_mode & (S_IRWXG | S_IRWXO)) {
    ::close(fd);
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    throw std::runtime_error("signing key '" + path + "' has mode " + mode +
                             ": others could read or change it; chmod 600 it (or make a new one with uav-keygen)");
  }
  SigningKey key;
  uint8_t extra = 0;
  const ssize_t n = ::read(fd, key.bytes.data(), key.bytes.size());
  const ssize_t more = n == static_cast<ssize_t>(key.bytes.size()) ? ::read(fd, &extra, 1) : 0;
  ::close(fd);
  if (n != static_cast<ssize_t>(key.bytes.size()) || more != 0)
    throw std::runtime_error("signing key '" + path + "' must hold exactly 32 bytes (uav-keygen writes one), it holds " +
                             std::to_string(st.st_size));
  return key;
}

SigningKey SigningKey::Generate(const std::string& path) {
  SigningKey key;
  size_t got = 0;
  while (got < key.bytes.size()) {
    const ssize_t n = ::getrandom(key.bytes.data() + got, key.bytes.size() - got, 0);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) throw std::runtime_error(std::string("cannot draw a random key: ") + std::strerror(errno));
    got += static_cast<size_t>(n);
  }
  key.Save(path);
  return key;
}

SigningKey SigningKey::FromPassphrase(const std::string& passphrase) {
  if (passphrase.empty()) throw std::invalid_argument("an empty passphrase makes no key");
  SigningKey key;
  Sha256 sha;
  sha.Update(passphrase.data(), passphrase.size());
  key.bytes = sha.Final();
  return key;
}

void SigningKey::Save(const std::string& path) const {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NOFOLLOW, 0600);
  if (fd < 0) throw std::runtime_error("cannot create signing key '" + path + "': " + std::strerror(errno));
  ::fchmod(fd, 0600);  // whatever the umask
  const ssize_t n = ::write(fd, bytes.data(), bytes.size());
  const bool synced = ::fsync(fd) == 0;
  const bool closed = ::close(fd) == 0;
  if (n != static_cast<ssize_t>(bytes.size()) || !synced || !closed) {
    ::unlink(path.c_str());
    throw std::runtime_error("cannot write signing key '" + path + "': " + std::strerror(errno));
  }
}

std::string SigningKey::Id() const { return Sha256::HexOf(bytes.data(), bytes.size()).substr(0, 16); }

int64_t SigningTimestamp(int64_t unix_us) {
  constexpr int64_t kEpoch2015Us = 1420070400LL * 1000000;  // 2015-01-01T00:00:00Z
  return (unix_us - kEpoch2015Us) / 10;
}

SigningTag SignatureTag(const SigningKey& key, const std::string& vehicle_id, int link_id, int64_t timestamp,
                        const void* bytes, size_t size) {
  std::string data = vehicle_id;
  data.push_back('\0');
  data.push_back(static_cast<char>(link_id & 0xff));
  for (int i = 0; i < 6; ++i) data.push_back(static_cast<char>((timestamp >> (8 * i)) & 0xff));
  data.append(static_cast<const char*>(bytes), size);
  return HmacSha256(key.bytes.data(), key.bytes.size(), data.data(), data.size());
}

MessageSigner::MessageSigner(const SigningKey& key, int link_id) : key_(key), key_id_(key.Id()), link_id_(link_id) {
  if (link_id < 0 || link_id > 255) throw std::invalid_argument("link id must be 0..255, got " + std::to_string(link_id));
}

Signature MessageSigner::Next(int64_t unix_us) {
  // Strictly increasing even when the wall clock steps back or two messages share a tick.
  last_ = std::max(last_ + 1, SigningTimestamp(unix_us));
  Signature s;
  s.link_id = link_id_;
  s.timestamp = last_;
  return s;
}

SigningTag MessageSigner::Tag(const std::string& vehicle_id, const Signature& s, const void* bytes, size_t size) const {
  return SignatureTag(key_, vehicle_id, s.link_id, s.timestamp, bytes, size);
}

const char* SignatureVerdictName(SignatureVerdict v) {
  switch (v) {
    case SignatureVerdict::kAccepted: return "accepted";
    case SignatureVerdict::kUnsigned: return "unsigned";
    case SignatureVerdict::kWrongVehicle: return "wrong vehicle";
    case SignatureVerdict::kBadTag: return "bad tag";
    case SignatureVerdict::kReplay: return "replay";
    case SignatureVerdict::kStale: return "stale";
  }
  return "?";
}

SignatureVerifier::SignatureVerifier(const SigningKey& key, std::string vehicle_id, int64_t floor,
                                     SignatureVerifierParams params)
    : key_(key), vehicle_id_(std::move(vehicle_id)), params_(params), floor_(floor), newest_(floor) {}

SignatureVerdict SignatureVerifier::Verify(bool signed_message, const std::string& addressed_to,
                                           const std::string& source, const Signature& s, const void* bytes,
                                           size_t size, int64_t now) {
  if (!signed_message) return SignatureVerdict::kUnsigned;
  if (addressed_to != vehicle_id_) return SignatureVerdict::kWrongVehicle;
  if (s.link_id < 0 || s.link_id > 255 || s.timestamp < 0 || s.timestamp > kSigningTimestampMax)
    return SignatureVerdict::kBadTag;  // fields no signer writes
  const SigningTag expected = SignatureTag(key_, addressed_to, s.link_id, s.timestamp, bytes, size);
  uint8_t diff = 0;  // constant time: how far a guess matched must not show in the timing
  for (size_t i = 0; i < expected.size(); ++i) diff |= static_cast<uint8_t>(expected[i] ^ s.tag[i]);
  if (diff != 0) return SignatureVerdict::kBadTag;
  const auto link = std::make_pair(source, s.link_id);
  const auto it = last_.find(link);
  if (it != last_.end()) {
    if (s.timestamp <= it->second) return SignatureVerdict::kReplay;
  } else if (s.timestamp <= floor_ || s.timestamp < std::max(now, newest_) - params_.window) {
    return SignatureVerdict::kStale;
  }
  last_[link] = s.timestamp;
  newest_ = std::max(newest_, s.timestamp);
  return SignatureVerdict::kAccepted;
}

}  // namespace uav
