#include "uav/waypoints/mission.hpp"

#include "uav/waypoints/geofence.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace uav::waypoints {
namespace {

bool SameNumber(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

bool HasPosition(const MissionItem& it) {
  return it.command == mav_cmd::kNavWaypoint || it.command == mav_cmd::kNavTakeoff ||
         it.command == mav_cmd::kNavLand || it.command == mav_cmd::kNavLoiterTime || IsFenceItem(it.command) ||
         IsRallyItem(it.command);
}

// A single photo is taken by the camera on at one frame a second while the vehicle holds still
// for half a second: exactly one frame is due in that time.
constexpr double kPhotoInterval_s = 1.0, kPhotoHold_s = 0.5;

[[noreturn]] void Fail(const std::string& where, const std::string& what) {
  throw std::invalid_argument(where + ": " + what);
}

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

}  // namespace

bool MissionItem::operator==(const MissionItem& o) const {
  for (int i = 0; i < 4; ++i)
    if (!SameNumber(param[i], o.param[i])) return false;
  return command == o.command && frame == o.frame && SameNumber(latitude_deg, o.latitude_deg) &&
         SameNumber(longitude_deg, o.longitude_deg) && SameNumber(altitude_m, o.altitude_m) &&
         autocontinue == o.autocontinue;
}

const char* CommandName(int command) {
  switch (command) {
    case mav_cmd::kNavWaypoint: return "NAV_WAYPOINT";
    case mav_cmd::kNavLoiterTime: return "NAV_LOITER_TIME";
    case mav_cmd::kNavReturnToLaunch: return "NAV_RETURN_TO_LAUNCH";
    case mav_cmd::kNavLand: return "NAV_LAND";
    case mav_cmd::kNavTakeoff: return "NAV_TAKEOFF";
    case mav_cmd::kDoChangeSpeed: return "DO_CHANGE_SPEED";
    case mav_cmd::kDoSetCamTriggDist: return "DO_SET_CAM_TRIGG_DIST";
    case mav_cmd::kImageStartCapture: return "IMAGE_START_CAPTURE";
    case mav_cmd::kImageStopCapture: return "IMAGE_STOP_CAPTURE";
    case mav_cmd::kNavFencePolygonVertexInclusion: return "NAV_FENCE_POLYGON_VERTEX_INCLUSION";
    case mav_cmd::kNavFencePolygonVertexExclusion: return "NAV_FENCE_POLYGON_VERTEX_EXCLUSION";
    case mav_cmd::kNavFenceCircleInclusion: return "NAV_FENCE_CIRCLE_INCLUSION";
    case mav_cmd::kNavFenceCircleExclusion: return "NAV_FENCE_CIRCLE_EXCLUSION";
    case mav_cmd::kNavRallyPoint: return "NAV_RALLY_POINT";
    default: return "";
  }
}

void ValidateMissionItem(const MissionItem& it, const GeodeticPoint& home, const std::string& where) {
    if (it.command < 0 || it.command > 65535) Fail(where, "command number is outside [0, 65535]");
    if (it.frame != mav_frame::kGlobal && it.frame != mav_frame::kMission &&
        it.frame != mav_frame::kGlobalRelativeAlt)
      Fail(where, "frame " + std::to_string(it.frame) +
                      " is not supported (0 global, 2 mission, 3 global relative altitude)");
    for (int k = 0; k < 4; ++k)
      if (std::isinf(it.param[k])) Fail(where, "param" + std::to_string(k + 1) + " is infinite");
    if (it.command == mav_cmd::kDoChangeSpeed && (!std::isfinite(it.param[1]) || it.param[1] <= 0 || it.param[1] > 15))
      Fail(where, "param2 (speed) = " + Num(it.param[1]) + " m/s is outside (0, 15]");
    if (it.command == mav_cmd::kDoSetCamTriggDist && (!std::isfinite(it.param[0]) || it.param[0] < 0 || it.param[0] > 1000))
      Fail(where, "param1 (trigger distance) = " + Num(it.param[0]) + " m is outside [0, 1000]");
    if (it.command == mav_cmd::kImageStartCapture && (!std::isfinite(it.param[1]) || it.param[1] < 0 || it.param[1] > 3600))
      Fail(where, "param2 (interval) = " + Num(it.param[1]) + " s is outside [0, 3600]");
    // Hold times: NaN is "none" (QGroundControl writes null for unused parameters).
    if ((it.command == mav_cmd::kNavWaypoint || it.command == mav_cmd::kNavLoiterTime) && !std::isnan(it.param[0]) &&
        (it.param[0] < 0 || it.param[0] > 3600))
      Fail(where, "param1 (hold time) = " + Num(it.param[0]) + " s is outside [0, 3600]");
    if (!HasPosition(it)) return;
    if (it.frame == mav_frame::kMission) Fail(where, "a position item needs frame 0 or 3, not 2");
    if (!std::isfinite(it.latitude_deg) || std::abs(it.latitude_deg) > 90)
      Fail(where, "latitude = " + Num(it.latitude_deg) + " is outside [-90, 90]");
    if (!std::isfinite(it.longitude_deg) || std::abs(it.longitude_deg) > 180)
      Fail(where, "longitude = " + Num(it.longitude_deg) + " is outside [-180, 180]");
    if (!std::isfinite(it.altitude_m)) Fail(where, "altitude is not a finite number");
    if (it.command != mav_cmd::kNavLand && !IsFenceItem(it.command)) {
      const double above_home = it.frame == mav_frame::kGlobal ? it.altitude_m - home.altitude_m : it.altitude_m;
      if (above_home < 0 || above_home > kMaxSurveyAltitude_m)
        Fail(where, "altitude = " + Num(it.altitude_m) + " m is " + Num(above_home) +
                        " m above home, outside [0, 120]");
    }
}

void ValidateMission(const Mission& m) {
  try {
    ValidateGeodetic(m.home);
  } catch (const std::invalid_argument& e) {
    Fail("home", e.what());
  }
  if (!std::isfinite(m.cruise_speed_m_s) || m.cruise_speed_m_s <= 0 || m.cruise_speed_m_s > 15)
    Fail("cruise speed", Num(m.cruise_speed_m_s) + " m/s is outside (0, 15]");
  if (m.items.empty()) Fail("mission", "has no items");
  if (m.items.size() > kMaxMissionItems)
    Fail("mission", "has " + std::to_string(m.items.size()) + " items, more than " +
                        std::to_string(kMaxMissionItems));
  for (std::size_t i = 0; i < m.items.size(); ++i) ValidateMissionItem(m.items[i], m.home, ItemLabel(m, i));
  try {
    CompileGeofence(m, LocalNedFrame(m.home));
  } catch (const std::invalid_argument& e) {
    Fail("geofence", e.what());
  }
  std::size_t free_from = 0;  // surveys in item order, not overlapping
  for (const SurveyDefinition& s : m.surveys) {
    if (s.item_count == 0 || s.first_item < free_from || s.first_item + s.item_count > m.items.size())
      Fail("survey", "its items [" + std::to_string(s.first_item) + ", " +
                         std::to_string(s.first_item + s.item_count) + ") are not within the mission's " +
                         std::to_string(m.items.size()) + " items after the previous survey's");
    free_from = s.first_item + s.item_count;
    try {
      LocalNedFrame frame(m.home);
      ValidatePolygon(PolygonToNed(s.polygon, frame));
      ValidateSurveyParams(s.params);
    } catch (const std::invalid_argument& e) {
      Fail("survey", e.what());
    }
  }
}

Mission MissionFromSurvey(const std::vector<GeodeticPoint>& area, const GeodeticPoint& home,
                          const SurveyParams& p, const SurveyPlan& plan) {
  if (!plan.ok()) throw std::invalid_argument("survey cannot be flown as planned: " + plan.overlap_problem);
  LocalNedFrame frame(home);
  Mission m;
  m.home = home;
  m.cruise_speed_m_s = p.speed_m_s;
  auto add = [&](int command, int frame_id, std::array<double, 4> params, double lat, double lon, double alt) {
    MissionItem it;
    it.command = command;
    it.frame = frame_id;
    it.param = params;
    it.latitude_deg = lat, it.longitude_deg = lon, it.altitude_m = alt;
    m.items.push_back(it);
  };
  const double nan = std::nan("");
  add(mav_cmd::kNavTakeoff, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, home.latitude_deg,
      home.longitude_deg, plan.altitude_m);
  add(mav_cmd::kDoChangeSpeed, mav_frame::kMission, {1, p.speed_m_s, -1, 0}, 0, 0, 0);
  SurveyDefinition def;
  def.polygon = area;
  def.params = p;
  def.first_item = m.items.size();
  for (const SurveyWaypoint& w : plan.waypoints) {
    const GeodeticPoint g = frame.ToGeodetic(Eigen::Vector3d(w.p_N.x(), w.p_N.y(), 0.0));
    add(mav_cmd::kNavWaypoint, mav_frame::kGlobalRelativeAlt, {0, 0, 0, w.yaw_rad * 180.0 / M_PI},
        g.latitude_deg, g.longitude_deg, -w.p_N.z());
    if (w.kind == SurveyWaypoint::Kind::kCaptureStart) {
      if (p.trigger_distance_m > 0)
        add(mav_cmd::kDoSetCamTriggDist, mav_frame::kMission, {p.trigger_distance_m, 0, 1, 0}, 0, 0, 0);
      else
        add(mav_cmd::kImageStartCapture, mav_frame::kMission, {0, 1.0 / p.capture_rate_hz, 0, 0}, 0, 0, 0);
    } else if (w.kind == SurveyWaypoint::Kind::kCaptureEnd) {
      if (p.trigger_distance_m > 0)
        add(mav_cmd::kDoSetCamTriggDist, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0);
      else
        add(mav_cmd::kImageStopCapture, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0);
    }
  }
  def.item_count = m.items.size() - def.first_item;
  m.surveys.push_back(def);
  add(mav_cmd::kNavReturnToLaunch, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0);
  ValidateMission(m);
  return m;
}

std::vector<MissionStep> CompileMission(const Mission& m, const LocalNedFrame& home, const VehicleLimits& limits) {
  ValidateMission(m);
  if (const auto problems = CheckMission(m, limits); !problems.empty())
    throw std::invalid_argument(DescribeProblems(problems));
  std::vector<MissionStep> steps;
  steps.push_back({MissionStep::Kind::kSetSpeed});
  steps.back().value = m.cruise_speed_m_s;
  const double home_alt = home.home().altitude_m;
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    MissionStep s{MissionStep::Kind::kWaypoint};
    s.item = i;
    const bool here = it.latitude_deg == 0 && it.longitude_deg == 0;
    auto position = [&]() -> Eigen::Vector3d {
      const double above_home = it.frame == mav_frame::kGlobal ? it.altitude_m - m.home.altitude_m : it.altitude_m;
      Eigen::Vector3d p = home.ToNed({it.latitude_deg, it.longitude_deg, home_alt});
      p.z() = -above_home;
      return p;
    };
    auto hold = [&](double seconds) {
      MissionStep h{MissionStep::Kind::kHold};
      h.item = i;
      h.value = seconds;
      steps.push_back(h);
    };
    if (IsFenceItem(it.command) || IsRallyItem(it.command)) continue;  // CompileGeofence's
    switch (it.command) {
      case mav_cmd::kNavWaypoint:
        s.p_N = position();
        s.yaw_rad = std::isnan(it.param[3]) ? std::nan("") : it.param[3] * M_PI / 180.0;
        steps.push_back(s);
        if (it.param[0] > 0) hold(it.param[0]);
        continue;
      case mav_cmd::kNavLoiterTime:  // at its point, or here (latitude/longitude 0)
        if (!here) {
          s.p_N = position();
          s.yaw_rad = std::nan("");
          steps.push_back(s);
        }
        hold(std::isnan(it.param[0]) ? 0.0 : it.param[0]);
        continue;
      case mav_cmd::kNavTakeoff:
        s.kind = MissionStep::Kind::kTakeoff;
        s.altitude_m = it.frame == mav_frame::kGlobal ? it.altitude_m - m.home.altitude_m : it.altitude_m;
        if (s.altitude_m < 1.0) Fail(ItemLabel(m, i), "take-off altitude " + Num(s.altitude_m) + " m is below 1 m");
        break;
      case mav_cmd::kNavLand:  // latitude/longitude 0 is "here" (MAVLink convention)
        s.kind = MissionStep::Kind::kLand;
        s.p_N = here ? Eigen::Vector3d::Constant(std::nan("")) : position();
        break;
      case mav_cmd::kNavReturnToLaunch:
        s.kind = MissionStep::Kind::kReturnHome;
        break;
      case mav_cmd::kDoChangeSpeed:
        s.kind = MissionStep::Kind::kSetSpeed;
        s.value = it.param[1];
        break;
      case mav_cmd::kDoSetCamTriggDist:
        s.kind = it.param[0] > 0 ? MissionStep::Kind::kCaptureStart : MissionStep::Kind::kCaptureStop;
        s.value = -it.param[0];
        break;
      case mav_cmd::kImageStartCapture:
        s.kind = MissionStep::Kind::kCaptureStart;
        if (IsSinglePhoto(it)) {
          s.value = kPhotoInterval_s;
          steps.push_back(s);
          hold(kPhotoHold_s);
          s.kind = MissionStep::Kind::kCaptureStop;
          break;
        }
        if (!(it.param[1] > 0)) Fail(ItemLabel(m, i), "param2 (interval) must be positive to capture (or param3 = 1 for one photo)");
        s.value = it.param[1];
        break;
      case mav_cmd::kImageStopCapture:
        s.kind = MissionStep::Kind::kCaptureStop;
        break;
      default:
        Fail(ItemLabel(m, i), "this vehicle cannot fly it (supported: NAV_WAYPOINT, NAV_LOITER_TIME, NAV_TAKEOFF, "
                              "NAV_LAND, NAV_RETURN_TO_LAUNCH, DO_CHANGE_SPEED, DO_SET_CAM_TRIGG_DIST, "
                              "IMAGE_START_CAPTURE, IMAGE_STOP_CAPTURE)");
    }
    steps.push_back(s);
  }
  return steps;
}

