#include "uav/gcs/mission_uploads.hpp"

#include "uav/waypoints/mission_file.hpp"

namespace uav::gcs {

bool MissionUploads::UploadMission(VehicleMission* v, const std::string& vehicle_id,
                                  const std::optional<GeodeticPoint>& home, CommandCenter& commands, double now,
                                  MessageLog& log) {
  error_.clear();
  if (!v) {
    error_ = "no vehicle selected";
    return false;
  }
  if (v->upload && v->upload->state() == waypoints::MissionUploader::State::kSending) {
    error_ = "an upload to " + vehicle_id + " is in progress";
    return false;
  }
  if (home) planner_.SetOrigin(*home);  // the vehicle's home is the mission's
  std::string error;
  const auto mission = editor_.MakeMission(planner_, planner_.origin(), &error);
  if (!mission) {
    error_ = error;
    return false;
  }
  v->upload.emplace(*mission, commands.NextSeq());
  v->whole_sent = false;
  log.Add(now, vehicle_id, "uploading mission of " + std::to_string(mission->items.size()) + " items", Severity::kInfo);
  return true;
}

void MissionUploads::OnMissionAck(VehicleMission& v, const std::string& vehicle_id,
                                  const waypoints::MissionUploadAck& ack, double now, MessageLog& log) {
  if (!v.upload) return;
  auto& up = *v.upload;
  const auto before = up.state();
  up.OnAck(ack, now);
  if (up.state() == before) return;
  using State = waypoints::MissionUploader::State;
  if (up.state() == State::kAccepted) {
    v.mission = up.mission();
    log.Add(now, vehicle_id, "mission of " + std::to_string(up.total_items()) + " items accepted", Severity::kInfo);
  } else {
    log.Add(now, vehicle_id,
            "mission upload " + std::string(up.state() == State::kRejected ? "rejected: " : "failed: ") + up.reason(),
            Severity::kWarning);
  }
}

void MissionUploads::Tick(VehicleMission& v, const std::string& id, bool whole_missions, double now, MessageLog& log) {
  if (!v.upload) return;
  if (whole_missions) {  // the link runs the transfer, its own resends and timeouts
    if (v.upload->state() == waypoints::MissionUploader::State::kSending && !v.whole_sent) {
      outgoing_whole_.push_back({id, v.upload->upload_id(), v.upload->mission()});
      v.whole_sent = true;
    }
    return;
  }
  const auto before = v.upload->state();
  for (auto& c : v.upload->Tick(now)) outgoing_.push_back({id, std::move(c)});
  if (before != v.upload->state()) log.Add(now, id, "mission upload failed: " + v.upload->reason(), Severity::kError);
}

bool MissionUploads::ExportMission(const std::string& path, double now, MessageLog& log) {
  std::string error;
  const auto mission = editor_.MakeMission(planner_, planner_.origin(), &error);
  if (!mission) {
    log.Add(now, "", "nothing exported: " + error, Severity::kWarning);
    return false;
  }
  try {
    waypoints::WriteMissionFile(path, *mission);
  } catch (const std::exception& e) {
    log.Add(now, "", e.what(), Severity::kWarning);
    return false;
  }
  log.Add(now, "", "exported " + std::to_string(mission->items.size()) + " items to " + path, Severity::kInfo);
  return true;
}

bool MissionUploads::ImportMission(const std::string& path, const std::optional<GeodeticPoint>& home,
                                   const waypoints::VehicleLimits& limits, double now, MessageLog& log) {
  waypoints::Mission m;
  try {
    m = waypoints::ReadMissionFile(path);
  } catch (const std::exception& e) {
    log.Add(now, "", e.what(), Severity::kWarning);
    return false;
  }
  return LoadMission(m, path, home, limits, now, log);
}

bool MissionUploads::LoadMission(const waypoints::Mission& m, const std::string& origin,
                                 const std::optional<GeodeticPoint>& home, const waypoints::VehicleLimits& limits,
                                 double now, MessageLog& log) {
  std::string error;
  if (!editor_.Load(m, &planner_, &error)) {
    log.Add(now, "", origin + ": " + error, Severity::kWarning);
    return false;
  }
  if (home) planner_.SetOrigin(*home);  // keep the map on the selected vehicle's home
  const std::size_t n = editor_.items().size();
  log.Add(now, "", "loaded " + (n ? std::to_string(n) + "-item mission" : std::string("survey")) + " (" +
                       std::to_string(m.items.size()) + " mission items) from " + origin,
          Severity::kInfo);
  // Checked as the vehicle will check it: loaded all the same, so the operator can fix it here.
  const auto problems = waypoints::CheckMission(m, limits);
  constexpr std::size_t kShown = 5;
  for (std::size_t k = 0; k < problems.size() && k < kShown; ++k)
    log.Add(now, "", origin + ": " + problems[k].text + " (the vehicle would refuse it)", Severity::kWarning);
  if (problems.size() > kShown)
    log.Add(now, "", origin + ": and " + std::to_string(problems.size() - kShown) + " more problems (see the Mission panel)",
            Severity::kWarning);
  return true;
}

}  // namespace uav::gcs
