#pragma once
// The mission editor behind the Map panel's item list (QGroundControl's Plan view): items added,
// inserted, dragged and deleted on the map, each with its altitude, speed, hold time and action,
// and the survey planner's survey as one item among them. It builds the Mission to upload or
// export, and loads any mission (a .plan or WPL file, or the one the vehicle holds) back into
// items. No ImGui here.
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::gcs {

class SurveyPlanner;

enum class PlanAction { kWaypoint, kLoiter, kPhoto, kLand, kReturn, kSurvey, kCameraStart, kCameraStop };
const char* Name(PlanAction a);  // "waypoint", "loiter", ...

struct PlanItem {
  PlanAction action = PlanAction::kWaypoint;
  // Where: waypoint, loiter and land (the others happen where the vehicle is).
  double latitude_deg = 0, longitude_deg = 0;
  double altitude_m = 10;     // [m] above home (waypoint, loiter)
  double speed_m_s = 0;       // [m/s] from this item on; 0: unchanged (the survey: its own)
  double hold_s = 0;          // [s] waypoint: stay at the point; loiter: its time
  double yaw_deg = std::numeric_limits<double>::quiet_NaN();  // [deg] waypoint heading; NaN keeps it (param4)
  double camera_interval_s = 0, camera_distance_m = 0;  // camera start: by time or by distance
  bool HasPosition() const;
};

// A geofence zone being drawn: a polygon's vertices, or a circle's centre (vertices[0]) and radius.
struct FenceDraft {
  bool inclusion = true;
  bool circle = false;
  std::vector<GeodeticPoint> vertices;  // latitude/longitude (altitude unused)
  double radius_m = 20;                 // [m] a circle's
};

// What a mission item is in the editor: the take-off (or the cruise speed), row `index` of
// items(), fence zone `index` of fences, rally point `index` of rally.
struct ItemOrigin {
  enum class Kind { kTakeoff, kRow, kFence, kRally };
  Kind kind = Kind::kTakeoff;
  std::size_t index = 0;
};

// The editor's mission checked as the vehicle will check it (waypoints::CheckMission against the
// vehicle's limits), each problem placed on what the editor shows.
struct EditorCheck {
  std::optional<waypoints::Mission> mission;  // nullopt: it cannot be built; `error` says why
  std::string error;
  std::vector<ItemOrigin> origins;  // per mission item
  std::vector<waypoints::MissionProblem> problems;
  std::vector<std::string> row_problems;  // per row of items(): the first problem, "" none
  // The row that mission item `item` came from, -1 when it is not a row's (the take-off, a zone).
  int RowOf(int item) const;
};

// What a click on the map adds while the mission is edited.
enum class MapTool { kWaypoint, kFenceVertex, kRallyPoint };

class MissionEditor {
 public:
  MissionEditor();

  // ---- Editing. Indices out of range are ignored.
  const std::vector<PlanItem>& items() const { return items_; }
  PlanItem& item(std::size_t i) { return items_.at(i); }
  void Insert(std::size_t before, const PlanItem& item);  // before == size(): append
  void MoveTo(std::size_t i, const GeodeticPoint& g);     // drags a position item
  void Delete(std::size_t i);
  void Clear();
  // The index of the position item within radius_m of `ne` (map metres through `planner`), or -1.
  int ItemNear(const SurveyPlanner& planner, const Eigen::Vector2d& ne, double radius_m) const;
  // ---- Geofence and rally points, uploaded with the mission (the .plan's geoFence and
  // rallyPoints). A click adds a vertex to fences[fence_selected] (a circle: moves its centre).
  std::vector<FenceDraft> fences;
  std::vector<GeodeticPoint> rally;  // altitude_m: above home
  int fence_selected = -1;
  MapTool tool = MapTool::kWaypoint;
  void AddFenceVertex(const GeodeticPoint& g);  // to fences[fence_selected]
  // Zone z as the vehicle names it ("keep-out polygon 1": the first keep-out polygon).
  std::string ZoneLabel(std::size_t z) const;
  // Deletes the fence vertex or rally point within radius_m of `ne`; false when there is none.
  bool DeleteFenceNear(const SurveyPlanner& planner, const Eigen::Vector2d& ne, double radius_m);

  int selected = -1;             // the item the list and the map highlight
  double takeoff_alt_m = 10.0;   // [m] above home: the mission starts with a take-off to it
  double cruise_speed_m_s = 3.0; // [m/s] until an item sets its own

  // The mission to upload or export, home at `home`: a take-off, then the items in order (a speed
  // change before an item that sets one; the survey item expands into the planner's survey).
  // With no items it is the planner's survey mission (take off, survey, return). The geofence
  // and rally points follow as MAVLink fence and rally items (polygons, circles, rally). nullopt
  // and *error naming the item when it cannot be built (a survey item without a flyable survey,
  // a fence polygon of fewer than 3 vertices or crossing itself).
  std::optional<waypoints::Mission> MakeMission(const SurveyPlanner& planner, const GeodeticPoint& home,
                                                std::string* error, std::vector<ItemOrigin>* origins = nullptr) const;
  // The mission made and checked against `limits`: what the editor warns of while editing.
  EditorCheck Check(const SurveyPlanner& planner, const GeodeticPoint& home, const waypoints::VehicleLimits& limits) const;
  // Loads a mission into items (a survey into `planner`). All or nothing: false and *error
  // naming the item when it holds what this editor cannot show (an unsupported command, a
  // second survey, a take-off after the first item); nothing changes then.
  bool Load(const waypoints::Mission& m, SurveyPlanner* planner, std::string* error);

 private:
  std::vector<PlanItem> items_;
};

}  // namespace uav::gcs
