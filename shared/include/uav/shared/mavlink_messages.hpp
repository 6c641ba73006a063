#pragma once
// The MAVLink messages we speak, as plain structs (one per row of mavlink_messages.def, fields in
// the specification's order and units), and their wire layouts derived from the same rows: the
// fields sorted by type size (extensions last, in declared order), each message's CRC_EXTRA
// computed from its name and base fields as mavgen does, the full payload length. Encoding and
// decoding walk the layout, so a message's layout is declared in one place only.
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "uav/shared/mavlink_frame.hpp"

namespace uav::mavlink {

template <class T, std::size_t N>
using FieldType = std::conditional_t<N == 0, T, std::array<T, N>>;

#define UAV_MAVLINK_FIELD(T, name, N) FieldType<T, N> name{};
#define UAV_MAVLINK_MESSAGE(Type, NAME, ID, FIELDS, EXTENSIONS) \
  struct Type {                                                 \
    static constexpr uint32_t kId = ID;                         \
    FIELDS EXTENSIONS                                           \
  };
#include "uav/shared/mavlink_messages.def"
#undef UAV_MAVLINK_MESSAGE
#undef UAV_MAVLINK_FIELD

struct FieldLayout {
  std::string name;
  std::string type;          // the specification's type name: "uint16_t", "char", "float"
  std::size_t element_size;  // bytes of one element
  std::size_t array_length;  // 0: a scalar
  bool extension;
  std::size_t struct_offset;  // in the C++ struct
  std::size_t wire_offset;    // in the payload
  std::size_t size() const { return element_size * (array_length ? array_length : 1); }
};

struct MessageLayout {
  uint32_t id = 0;
  std::string name;               // "HEARTBEAT"
  uint8_t crc_extra = 0;
  std::size_t length = 0;         // full payload, extensions included
  std::size_t base_length = 0;    // without extensions (what a MAVLink 1 frame carries)
  std::vector<FieldLayout> fields;  // wire order
};

// Every message of the table, by id order.
const std::vector<MessageLayout>& Layouts();
// The layout of `id`, or null for a message we do not speak.
const MessageLayout* FindLayout(uint32_t id);
// What the frame parser needs: CRC_EXTRA and length of a known id.
MessageLookup Lookup();

// The payload of a message (full length; the frame encoder drops trailing zeros) and back.
// Unpack takes a payload padded to the full length (the parser does that) and throws
// std::invalid_argument when it is shorter or the id is not the message's.
std::vector<uint8_t> PackPayload(const MessageLayout& layout, const void* message);
void UnpackPayload(const MessageLayout& layout, const std::vector<uint8_t>& payload, void* message);

template <class M>
std::vector<uint8_t> Pack(const M& m) {
  return PackPayload(*FindLayout(M::kId), &m);
}
template <class M>
M Unpack(const Frame& f) {
  M m;
  if (f.msgid != M::kId) throw std::invalid_argument("MAVLink message " + std::to_string(f.msgid) + " is not " +
                                                     FindLayout(M::kId)->name);
  UnpackPayload(*FindLayout(M::kId), f.payload, &m);
  return m;
}

// A parameter's MAVLink id (PARAM_VALUE's param_id holds 16 characters): its name when it fits,
// else its first 11 characters, '_' and 4 hex digits of a hash of the whole name. Stable (it
// depends on the name alone, so a GCS's saved parameter files keep working as parameters are
// added) and checked unique over the vehicle's schema by the tests.
std::string ParamIdOf(const std::string& name);

// A char[N] field as text (up to its first NUL; N characters when it has none, as MAVLink
// allows) and back (truncated to N).
template <std::size_t N>
std::string Text(const std::array<char, N>& a) {
  std::size_t n = 0;
  while (n < N && a[n] != '\0') ++n;
  return std::string(a.data(), n);
}
template <std::size_t N>
void SetText(std::array<char, N>& a, const std::string& s) {
  a.fill('\0');
  for (std::size_t i = 0; i < N && i < s.size(); ++i) a[i] = s[i];
}

}  // namespace uav::mavlink
