#pragma once
// The CMM thread's translators, one per topic: each owns the conversion between one LCM type
// and the plain data of the blackboard, the command intake or the stores. Private to the link.
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uav/wire/messages.hpp"
#include "uav/runtime/blackboard.hpp"
#include "uav/runtime/command_intake.hpp"
#include "uav/runtime/link_worker.hpp"
#include "uav/runtime/mission_store.hpp"
#include "uav/wire/bus.hpp"
#include "uav/shared/channels.hpp"
#include "uav/shared/file_transfer.hpp"
#include "uav/wire/signed_message.hpp"
#include "uav/shared/time.hpp"
#include "uavmsg/header_t.hpp"

namespace uav::runtime {

// "signature check: bad tag: ..." naming both key ids when they differ (`sender_key_id` is what
// the message names; empty for an unsigned sender).
std::string SignatureRefusal(SignatureVerdict v, const std::string& sender_key_id = "", const std::string& own_key_id = "");

// The signature check of every inbound message that changes what the vehicle does: counts and
// reports refusals by reason (at most one status text a second per reason, with the count), and
// keeps the newest accepted timestamp in a file for the next start.
class SignatureGate {
 public:
  SignatureGate(const LinkParams& p, const std::string& vehicle_id, Blackboard& board);
  ~SignatureGate();  // saves the newest timestamp
  SignatureGate(const SignatureGate&) = delete;
  SignatureGate& operator=(const SignatureGate&) = delete;
  bool enabled() const { return verifier_.has_value(); }
  int64_t rejections() const { return rejections_; }
  // The verdict on `m` from `source` on `topic`; refusals are counted and reported.
  template <class Msg>
  SignatureVerdict Check(Topic topic, const Msg& m, const std::string& source) {
    if (!verifier_) return SignatureVerdict::kAccepted;
    const SignatureVerdict v = VerifyMessage(*verifier_, m, source, SigningTimestamp(WallTimeMicros()));
    if (v != SignatureVerdict::kAccepted) Refused(v, topic, source, Refusal(v, m));
    return v;
  }
  // Why `m` was refused, as the sender is told: for a bad tag, whether the keys differ (and
  // which key id each side holds) or the message was altered.
  template <class Msg>
  std::string Refusal(SignatureVerdict v, const Msg& m) const {
    return SignatureRefusal(v, m.signature.key_id, key_id_);
  }
  // Reports refusals not yet reported, and saves the newest timestamp; once a tick.
  void Tick();

 private:
  void Refused(SignatureVerdict v, Topic topic, const std::string& source, const std::string& why);
  void Save();
  std::optional<SignatureVerifier> verifier_;
  std::string key_id_;  // this vehicle's key (SigningKey::Id())
  std::string state_file_;
  Blackboard& board_;
  int64_t rejections_ = 0;
  struct Pending {
    int64_t count = 0;
    int64_t last_report_us = -1;  // wall clock
    std::string last;             // what the latest refused message was
    std::string why;              // and why it was refused
  };
  std::map<SignatureVerdict, Pending> pending_;
  int64_t saved_ = -1;        // newest timestamp in the state file
  int64_t last_save_us_ = 0;  // monotonic clock
  bool save_failed_ = false;
};

// Reason text for a refusal, as acknowledgements and status texts say it.

// What every translator shares: the bus, the vehicle's channels and their sequence numbers.
struct LinkContext {
  LinkContext(std::string id, Bus& shared_bus, const LinkParams& p, Blackboard& b, MissionStore& m)
      : vehicle_id(std::move(id)), bus(shared_bus), params(p), board(b), missions(m), intake(vehicle_id),
        signatures(p, vehicle_id, b) {}
  std::string vehicle_id;
  Bus& bus;
  LinkParams params;
  Blackboard& board;
  MissionStore& missions;
  CommandIntake intake;  // shared by the command translator (requests) and the ack translator (answers)
  SignatureGate signatures;
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
// The operator's sticks (manual_control_t), signed, into the blackboard for the `sticks` task.
void SubscribeManualControl(LinkContext& c);
// GCS heartbeats: posts the age of the newest to the blackboard every tick (link-loss input).
std::unique_ptr<Translator> MakeGcsHeartbeatTranslator(LinkContext& c);

// Answers a command (command_ack_t) and, unless told not to, remembers the answer for repeats
// of it.
void SendAck(LinkContext& c, int64_t utime, const CommandAck& r, bool remember = true);

// Outbound.
std::unique_ptr<Translator> MakeAckTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeStatusTextTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeStateTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeHeartbeatTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeVideoTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeTrackStatusTranslator(LinkContext& c);
// One per type of VehicleReports.
std::vector<std::unique_ptr<Translator>> MakeReportTranslators(LinkContext& c);
std::unique_ptr<Translator> MakeMapTileTranslator(LinkContext& c);
std::unique_ptr<Translator> MakeFileTransferTranslator(LinkContext& c, FileSender& files);

}  // namespace uav::runtime
