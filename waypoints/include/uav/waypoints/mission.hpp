#pragma once
// A mission as operators exchange them: MAVLink mission items (the model behind QGroundControl
// .plan files and QGC WPL text files), the survey that generated some of them, and the flyable
// program the vehicle compiles them into.
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/survey.hpp"

namespace uav::waypoints {

// MAVLink MAV_CMD values we read, write and fly.
namespace mav_cmd {
constexpr int kNavWaypoint = 16;      // param1: hold time at the point [s]
constexpr int kNavLoiterTime = 19;    // param1: time to hold [s]; latitude/longitude 0: here
constexpr int kNavReturnToLaunch = 20;
constexpr int kNavLand = 21;
constexpr int kNavTakeoff = 22;
constexpr int kDoChangeSpeed = 178;
constexpr int kDoSetCamTriggDist = 206;
constexpr int kImageStartCapture = 2000;  // param2: interval [s]; param3: images (1: one photo)
constexpr int kImageStopCapture = 2001;
// The geofence and rally points travel as MAVLink's fence and rally items after the mission's
// own (QGroundControl's .plan keeps them apart, in geoFence and rallyPoints).
constexpr int kNavFencePolygonVertexInclusion = 5001;  // param1: the polygon's vertex count
constexpr int kNavFencePolygonVertexExclusion = 5002;
constexpr int kNavFenceCircleInclusion = 5003;         // param1: radius [m]
constexpr int kNavFenceCircleExclusion = 5004;
constexpr int kNavRallyPoint = 5100;
}  // namespace mav_cmd
bool IsFenceItem(int command);  // 5001-5004
bool IsRallyItem(int command);  // 5100
// MAVLink MAV_FRAME values accepted in files.
namespace mav_frame {
constexpr int kGlobal = 0;               // altitude above mean sea level (we use the ellipsoid)
constexpr int kMission = 2;              // not a position: the item's params only
constexpr int kGlobalRelativeAlt = 3;    // altitude above home
}  // namespace mav_frame

// Most items a mission may have: a 1 km^2 survey at 2 cm/px with a 640x480 camera needs ~1200.
constexpr std::size_t kMaxMissionItems = 5000;

struct MissionItem {
  int command = mav_cmd::kNavWaypoint;
  int frame = mav_frame::kGlobalRelativeAlt;
  std::array<double, 4> param{0, 0, 0, 0};  // NaN: unused (QGC writes null)
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;  // params 5-7
  bool autocontinue = true;
  bool operator==(const MissionItem& o) const;
};

// The survey a run of items came from, kept so a .plan file round-trips as a survey.
struct SurveyDefinition {
  std::vector<GeodeticPoint> polygon;  // latitude/longitude; altitude unused
  SurveyParams params;
  std::string camera_name = "Custom Camera";
  std::size_t first_item = 0;  // the survey's items are items[first_item, first_item + item_count)
  std::size_t item_count = 0;
};

struct Mission {
  GeodeticPoint home;             // planned home; frame-3 altitudes are above it
  double cruise_speed_m_s = 3.0;  // used until a DO_CHANGE_SPEED item
  std::vector<MissionItem> items;
  std::vector<SurveyDefinition> surveys;  // in item order, their item ranges disjoint
};

// Is `it` a single photo (IMAGE_START_CAPTURE of one image, QGroundControl's "Take photo")?
bool IsSinglePhoto(const MissionItem& it);

const char* CommandName(int command);  // "NAV_WAYPOINT", or "" when unknown

// Throws std::invalid_argument naming the item and field: no items or more than
// kMaxMissionItems, invalid home, a frame other than 0/2/3, a position item whose latitude,
// longitude or altitude is not finite or out of range (altitude above home in [0, 120] m), a
// non-finite speed or trigger parameter, or a survey whose item range or polygon is invalid.
void ValidateMission(const Mission& m);
// The per-item part of ValidateMission; `where` starts the message ("item 3 (NAV_WAYPOINT)",
// "mission.items[3]", "line 5").
void ValidateMissionItem(const MissionItem& it, const GeodeticPoint& home, const std::string& where);

// Survey mission as flown: take off to the survey altitude, set the speed, fly the survey with
// the camera started/stopped on each capture leg (by rate, or by distance), return home.
Mission MissionFromSurvey(const std::vector<GeodeticPoint>& area, const GeodeticPoint& home,
                          const SurveyParams& p, const SurveyPlan& plan);

// One step of a mission, in the vehicle's local NED frame.
struct MissionStep {
  enum class Kind { kTakeoff, kWaypoint, kSetSpeed, kCaptureStart, kCaptureStop, kReturnHome, kLand, kHold };
  Kind kind;
  Eigen::Vector3d p_N = Eigen::Vector3d::Zero();  // kWaypoint; kTakeoff/kLand use x, y (NaN: here)
  double altitude_m = 0;                          // kTakeoff: above home
  double yaw_rad = 0;                             // kWaypoint: NaN keeps the heading
  double value = 0;   // kSetSpeed: m/s; kCaptureStart: interval s (> 0) or -distance m (< 0);
                      // kHold: seconds to stay at the last point
  std::size_t item = 0;  // index of the mission item it came from, for progress reports
};

// Compiles a validated mission into steps in the NED frame at `home`. Throws
// std::invalid_argument naming the first item the vehicle cannot fly (an unsupported command, a
// speed above max_speed_m_s).
std::vector<MissionStep> CompileMission(const Mission& m, const LocalNedFrame& home,
                                        double max_speed_m_s);

// Camera state before steps[i]: interval s (> 0), -distance m (< 0), or nullopt (off).
std::optional<double> CaptureBefore(const std::vector<MissionStep>& steps, std::size_t i);

// The steps that fly a compiled mission on from steps[from] (the step being flown when it
// stopped), as QGroundControl's "resume mission": the speed and camera settings in force there,
// then the rest. A stop inside a capture leg goes back to the leg's first point, so the leg is
// photographed whole and no covered leg is flown again. A vehicle on the ground first takes
// off to the mission's take-off altitude (or the resumed point's). Throws std::invalid_argument
// when `from` is past the last step.
struct ResumedMission {
  std::vector<MissionStep> steps;
  std::size_t first = 0;   // the mission's step that steps[prefix] is (the leg's start or `from`) ...
  std::size_t prefix = 0;  // ... after this many steps that re-establish the state
};
ResumedMission ResumeSteps(const std::vector<MissionStep>& steps, std::size_t from, bool airborne);

}  // namespace uav::waypoints
