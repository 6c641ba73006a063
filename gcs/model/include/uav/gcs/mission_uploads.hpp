#pragma once
// Mission planning and upload: the mission editor and the survey planner, the upload in progress
// to each vehicle and the mission each vehicle accepted (which the map draws).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "uav/gcs/commands.hpp"
#include "uav/gcs/message_log.hpp"
#include "uav/gcs/mission_editor.hpp"
#include "uav/gcs/survey_planner.hpp"
#include "uav/shared/program.hpp"
#include "uav/waypoints/mission_transfer.hpp"

namespace uav::gcs {

struct OutgoingMissionChunk {
  std::string vehicle_id;
  waypoints::MissionChunk chunk;
};

// A whole mission for a link that runs its own transfer protocol (MAVLink's mission service):
// it answers with MissionUploadAcks (progress, then accepted with the mission's digest, or
// rejected with the reason), as our vehicles do chunk by chunk.
struct OutgoingMission {
  std::string vehicle_id;
  int64_t upload_id = 0;
  waypoints::Mission mission;
};

// Per vehicle.
struct VehicleMission {
  std::optional<waypoints::MissionUploader> upload;  // in progress, or the last finished
  std::optional<waypoints::Mission> mission;         // the last one it accepted
  bool whole_sent = false;  // the upload in progress has been handed to a link that takes whole missions
};

class MissionUploads {
 public:
  // Map origin until a vehicle reports its home: the simulator's default home (NUS, Singapore).
  static constexpr GeodeticPoint kDefaultMapOrigin{1.2966, 103.7764, 15.0};
  MissionUploads() : planner_(ResourcePath("cameras"), kDefaultMapOrigin) {}

  // Uploads the editor's mission (the planner's survey when it has no items) to `v` (its home is
  // the mission's origin). Returns false and sets error() when there is no vehicle, no valid
  // mission, or an upload is already running.
  bool UploadMission(VehicleMission* v, const std::string& vehicle_id, const std::optional<GeodeticPoint>& home,
                    CommandCenter& commands, double now, MessageLog& log);
  // Only answers to this GCS (`gcs_name`) count.
  void OnMissionAck(VehicleMission& v, const std::string& vehicle_id, const waypoints::MissionUploadAck& ack,
                    double now, MessageLog& log);
  // `whole_missions`: the vehicle's link takes whole missions and runs its own transfer (MAVLink's
  // mission service), not our chunks.
  void Tick(VehicleMission& v, const std::string& vehicle_id, bool whole_missions, double now, MessageLog& log);
  std::vector<OutgoingMissionChunk> TakeOutgoing() { return std::exchange(outgoing_, {}); }
  std::vector<OutgoingMission> TakeOutgoingWhole() { return std::exchange(outgoing_whole_, {}); }
  // Vehicles whose link is asked for the mission they hold (into the editor when it arrives).
  void RequestDownload(const std::string& vehicle_id) { downloads_.push_back(vehicle_id); }
  std::vector<std::string> TakeDownloadRequests() { return std::exchange(downloads_, {}); }
  // The editor's file actions (.plan, or WPL by extension); the outcome is logged. Import keeps
  // the map on `home` if given, and changes nothing when the file cannot be loaded. What the
  // vehicle would refuse (waypoints::CheckMission against `limits`) is logged as warnings; the
  // mission is loaded all the same, for the operator to fix.
  bool ExportMission(const std::string& path, double now, MessageLog& log);
  bool ImportMission(const std::string& path, const std::optional<GeodeticPoint>& home,
                     const waypoints::VehicleLimits& limits, double now, MessageLog& log);

  // Loads a mission (downloaded from a vehicle) into the editor; logged and checked like an import.
  bool LoadMission(const waypoints::Mission& m, const std::string& origin, const std::optional<GeodeticPoint>& home,
                   const waypoints::VehicleLimits& limits, double now, MessageLog& log);
  MissionEditor& editor() { return editor_; }
  const MissionEditor& editor() const { return editor_; }
  SurveyPlanner& planner() { return planner_; }
  const SurveyPlanner& planner() const { return planner_; }
  const std::string& error() const { return error_; }

 private:
  SurveyPlanner planner_;
  MissionEditor editor_;
  std::string error_;
  std::vector<OutgoingMissionChunk> outgoing_;
  std::vector<OutgoingMission> outgoing_whole_;
  std::vector<std::string> downloads_;
};

}  // namespace uav::gcs
