#pragma once
// Signing and checking LCM messages that embed a uavmsg::signature_t named `signature` and a
// header_t named `header` (shared/signing.hpp has the model). The bytes tagged are the message's
// own LCM encoding with the tag zeroed: the encoding is canonical, so the receiver re-encodes
// what it decoded and gets the sender's bytes.
#include <algorithm>
#include <string>
#include <vector>

#include "uav/shared/signing.hpp"
#include "uavmsg/signature_t.hpp"

namespace uav {

namespace signing_detail {
template <class Msg>
std::vector<uint8_t> EncodeWithZeroTag(Msg m) {
  std::fill(std::begin(m.signature.tag), std::end(m.signature.tag), uint8_t{0});
  std::vector<uint8_t> bytes(static_cast<size_t>(m.getEncodedSize()));
  m.encode(bytes.data(), 0, static_cast<int>(bytes.size()));
  return bytes;
}
}  // namespace signing_detail

// Stamps `m` with the signer's next link timestamp and its tag. `unix_us`: the wall clock.
template <class Msg>
void SignMessage(MessageSigner& signer, int64_t unix_us, Msg& m) {
  const Signature s = signer.Next(unix_us);
  m.signature.version = uavmsg::signature_t::VERSION_HMAC_SHA256;
  m.signature.link_id = static_cast<int16_t>(s.link_id);
  m.signature.timestamp = s.timestamp;
  m.signature.key_id = signer.key_id();
  const std::vector<uint8_t> bytes = signing_detail::EncodeWithZeroTag(m);
  const SigningTag tag = signer.Tag(m.header.vehicle_id, s, bytes.data(), bytes.size());
  std::copy(tag.begin(), tag.end(), std::begin(m.signature.tag));
}

// The verdict on a decoded message from `source`; `now`: SigningTimestamp of this wall clock.
template <class Msg>
SignatureVerdict VerifyMessage(SignatureVerifier& verifier, const Msg& m, const std::string& source, int64_t now) {
  Signature s;
  s.link_id = m.signature.link_id;
  s.timestamp = m.signature.timestamp;
  std::copy(std::begin(m.signature.tag), std::end(m.signature.tag), s.tag.begin());
  const std::vector<uint8_t> bytes = signing_detail::EncodeWithZeroTag(m);
  return verifier.Verify(m.signature.version == uavmsg::signature_t::VERSION_HMAC_SHA256, m.header.vehicle_id,
                         source, s, bytes.data(), bytes.size(), now);
}

}  // namespace uav
