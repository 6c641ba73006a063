// Inbound translators: commands, mission uploads, file requests and GCS heartbeats.
#include "link_translators.hpp"

#include <memory>

#include "uav/shared/time.hpp"
#include "uav/waypoints/mission_file.hpp"
#include "uav/waypoints/mission_messages.hpp"
#include "uavmsg/command_ack_t.hpp"
#include "uavmsg/command_t.hpp"
#include "uavmsg/file_request_t.hpp"
#include "uavmsg/heartbeat_t.hpp"
#include "uavmsg/manual_control_t.hpp"
#include "uavmsg/track_target_t.hpp"

namespace uav::runtime {

void SendAck(LinkContext& c, int64_t utime, const CommandAck& r, bool remember) {
  if (remember) c.intake.Remember(r);
  uavmsg::command_ack_t ack = ToMessage(r);
  ack.utime = utime;
  c.Publish(Topic::kCommandAck, ack);
}

void SubscribeCommands(LinkContext& c) {
  c.bus.Subscribe<uavmsg::command_t>(Channel(c.vehicle_id, Topic::kCommand),
                                     [&c](const std::string&, const uavmsg::command_t& m) {
                                       const SignatureVerdict v = c.signatures.Check(Topic::kCommand, m, m.source);
                                       if (v != SignatureVerdict::kAccepted) {
                                         // Told, never executed, and not remembered as the answer
                                         // to (source, seq): the real sender's request may follow.
                                         // A replay's sender is not the source it names: no answer.
                                         if (v == SignatureVerdict::kReplay) return;
                                         SendAck(c, c.now,
                                                 {m.source, m.command_seq, m.text.substr(0, 256),
                                                  CommandResult::kRejected, 0, c.signatures.Refusal(v, m)},
                                                 false);
                                         return;
                                       }
                                       auto r = c.intake.Receive(m.header.vehicle_id, m.source, m.command_seq, m.text);
                                       for (const auto& rep : r.replies) SendAck(c, c.now, rep);
                                       if (r.request) c.board.commands.Push(*r.request);
                                     });
}

void SubscribeMissionUploads(LinkContext& c) {
  // Uploads in progress, per GCS.
  auto uploads = std::make_shared<std::map<std::string, waypoints::MissionAssembler>>();
  c.bus.Subscribe<uavmsg::mission_upload_t>(
      Channel(c.vehicle_id, Topic::kMissionUpload), [&c, uploads](const std::string&, const uavmsg::mission_upload_t& m) {
        if (m.header.vehicle_id != c.vehicle_id || m.source.empty() || m.source.size() > 64) return;
        using Result = waypoints::MissionUploadAck::Result;
        waypoints::MissionUploadAck ack;
        const SignatureVerdict v = c.signatures.Check(Topic::kMissionUpload, m, m.source);
        if (v == SignatureVerdict::kReplay) return;
        if (v != SignatureVerdict::kAccepted) {
          ack.upload_id = m.upload_id;
          ack.result = Result::kRejected;
          ack.reason = c.signatures.Refusal(v, m);
        } else try {
          ack = (*uploads)[m.source].Receive(waypoints::FromMessage(m), [&c](const waypoints::Mission& mission) {
            std::string refused = c.missions.AcceptUpload(mission);
            // The mission the vehicle now holds, offered as a .plan: any GCS can download it
            // into its editor (QGroundControl's "download from vehicle").
            if (refused.empty())
              c.board.downloads.Push({"mission_" + std::to_string(c.missions.upload_count()) + ".plan",
                                      waypoints::FormatPlan(mission)});
            return refused;
          });
        } catch (const std::invalid_argument& e) {
          ack.upload_id = m.upload_id;
          ack.result = Result::kRejected;
          ack.reason = e.what();
        }
        if (ack.result != Result::kInProgress && ack.received_items == ack.total_items)
          c.board.PushStatus(ack.result == Result::kAccepted ? Severity::kInfo : Severity::kWarning,
                             ack.result == Result::kAccepted
                                 ? "mission of " + std::to_string(ack.total_items) + " items accepted from " + m.source
                                 : "mission upload rejected: " + ack.reason);
        else if (ack.result == Result::kRejected)
          c.board.PushStatus(Severity::kWarning, "mission upload rejected: " + ack.reason);
        uavmsg::mission_ack_t out = waypoints::ToMessage(ack);
        out.utime = c.now;
        out.source = m.source;
        c.Publish(Topic::kMissionAck, out);
      });
}

void SubscribeFileRequests(LinkContext& c, FileSender& files) {
  c.bus.Subscribe<uavmsg::file_request_t>(
      Channel(c.vehicle_id, Topic::kFileRequest), [&c, &files](const std::string&, const uavmsg::file_request_t& m) {
        if (m.header.vehicle_id != c.vehicle_id) return;
        if (c.signatures.Check(Topic::kFileRequest, m, m.source) != SignatureVerdict::kAccepted) return;
        FileRequest r;
        r.transfer_id = m.transfer_id;
        r.complete = m.complete;
        for (int i = 0; i < m.n_ranges && i < static_cast<int>(m.first.size()) && i < static_cast<int>(m.count.size()); ++i)
          r.ranges.push_back({m.first[i], m.count[i]});
        files.OnRequest(r);
      });
}

void SubscribeManualControl(LinkContext& c) {
  auto last_said = std::make_shared<int64_t>(-1'000'000'000);  // a refusal, said once a second at most
  c.bus.Subscribe<uavmsg::manual_control_t>(
      Channel(c.vehicle_id, Topic::kManualControl), [&c, last_said](const std::string&, const uavmsg::manual_control_t& m) {
        if (m.header.vehicle_id != c.vehicle_id) return;
        // Unsigned or a stranger's sticks are dropped, and said (they come at 20 Hz).
        const SignatureVerdict v = c.signatures.Check(Topic::kManualControl, m, m.source);
        if (v == SignatureVerdict::kReplay) return;
        auto refuse = [&c, &last_said](const std::string& why) {
          if (c.now - *last_said < 1'000'000) return;
          *last_said = c.now;
          c.board.PushStatus(Severity::kWarning, "sticks refused: " + why);
        };
        if (v != SignatureVerdict::kAccepted) return refuse(c.signatures.Refusal(v, m));
        try {
          ManualSticks s = FromMessage(m);
          s.utime = c.now;  // the vehicle's clock: how fresh they are is judged against it
          c.board.Update([&](BlackboardData& b) { b.sticks = s; });
        } catch (const std::invalid_argument& e) {
          refuse(e.what());
        }
      });
}

void SubscribeTrackTargets(LinkContext& c) {
  c.bus.Subscribe<uavmsg::track_target_t>(
      Channel(c.vehicle_id, Topic::kTrackTarget), [&c](const std::string&, const uavmsg::track_target_t& m) {
        auto reject = [&](const std::string& reason) {
          TrackStatus r;
          r.utime = m.frame_utime;
          r.target_seq = m.target_seq;
          r.camera = m.camera;
          r.state = TrackStatus::State::kRejected;
          r.reason = reason;
          c.board.track_reports.Push(r);
          c.board.PushStatus(Severity::kWarning, "target " + std::to_string(m.target_seq) + " rejected: " + reason);
        };
        if (m.header.vehicle_id != c.vehicle_id) {
          reject("the target is for vehicle '" + m.header.vehicle_id + "', this is '" + c.vehicle_id + "'");
          return;
        }
        const SignatureVerdict v = c.signatures.Check(Topic::kTrackTarget, m, m.source);
        if (v == SignatureVerdict::kReplay) return;
        if (v != SignatureVerdict::kAccepted) {
          reject(c.signatures.Refusal(v, m));
          return;
        }
        if (c.board.Snapshot().tracking_camera.empty()) {
          reject("this vehicle has no tracking camera");
          return;
        }
        try {
          c.board.track_requests.Push(FromMessage(m));
        } catch (const std::invalid_argument& e) {
          reject(e.what());
        }
      });
}

namespace {

class GcsHeartbeatTranslator : public Translator {
 public:
  explicit GcsHeartbeatTranslator(LinkContext& c) : c_(c) {
    c.bus.Subscribe<uavmsg::heartbeat_t>(Channel(c.vehicle_id, Topic::kGcsHeartbeat),
                                         [this](const std::string&, const uavmsg::heartbeat_t& m) {
                                           if (m.source_kind != uavmsg::heartbeat_t::SOURCE_GCS) return;
                                           // A stranger must not hold off the link-loss failsafe.
                                           if (c_.signatures.Check(Topic::kGcsHeartbeat, m, m.source_name) !=
                                               SignatureVerdict::kAccepted)
                                             return;
                                           if (!seen_.count(m.source_name))
                                             c_.board.PushStatus(Severity::kInfo, "GCS link up: " + m.source_name);
                                           seen_[m.source_name] = c_.now;
                                           last_wall_us_ = MonotonicMicros();
                                         });
  }
  void Tick(int64_t) override {
    // Wall clock: the link is lost in real seconds, whatever the simulation speed.
    const double age = last_wall_us_ < 0 ? -1.0 : (MonotonicMicros() - last_wall_us_) * 1e-6;
    c_.board.Update([&](BlackboardData& b) { b.gcs_link_age_s = age; });
  }

 private:
  LinkContext& c_;
  std::map<std::string, int64_t> seen_;  // GCS name -> vehicle utime of its last heartbeat
  int64_t last_wall_us_ = -1;            // monotonic wall clock of the last GCS heartbeat
};

}  // namespace

std::unique_ptr<Translator> MakeGcsHeartbeatTranslator(LinkContext& c) {
  return std::make_unique<GcsHeartbeatTranslator>(c);
}

}  // namespace uav::runtime
