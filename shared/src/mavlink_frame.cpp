#include "uav/shared/mavlink_frame.hpp"

#include <algorithm>
#include <stdexcept>

#include "uav/shared/sha256.hpp"

namespace uav::mavlink {
namespace {

constexpr std::size_t kHeaderV2 = 10, kHeaderV1 = 6, kChecksum = 2, kSignature = 13;

}  // namespace

uint16_t Crc16(const uint8_t* data, std::size_t size, uint16_t crc) {
  for (std::size_t i = 0; i < size; ++i) {
    uint8_t tmp = data[i] ^ static_cast<uint8_t>(crc & 0xFF);
    tmp ^= static_cast<uint8_t>(tmp << 4);
    crc = static_cast<uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
  }
  return crc;
}

std::array<uint8_t, 6> SignatureOf(const SecretKey& key, const uint8_t* frame, std::size_t size, uint8_t link_id,
                                   uint64_t timestamp) {
  Sha256 sha;
  sha.Update(key.data(), key.size());
  sha.Update(frame, size);
  uint8_t tail[7] = {link_id};
  for (int i = 0; i < 6; ++i) tail[1 + i] = static_cast<uint8_t>(timestamp >> (8 * i));
  sha.Update(tail, sizeof tail);
  const std::array<uint8_t, 32> digest = sha.Final();
  std::array<uint8_t, 6> out{};
  std::copy_n(digest.begin(), 6, out.begin());
  return out;
}

std::vector<uint8_t> Encode(const Frame& f, uint8_t crc_extra, const SecretKey* key, uint8_t link_id, uint64_t timestamp) {
  if (f.payload.size() > 255) throw std::invalid_argument("MAVLink payload of " + std::to_string(f.payload.size()) + " bytes (at most 255)");
  if (timestamp >> 48) throw std::invalid_argument("MAVLink signing timestamp over 48 bits");
  std::vector<uint8_t> out;
  if (f.version == 1) {
    if (f.msgid > 255) throw std::invalid_argument("MAVLink 1 cannot carry message id " + std::to_string(f.msgid));
    out = {kStxV1, static_cast<uint8_t>(f.payload.size()), f.seq, f.sysid, f.compid, static_cast<uint8_t>(f.msgid)};
    out.insert(out.end(), f.payload.begin(), f.payload.end());
  } else {
    if (f.msgid >> 24) throw std::invalid_argument("MAVLink message id " + std::to_string(f.msgid) + " over 24 bits");
    // Trailing zeros are not sent; the first payload byte always is.
    std::size_t n = f.payload.size();
    while (n > 1 && f.payload[n - 1] == 0) --n;
    const uint8_t incompat = static_cast<uint8_t>((f.incompat_flags & ~kIncompatSigned) | (key ? kIncompatSigned : 0));
    out = {kStxV2, static_cast<uint8_t>(n), incompat, f.compat_flags, f.seq, f.sysid, f.compid,
           static_cast<uint8_t>(f.msgid), static_cast<uint8_t>(f.msgid >> 8), static_cast<uint8_t>(f.msgid >> 16)};
    out.insert(out.end(), f.payload.begin(), f.payload.begin() + static_cast<long>(n));
  }
  uint16_t crc = Crc16(out.data() + 1, out.size() - 1);
  crc = Crc16(&crc_extra, 1, crc);
  out.push_back(static_cast<uint8_t>(crc & 0xFF));
  out.push_back(static_cast<uint8_t>(crc >> 8));
  if (key && f.version == 2) {
    const std::array<uint8_t, 6> sig = SignatureOf(*key, out.data(), out.size(), link_id, timestamp);
    out.push_back(link_id);
    for (int i = 0; i < 6; ++i) out.push_back(static_cast<uint8_t>(timestamp >> (8 * i)));
    out.insert(out.end(), sig.begin(), sig.end());
  }
  return out;
}

bool Verify(const SecretKey& key, const std::vector<uint8_t>& raw) {
  if (raw.size() < kHeaderV2 + kChecksum + kSignature || raw[0] != kStxV2 || !(raw[2] & kIncompatSigned)) return false;
  const std::size_t unsigned_size = raw.size() - kSignature;
  const uint8_t* s = raw.data() + unsigned_size;
  uint64_t timestamp = 0;
  for (int i = 0; i < 6; ++i) timestamp |= static_cast<uint64_t>(s[1 + i]) << (8 * i);
  const std::array<uint8_t, 6> expected = SignatureOf(key, raw.data(), unsigned_size, s[0], timestamp);
  return std::equal(expected.begin(), expected.end(), s + 7);
}

const char* SignedStreams::Name(Verdict v) {
  switch (v) {
    case Verdict::kAccepted: return "accepted";
    case Verdict::kUnsigned: return "unsigned";
    case Verdict::kBadSignature: return "bad signature";
    case Verdict::kReplay: return "replayed";
    case Verdict::kStale: return "stale";
  }
  return "?";
}

SignedStreams::Verdict SignedStreams::Check(const Frame& f, uint64_t now) {
  newest_ = std::max(newest_, now);
  if (!f.signature) return insecure_ ? Verdict::kAccepted : Verdict::kUnsigned;
  if (!Verify(key_, f.raw)) return Verdict::kBadSignature;
  const uint64_t t = f.signature->timestamp;
  const auto stream = std::make_tuple(f.sysid, f.compid, f.signature->link_id);
  const auto it = last_.find(stream);
  if (it != last_.end() && t <= it->second) return Verdict::kReplay;
  if (it == last_.end() && t + kNewStreamWindow < newest_) return Verdict::kStale;
  last_[stream] = t;
  newest_ = std::max(newest_, t);
  return Verdict::kAccepted;
}

uint64_t SignedStreams::NextTimestamp(uint64_t now) {
  sent_ = std::max({sent_ + 1, now, newest_});
  return sent_;
}

std::vector<Frame> Parser::Push(const uint8_t* data, std::size_t size) {
  buffer_.insert(buffer_.end(), data, data + size);
  std::vector<Frame> out;
  std::size_t at = 0;
  while (at < buffer_.size()) {
    const uint8_t stx = buffer_[at];
    if (stx != kStxV1 && stx != kStxV2) {
      ++at;
      ++counts_.skipped_bytes;
      continue;
    }
    const bool v2 = stx == kStxV2;
    const std::size_t header = v2 ? kHeaderV2 : kHeaderV1;
    if (buffer_.size() - at < header) break;  // wait for the rest
    const uint8_t len = buffer_[at + 1];
    const bool signed_frame = v2 && (buffer_[at + 2] & kIncompatSigned);
    const std::size_t total = header + len + kChecksum + (signed_frame ? kSignature : 0);
    if (buffer_.size() - at < total) break;
    const uint8_t* p = buffer_.data() + at;
    Frame f;
    f.version = v2 ? 2 : 1;
    if (v2) {
      f.incompat_flags = p[2], f.compat_flags = p[3], f.seq = p[4], f.sysid = p[5], f.compid = p[6];
      f.msgid = p[7] | (p[8] << 8) | (static_cast<uint32_t>(p[9]) << 16);
    } else {
      f.seq = p[2], f.sysid = p[3], f.compid = p[4], f.msgid = p[5];
    }
    if (v2 && (f.incompat_flags & ~kIncompatSigned)) {
      // A flag this parser does not know: the frame must be dropped (the specification's rule).
      ++counts_.bad_flags;
      at += total;
      continue;
    }
    const std::optional<MessageInfo> info = lookup_(f.msgid);
    if (!info) {
      ++counts_.unknown_message;
      at += total;
      continue;
    }
    uint16_t crc = Crc16(p + 1, header - 1 + len);
    crc = Crc16(&info->crc_extra, 1, crc);
    const uint16_t sent = static_cast<uint16_t>(p[header + len] | (p[header + len + 1] << 8));
    if (crc != sent) {
      // Not a frame after all (or a damaged one): look for the next start marker from the next byte.
      ++counts_.bad_checksum;
      ++at;
      continue;
    }
    f.payload.assign(p + header, p + header + len);
    if (f.payload.size() < info->length) f.payload.resize(info->length, 0);  // truncated zeros back
    if (signed_frame) {
      const uint8_t* s = p + header + len + kChecksum;
      Signature sig;
      sig.link_id = s[0];
      for (int i = 0; i < 6; ++i) sig.timestamp |= static_cast<uint64_t>(s[1 + i]) << (8 * i);
      std::copy_n(s + 7, 6, sig.value.begin());
      f.signature = sig;
    }
    f.raw.assign(p, p + total);
    out.push_back(std::move(f));
    ++counts_.frames;
    at += total;
  }
  buffer_.erase(buffer_.begin(), buffer_.begin() + static_cast<long>(at));
  return out;
}

std::vector<Frame> Parser::PushDatagram(const uint8_t* data, std::size_t size) {
  std::vector<Frame> out = Push(data, size);
  counts_.skipped_bytes += static_cast<int64_t>(buffer_.size());
  buffer_.clear();
  return out;
}

}  // namespace uav::mavlink
