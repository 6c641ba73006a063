#include "uav/shared/mavlink_messages.hpp"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <map>
#include <stdexcept>

namespace uav::mavlink {
namespace {

static_assert(__BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__, "MAVLink is little-endian; this codec copies fields as they are");

struct Declared {
  const char* name;
  const char* type;
  std::size_t element_size;
  std::size_t array_length;
  std::size_t struct_offset;
};

// Wire order (mavlink.io "Field Reordering"): base fields sorted by element size, largest
// first, a stable sort so that equal sizes keep their declared order; extensions follow in their
// declared order, unsorted. CRC_EXTRA (mavgen): X.25 over "NAME ", then for each base field in
// wire order "type name " and, for an array, its length as one byte; the high byte xor the low.
MessageLayout Build(uint32_t id, const char* name, const std::vector<Declared>& base,
                    const std::vector<Declared>& extensions) {
  MessageLayout l;
  l.id = id;
  l.name = name;
  auto add = [&l](const Declared& d, bool extension) {
    l.fields.push_back({d.name, d.type, d.element_size, d.array_length, extension, d.struct_offset, 0});
  };
  for (const Declared& d : base) add(d, false);
  std::stable_sort(l.fields.begin(), l.fields.end(),
                   [](const FieldLayout& a, const FieldLayout& b) { return a.element_size > b.element_size; });
  for (const Declared& d : extensions) add(d, true);
  std::size_t offset = 0;
  for (FieldLayout& f : l.fields) {
    f.wire_offset = offset;
    offset += f.size();
    if (!f.extension) l.base_length = offset;
  }
  l.length = offset;
  auto accumulate = [](uint16_t crc, const std::string& s) {
    return Crc16(reinterpret_cast<const uint8_t*>(s.data()), s.size(), crc);
  };
  uint16_t crc = accumulate(0xFFFF, l.name + " ");
  for (const FieldLayout& f : l.fields) {
    if (f.extension) continue;
    crc = accumulate(crc, f.type + " ");
    crc = accumulate(crc, f.name + " ");
    if (f.array_length) {
      const uint8_t n = static_cast<uint8_t>(f.array_length);
      crc = Crc16(&n, 1, crc);
    }
  }
  l.crc_extra = static_cast<uint8_t>((crc & 0xFF) ^ (crc >> 8));
  return l;
}

std::vector<MessageLayout> BuildAll() {
  std::vector<MessageLayout> all;
#define UAV_MAVLINK_FIELD(T, name, N) Declared{#name, #T, sizeof(T), N, offsetof(Self, name)},
#define UAV_MAVLINK_MESSAGE(Type, NAME, ID, FIELDS, EXTENSIONS) \
  {                                                             \
    using Self = Type;                                          \
    all.push_back(Build(ID, #NAME, {FIELDS}, {EXTENSIONS}));    \
  }
#include "uav/shared/mavlink_messages.def"
#undef UAV_MAVLINK_MESSAGE
#undef UAV_MAVLINK_FIELD
  std::sort(all.begin(), all.end(), [](const MessageLayout& a, const MessageLayout& b) { return a.id < b.id; });
  return all;
}

}  // namespace

const std::vector<MessageLayout>& Layouts() {
  static const std::vector<MessageLayout> kAll = BuildAll();
  return kAll;
}

const MessageLayout* FindLayout(uint32_t id) {
  static const std::map<uint32_t, const MessageLayout*> kById = [] {
    std::map<uint32_t, const MessageLayout*> m;
    for (const MessageLayout& l : Layouts()) m[l.id] = &l;
    return m;
  }();
  const auto it = kById.find(id);
  return it == kById.end() ? nullptr : it->second;
}

MessageLookup Lookup() {
  return [](uint32_t id) -> std::optional<MessageInfo> {
    const MessageLayout* l = FindLayout(id);
    if (!l) return std::nullopt;
    return MessageInfo{l->crc_extra, static_cast<uint8_t>(l->length)};
  };
}

std::string ParamIdOf(const std::string& name) {
  if (name.size() <= 16) return name;
  uint32_t h = 2166136261u;  // FNV-1a, folded to 16 bits
  for (unsigned char ch : name) h = (h ^ ch) * 16777619u;
  char tail[8];
  std::snprintf(tail, sizeof tail, "_%04x", static_cast<unsigned>((h ^ (h >> 16)) & 0xFFFF));
  return name.substr(0, 11) + tail;
}

std::vector<uint8_t> PackPayload(const MessageLayout& layout, const void* message) {
  std::vector<uint8_t> payload(layout.length, 0);
  const auto* s = static_cast<const uint8_t*>(message);
  for (const FieldLayout& f : layout.fields) std::memcpy(payload.data() + f.wire_offset, s + f.struct_offset, f.size());
  return payload;
}

void UnpackPayload(const MessageLayout& layout, const std::vector<uint8_t>& payload, void* message) {
  if (payload.size() < layout.length)
    throw std::invalid_argument(layout.name + ": payload of " + std::to_string(payload.size()) + " bytes, " +
                                std::to_string(layout.length) + " expected");
  auto* s = static_cast<uint8_t*>(message);
  for (const FieldLayout& f : layout.fields) std::memcpy(s + f.struct_offset, payload.data() + f.wire_offset, f.size());
}

}  // namespace uav::mavlink
