#pragma once
// A mission as operators exchange them: MAVLink mission items (the model behind QGroundControl
// .plan files and QGC WPL text files), the survey that generated some of them, and the flyable
// program the vehicle compiles them into.
#include <array>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
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

// What a vehicle's parameters allow a mission, checked where it is made (the editor, an import)
// and where it arrives (the vehicle refuses it at upload), as PX4 checks GF_MAX_HOR_DIST,
// GF_MAX_VER_DIST and the geofence before it accepts a mission.
struct VehicleLimits {
  double max_speed_m_s = 3.0;  // ctl_speed_max_xy; a tail-sitter: its wing-borne cruise if higher
  double ceiling_m = 120.0;    // fs_fence_alt: altitude above home
  double range_m = 500.0;      // fs_fence_radius: horizontal distance from home
  // From a vehicle's parameters by name; `value` returns NaN for one it lacks (its schema default
  // is taken then).
  static VehicleLimits Of(const std::function<double(const std::string&)>& value);
};

// One thing the vehicle would refuse. `item` indexes Mission::items (kCruise: the cruise speed);
// `text` names the item as the editor does and gives both numbers ("item 4 (NAV_WAYPOINT): 130 m
// above home, above the vehicle's 100 m ceiling (fs_fence_alt)").
struct MissionProblem {
  static constexpr std::size_t kCruise = static_cast<std::size_t>(-1);
  std::size_t item = kCruise;
  std::string text;
};

// Every problem of a validated mission against `limits`, in item order: a speed above the
// vehicle's; a point (waypoint, loiter, take-off, land, rally) above the ceiling, beyond the range
// or breaching the mission's own geofence (inside a keep-out zone, outside every keep-in zone); a
// straight leg between points that crosses a keep-out zone or leaves the keep-in zones.
std::vector<MissionProblem> CheckMission(const Mission& m, const VehicleLimits& limits);
// The problems as one refusal: the first, and how many more.
std::string DescribeProblems(const std::vector<MissionProblem>& problems);

// "item 4 (NAV_WAYPOINT)"; a fence or rally item by the zone or point it belongs to, as the
// mission editor shows it ("keep-out polygon 1 (item 9)", "rally point 2 (item 14)").
std::string ItemLabel(const Mission& m, std::size_t i);

// Compiles a validated mission into steps in the NED frame at `home`. Throws
// std::invalid_argument naming the first item the vehicle cannot fly (an unsupported command, or
// the first CheckMission problem).
std::vector<MissionStep> CompileMission(const Mission& m, const LocalNedFrame& home, const VehicleLimits& limits);

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