bool IsFenceItem(int command) {
  return command >= mav_cmd::kNavFencePolygonVertexInclusion && command <= mav_cmd::kNavFenceCircleExclusion;
}
bool IsRallyItem(int command) { return command == mav_cmd::kNavRallyPoint; }

bool IsSinglePhoto(const MissionItem& it) {
  return it.command == mav_cmd::kImageStartCapture && it.param[2] == 1 && !(it.param[1] > 0);
}

std::optional<double> CaptureBefore(const std::vector<MissionStep>& steps, std::size_t i) {
  std::optional<double> on;
  for (std::size_t k = 0; k < i && k < steps.size(); ++k) {
    if (steps[k].kind == MissionStep::Kind::kCaptureStart) on = steps[k].value;
    if (steps[k].kind == MissionStep::Kind::kCaptureStop) on.reset();
  }
  return on;
}

ResumedMission ResumeSteps(const std::vector<MissionStep>& steps, std::size_t from, bool airborne) {
  using Kind = MissionStep::Kind;
  if (from >= steps.size())
    throw std::invalid_argument("nothing to resume: step " + std::to_string(from) + " is past the mission's " +
                                std::to_string(steps.size()) + " steps");
  std::size_t start = from;
  if (CaptureBefore(steps, from)) {
    // Inside a capture leg: back to the point where its camera was switched on.
    std::size_t c = from;
    while (steps[c - 1].kind != Kind::kCaptureStart) --c;
    start = c - 1;
    while (start > 0 && steps[start].kind != Kind::kWaypoint) --start;
  }
  std::vector<MissionStep> out;
  if (!airborne && steps[start].kind != Kind::kTakeoff) {
    MissionStep takeoff{Kind::kTakeoff};
    takeoff.item = steps[start].item;
    takeoff.altitude_m = std::nan("");
    for (std::size_t k = 0; k < start && std::isnan(takeoff.altitude_m); ++k)
      if (steps[k].kind == Kind::kTakeoff) takeoff.altitude_m = steps[k].altitude_m;
    for (std::size_t k = start; k < steps.size() && std::isnan(takeoff.altitude_m); ++k)
      if (steps[k].kind == Kind::kWaypoint) takeoff.altitude_m = -steps[k].p_N.z();
    if (std::isnan(takeoff.altitude_m) || takeoff.altitude_m < 1.0) takeoff.altitude_m = 1.0;
    out.push_back(takeoff);
  }
  for (std::size_t k = start; k-- > 0;)
    if (steps[k].kind == Kind::kSetSpeed) {
      out.push_back(steps[k]);
      break;
    }
  if (const auto capture = CaptureBefore(steps, start)) {
    MissionStep on{Kind::kCaptureStart};
    on.item = steps[start].item;
    on.value = *capture;
    out.push_back(on);
  }
  ResumedMission r;
  r.first = start;
  r.prefix = out.size();
  out.insert(out.end(), steps.begin() + static_cast<std::ptrdiff_t>(start), steps.end());
  r.steps = std::move(out);
  return r;
}

}  // namespace uav::waypoints
