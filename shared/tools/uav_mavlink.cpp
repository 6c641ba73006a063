// uav-mavlink: our MAVLink tables and a decoder for captured bytes.
//   uav-mavlink tables            every message we speak: id, CRC_EXTRA, lengths, fields in wire
//                                 order (JSON; tests/mavlink/tables.js checks it against npm's
//                                 mavlink-mappings)
//   uav-mavlink decode FILE [--key K]
//                                 the frames in a capture (a raw byte stream, or a QGroundControl
//                                 .tlog: its 8-byte time stamps are skipped as noise) as JSON lines,
//                                 with whether each signature is the key's, then the counts
#include <fstream>
#include <iostream>
#include <cstring>
#include <iterator>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "uav/shared/mavlink_messages.hpp"
#include "uav/shared/program.hpp"
#include "uav/shared/signing.hpp"

namespace {

using nlohmann::json;
using namespace uav::mavlink;

json Tables() {
  json out = json::array();
  for (const MessageLayout& l : Layouts()) {
    json fields = json::array();
    for (const FieldLayout& f : l.fields)
      fields.push_back({{"name", f.name}, {"type", f.type}, {"offset", f.wire_offset}, {"size", f.size()},
                        {"array_length", f.array_length}, {"extension", f.extension}});
    out.push_back({{"id", l.id}, {"name", l.name}, {"crc_extra", l.crc_extra}, {"length", l.length},
                   {"base_length", l.base_length}, {"fields", fields}});
  }
  return out;
}

// A field's value as JSON: numbers, text for char arrays, lists for other arrays.
json FieldValue(const FieldLayout& f, const uint8_t* p) {
  auto scalar = [&f](const uint8_t* q) -> json {
    auto get = [q](auto v) {
      std::memcpy(&v, q, sizeof v);
      return v;
    };
    if (f.type == "uint8_t") return get(uint8_t{});
    if (f.type == "int8_t") return get(int8_t{});
    if (f.type == "uint16_t") return get(uint16_t{});
    if (f.type == "int16_t") return get(int16_t{});
    if (f.type == "uint32_t") return get(uint32_t{});
    if (f.type == "int32_t") return get(int32_t{});
    if (f.type == "uint64_t") return get(uint64_t{});
    if (f.type == "int64_t") return get(int64_t{});
    if (f.type == "float") return get(float{});
    if (f.type == "double") return get(double{});
    return get(char{});
  };
  if (f.type == "char") {
    std::string s(reinterpret_cast<const char*>(p), f.size());
    return s.substr(0, s.find('\0'));
  }
  if (!f.array_length) return scalar(p);
  json a = json::array();
  for (std::size_t i = 0; i < f.array_length; ++i) a.push_back(scalar(p + i * f.element_size));
  return a;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"uav-mavlink: the MAVLink messages this vehicle and GCS speak, and a decoder for captures"};
  cli.require_subcommand(1);
  CLI::App* tables = cli.add_subcommand("tables", "print every message's layout as JSON");
  CLI::App* decode = cli.add_subcommand("decode", "decode the MAVLink frames in a capture file (raw bytes or .tlog)");
  std::string file, key_file;
  decode->add_option("FILE", file, "capture file")->required()->check(CLI::ExistingFile);
  decode->add_option("--key", key_file, "signing key file: say whether each signature is this key's");
  uav::PrepareCommandLine(cli);
  CLI11_PARSE(cli, argc, argv);
  try {
    if (tables->parsed()) {
      std::cout << Tables().dump(1) << "\n";
      return 0;
    }
    std::optional<uav::SigningKey> key;
    if (!key_file.empty()) key = uav::SigningKey::LoadFile(key_file);
    std::ifstream in(file, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    Parser parser(Lookup());
    for (const Frame& f : parser.Push(bytes.data(), bytes.size())) {
      const MessageLayout& l = *FindLayout(f.msgid);
      json fields = json::object();
      for (const FieldLayout& fl : l.fields) fields[fl.name] = FieldValue(fl, f.payload.data() + fl.wire_offset);
      json line = {{"version", f.version}, {"seq", f.seq}, {"sysid", f.sysid}, {"compid", f.compid},
                   {"msgid", f.msgid}, {"name", l.name}, {"fields", fields}};
      if (f.signature) {
        line["signature"] = {{"link_id", f.signature->link_id}, {"timestamp", f.signature->timestamp}};
        if (key) line["signature"]["valid"] = Verify(key->bytes, f.raw);
      }
      std::cout << line.dump() << "\n";
    }
    const Parser::Counts& c = parser.counts();
    std::cerr << "uav-mavlink: " << c.frames << " frames, " << c.unknown_message << " of unknown messages, "
              << c.bad_checksum << " with a bad checksum, " << c.bad_flags << " with unknown flags, " << c.skipped_bytes
              << " bytes outside frames\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "uav-mavlink: " << e.what() << "\n";
    return 1;
  }
}
