#pragma once
// The CMM thread's translators, one per topic: each owns the conversion between one LCM type
// and the plain data of the blackboard, the command intake or the stores. Private to the link.
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "uav/app/blackboard.hpp"
#include "uav/app/command_intake.hpp"
#include "uav/app/link_worker.hpp"
#include "uav/app/mission_store.hpp"
#include "uav/shared/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/file_transfer.hpp"
#include "uavmsg/header_t.hpp"

namespace uav::app {

// What every translator shares: the bus, the vehicle's channels and their sequence numbers.
struct LinkContext {
  LinkContext(std::string id, const std::string& url, const LinkParams& p, Blackboard& b, MissionStore& m)
      : vehicle_id(std::move(id)), bus(url), params(p), board(b), missions(m), intake(vehicle_id) {}
  std::string vehicle_id;
  Bus bus;
  LinkParams params;
  Blackboard& board;
  MissionStore& missions;
  CommandIntake intake;  // shared by the command translator (requests) and the ack translator (answers)
  std::map<Topic, int64_t> seq;
  int64_t now = 0;  // [us] vehicle clock of the current tick

  template <class Msg>
  void Publish(Topic t, Msg& m) {
    m.header = uavmsg::header_t{vehicle_id, ++seq[t]};
    bus.Publish(Channel(vehicle_id, t), m);
  }
};

// Outbound translators run once per tick, in the order they were added.
class Translator {
 public:
  virtual ~Translator() = default;
  virtual void Tick(int64_t utime) = 0;
};

// Inbound: subscribe in their constructors, act when the bus is handled.
void SubscribeCommands(LinkContext& c);
void SubscribeMissionUploads(LinkContext& c);
void SubscribeFileRequests(LinkContext& c, FileSender& files);
// Targets for the tracker; a malformed one, or one for another vehicle, is answered as rejected.
void SubscribeTrackTargets(LinkContext& c);
// GCS heartbeats: posts the age of the newest to the blackboard every tick (link-loss input).
std::unique_ptr<Translator> MakeGcsHeartbeatTranslator(LinkContext& c);

// Answers a command (command_ack_t) and remembers the answer for repeats of it.
void SendAck(LinkContext& c, int64_t utime, const control::TaskReport& r);

// Outbound.
std::unique_ptr<Translator> MakeAckTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeStatusTextTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeStateTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeHeartbeatTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeVideoTranslator(LinkContext& c);
std::unique_ptr<Translator> MakePowerLinesTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeObstaclesTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeMonoDepthTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeActiveStereoTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeVisualOdometryTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeTrackStatusTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeMapTileTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeFileTransferTranslator(LinkContext& c, FileSender& files);

}  // namespace uav::app
