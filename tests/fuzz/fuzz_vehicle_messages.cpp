// Every LCM message the vehicle decodes (GCS -> vehicle), as the link does it: the datagram
// decoded once (DecodeDatagram), the signature checked (the signing check, with a fixed key),
// then the plain-data conversion and the consumer: the command intake, the mission assembler,
// the tracker's target check, the file sender. The first byte chooses the topic.
#include <stdexcept>

#include "fuzz_input.hpp"
#include "uav/wire/messages.hpp"
#include "uav/runtime/command_intake.hpp"
#include "uav/wire/bus.hpp"
#include "uav/shared/file_transfer.hpp"
#include "uav/wire/signed_message.hpp"
#include "uav/shared/tracking.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uav/waypoints/mission_transfer.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/mission_upload_t.hpp"
#include "uavmsg/track_target_t.hpp"

namespace {

uav::SigningKey FuzzKey() {
  uav::SigningKey k;
  k.bytes.fill(0x42);  // the seeds (make_fuzz_seeds) are signed with it, so the fuzzer starts past the tag
  return k;
}

template <class Msg>
bool Admit(const Msg& m, const std::string& source) {
  static uav::SignatureVerifier verifier(FuzzKey(), "UAV1", 0);
  return uav::VerifyMessage(verifier, m, source, uav::kSigningTimestampMax) == uav::SignatureVerdict::kAccepted;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t* p = data + 1;
  const size_t n = size - 1;
  switch (data[0] % 5) {
    case 0: {
      uavmsg::command_t m;
      if (!uav::DecodeDatagram(p, n, &m)) return 0;
      Admit(m, m.source);
      uav::runtime::CommandIntake intake("UAV1");
      (void)intake.Receive(m.header.vehicle_id, m.source, m.command_seq, m.text);
      break;
    }
    case 1: {
      uavmsg::mission_upload_t m;
      if (!uav::DecodeDatagram(p, n, &m)) return 0;
      Admit(m, m.source);
      uav::waypoints::MissionAssembler assembler;
      try {
        assembler.Receive(uav::waypoints::FromMessage(m), [](const uav::waypoints::Mission&) { return std::string(); });
      } catch (const std::invalid_argument&) {
      }
      break;
    }
    case 2: {
      uavmsg::file_request_t m;
      if (!uav::DecodeDatagram(p, n, &m)) return 0;
      Admit(m, m.source);
      uav::FileSender sender;
      const uav::FileOffer offer = sender.Offer("map_1.tif", std::string(3000, 'x'));
      uav::FileRequest r;
      r.transfer_id = m.transfer_id == 0 ? offer.transfer_id : m.transfer_id;
      r.complete = m.complete;
      for (int i = 0; i < m.n_ranges && i < static_cast<int>(m.first.size()) && i < static_cast<int>(m.count.size()); ++i)
        r.ranges.push_back({m.first[i], m.count[i]});
      sender.OnRequest(r);
      (void)sender.Poll(1.0);
      break;
    }
    case 3: {
      uavmsg::track_target_t m;
      if (!uav::DecodeDatagram(p, n, &m)) return 0;
      Admit(m, m.source);
      try {
        uav::FromMessage(m);
      } catch (const std::invalid_argument&) {
      }
      break;
    }
    case 4: {
      uavmsg::heartbeat_t m;
      if (!uav::DecodeDatagram(p, n, &m)) return 0;
      Admit(m, m.source_name);
      break;
    }
  }
  return 0;
}
