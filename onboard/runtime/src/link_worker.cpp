#include "uav/runtime/link_worker.hpp"

#include "link_translators.hpp"

namespace uav::runtime {
namespace {
// Messages the event log's subscription holds between two CMM ticks (LCM's default is 30: a map
// download's chunk burst overflowed it and the log lost telemetry).
constexpr int kEventLogQueue = 5000;
}  // namespace

LinkParams LinkParams::FromParameters(const ParameterSet& p, AttitudeMode attitude_mode) {
  LinkParams l;
  l.heartbeat_period_s = p.Get("link_heartbeat_period");
  l.tile_period_s = p.Get("link_tile_period");
  l.attitude_mode = attitude_mode;
  return l;
}

struct LinkWorker::Impl {
  Impl(const std::string& id, std::unique_ptr<Bus> own, Bus& bus, const LinkParams& p, Blackboard& b, MissionStore& m)
      : owned_bus(std::move(own)), context(id, bus, p, b, m) {}
  std::unique_ptr<Bus> owned_bus;  // null when the bus is the caller's
  LinkContext context;
  FileSender files;  // finished maps, offered until a GCS has them
  std::unique_ptr<EventLog> events;
  std::vector<std::unique_ptr<Translator>> translators;  // run in this order every tick
  std::unique_ptr<MavlinkEndpoint> mavlink;             // after them: it reads what they published
};

LinkWorker::LinkWorker(const std::string& vehicle_id, const std::string& lcm_url, const LinkParams& params,
                       Blackboard& board, MissionStore& missions, std::unique_ptr<EventLog> events) {
  auto bus = std::make_unique<Bus>(lcm_url);
  Bus& b = *bus;
  impl_ = std::make_unique<Impl>(vehicle_id, std::move(bus), b, params, board, missions);
  Start(std::move(events));
}

LinkWorker::LinkWorker(const std::string& vehicle_id, Bus& bus, const LinkParams& params, Blackboard& board,
                       MissionStore& missions, std::unique_ptr<EventLog> events)
    : impl_(std::make_unique<Impl>(vehicle_id, nullptr, bus, params, board, missions)) {
  Start(std::move(events));
}

void LinkWorker::Start(std::unique_ptr<EventLog> events) {
  Impl& im = *impl_;
  LinkContext& c = im.context;
  im.events = std::move(events);
  if (EventLog* log = im.events.get()) {
    // The whole bus, bursts included: a queue of kEventLogQueue messages between two ticks.
    c.bus.SubscribeRaw(
        ".*",
        [log](const std::string& channel, const lcm::ReceiveBuffer& rbuf) {
          log->Write(channel, rbuf.data, static_cast<int>(rbuf.data_size), rbuf.recv_utime);
        },
        kEventLogQueue);
  }
  SubscribeMissionUploads(c);
  SubscribeCommands(c);
  SubscribeFileRequests(c, im.files);
  SubscribeTrackTargets(c);
  SubscribeManualControl(c);
  im.translators.push_back(MakeGcsHeartbeatTranslator(c));
  im.translators.push_back(MakeAckTranslator(c));
  im.translators.push_back(MakeStatusTextTranslator(c));
  im.translators.push_back(MakeStateTranslator(c));
  im.translators.push_back(MakeHeartbeatTranslator(c));
  im.translators.push_back(MakeVideoTranslator(c));
  for (auto& t : MakeReportTranslators(c)) im.translators.push_back(std::move(t));
  im.translators.push_back(MakeTrackStatusTranslator(c));
  im.translators.push_back(MakeMapTileTranslator(c));
  im.translators.push_back(MakeFileTransferTranslator(c, im.files));
  if (c.params.mavlink)
    im.mavlink = std::make_unique<MavlinkEndpoint>(c.vehicle_id, c.bus, *c.params.mavlink, c.params.signing_key,
                                                   [&board = c.board](Severity s, const std::string& text) {
                                                     board.PushStatus(s, text);
                                                   });
}

LinkWorker::~LinkWorker() = default;

void LinkWorker::Tick(int64_t utime) {
  Impl& im = *impl_;
  im.context.now = utime;
  im.context.bus.Handle(0);  // commands, uploads, requests and GCS heartbeats since the last tick
  im.context.signatures.Tick();
  for (auto& t : im.translators) t->Tick(utime);
  if (im.mavlink) im.mavlink->Tick(utime);
  if (im.events) im.events->Flush();
}

}  // namespace uav::runtime
