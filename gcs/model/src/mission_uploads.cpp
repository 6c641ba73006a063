#include "uav/gcs/mission_uploads.hpp"

namespace uav::gcs {

bool MissionUploads::UploadSurvey(VehicleMission* v, const std::string& vehicle_id,
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
  const auto mission = planner_.MakeMission(&error);
  if (!mission) {
    error_ = error;
    return false;
  }
  v->upload.emplace(*mission, commands.NextSeq());
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

void MissionUploads::Tick(VehicleMission& v, const std::string& id, double now, MessageLog& log) {
  if (!v.upload) return;
  const auto before = v.upload->state();
  for (auto& c : v.upload->Tick(now)) outgoing_.push_back({id, std::move(c)});
  if (before != v.upload->state()) log.Add(now, id, "mission upload failed: " + v.upload->reason(), Severity::kError);
}

bool MissionUploads::ExportSurvey(const std::string& path, double now, MessageLog& log) {
  std::string message;
  const bool ok = planner_.Export(path, &message);
  log.Add(now, "", message, ok ? Severity::kInfo : Severity::kWarning);
  return ok;
}

bool MissionUploads::ImportSurvey(const std::string& path, const std::optional<GeodeticPoint>& home, double now,
                                  MessageLog& log) {
  std::string message;
  const bool ok = planner_.Import(path, &message);
  if (ok && home) planner_.SetOrigin(*home);  // keep the map on the selected vehicle's home
  log.Add(now, "", message, ok ? Severity::kInfo : Severity::kWarning);
  return ok;
}

}  // namespace uav::gcs
