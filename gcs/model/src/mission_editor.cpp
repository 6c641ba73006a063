#include "uav/gcs/mission_editor.hpp"

#include <cmath>
#include <stdexcept>

#include "uav/gcs/survey_planner.hpp"
#include "uav/waypoints/geofence.hpp"

namespace uav::gcs {

namespace mav_cmd = waypoints::mav_cmd;
namespace mav_frame = waypoints::mav_frame;
using waypoints::Mission;
using waypoints::MissionItem;

const char* Name(PlanAction a) {
  switch (a) {
    case PlanAction::kWaypoint: return "waypoint";
    case PlanAction::kLoiter: return "loiter";
    case PlanAction::kPhoto: return "photo";
    case PlanAction::kLand: return "land";
    case PlanAction::kReturn: return "return";
    case PlanAction::kSurvey: return "survey";
    case PlanAction::kCameraStart: return "camera on";
    case PlanAction::kCameraStop: return "camera off";
  }
  return "?";
}

bool PlanItem::HasPosition() const {
  return action == PlanAction::kWaypoint || action == PlanAction::kLoiter || action == PlanAction::kLand;
}

MissionEditor::MissionEditor() = default;

void MissionEditor::Insert(std::size_t before, const PlanItem& item) {
  if (before > items_.size()) return;
  items_.insert(items_.begin() + static_cast<std::ptrdiff_t>(before), item);
  selected = static_cast<int>(before);
}

void MissionEditor::MoveTo(std::size_t i, const GeodeticPoint& g) {
  if (i >= items_.size() || !items_[i].HasPosition()) return;
  items_[i].latitude_deg = g.latitude_deg;
  items_[i].longitude_deg = g.longitude_deg;
}

void MissionEditor::Delete(std::size_t i) {
  if (i >= items_.size()) return;
  items_.erase(items_.begin() + static_cast<std::ptrdiff_t>(i));
  if (selected >= static_cast<int>(items_.size())) selected = static_cast<int>(items_.size()) - 1;
}

void MissionEditor::Clear() {
  items_.clear();
  selected = -1;
  fences.clear();
  rally.clear();
  fence_selected = -1;
  tool = MapTool::kWaypoint;
}

std::string MissionEditor::ZoneLabel(std::size_t z) const {
  if (z >= fences.size()) return "";
  int number = 0;
  for (std::size_t k = 0; k <= z; ++k)
    if (fences[k].inclusion == fences[z].inclusion && fences[k].circle == fences[z].circle) ++number;
  return waypoints::ZoneName(fences[z].inclusion, fences[z].circle, number);
}

void MissionEditor::AddFenceVertex(const GeodeticPoint& g) {
  if (fence_selected < 0 || fence_selected >= static_cast<int>(fences.size())) return;
  FenceDraft& f = fences[static_cast<std::size_t>(fence_selected)];
  if (f.circle) f.vertices.assign(1, g);
  else f.vertices.push_back(g);
}

bool MissionEditor::DeleteFenceNear(const SurveyPlanner& planner, const Eigen::Vector2d& ne, double radius_m) {
  auto near = [&](const GeodeticPoint& g) { return (planner.ToMap(g) - ne).norm() <= radius_m; };
  for (std::size_t k = 0; k < rally.size(); ++k)
    if (near(rally[k])) {
      rally.erase(rally.begin() + static_cast<std::ptrdiff_t>(k));
      return true;
    }
  for (std::size_t z = 0; z < fences.size(); ++z)
    for (std::size_t k = 0; k < fences[z].vertices.size(); ++k)
      if (near(fences[z].vertices[k])) {
        fences[z].vertices.erase(fences[z].vertices.begin() + static_cast<std::ptrdiff_t>(k));
        return true;
      }
  return false;
}

int MissionEditor::ItemNear(const SurveyPlanner& planner, const Eigen::Vector2d& ne, double radius_m) const {
  int best = -1;
  double best_d = radius_m;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    if (!items_[i].HasPosition()) continue;
    const double d = (planner.ToMap({items_[i].latitude_deg, items_[i].longitude_deg, 0}) - ne).norm();
    if (d <= best_d) best = static_cast<int>(i), best_d = d;
  }
  return best;
}

int EditorCheck::RowOf(int item) const {
  if (item < 0 || static_cast<std::size_t>(item) >= origins.size()) return -1;
  const ItemOrigin& o = origins[static_cast<std::size_t>(item)];
  return o.kind == ItemOrigin::Kind::kRow ? static_cast<int>(o.index) : -1;
}

EditorCheck MissionEditor::Check(const SurveyPlanner& planner, const GeodeticPoint& home,
                                 const waypoints::VehicleLimits& limits) const {
  EditorCheck c;
  c.mission = MakeMission(planner, home, &c.error, &c.origins);
  c.row_problems.assign(items_.size(), "");
  if (!c.mission) return c;
  c.problems = waypoints::CheckMission(*c.mission, limits);
  for (const waypoints::MissionProblem& p : c.problems) {
    const int row = c.RowOf(p.item == waypoints::MissionProblem::kCruise ? -1 : static_cast<int>(p.item));
    if (row >= 0 && c.row_problems[static_cast<std::size_t>(row)].empty())
      c.row_problems[static_cast<std::size_t>(row)] = p.text;
  }
  return c;
}

std::optional<Mission> MissionEditor::MakeMission(const SurveyPlanner& planner, const GeodeticPoint& home,
                                                  std::string* error, std::vector<ItemOrigin>* origins) const {
  Mission m;
  std::vector<ItemOrigin> from;  // per item of m
  ItemOrigin now{ItemOrigin::Kind::kTakeoff, 0};
  if (items_.empty()) {
    const auto survey = planner.MakeMission(error);
    if (!survey) return std::nullopt;
    m = *survey;
    from.assign(m.items.size(), now);
  } else {
    m.home = home;
    m.cruise_speed_m_s = cruise_speed_m_s;
  }
  const double nan = std::nan("");
  auto add = [&](int command, int frame, std::array<double, 4> param, double lat, double lon, double alt) {
    MissionItem it;
    it.command = command, it.frame = frame, it.param = param;
    it.latitude_deg = lat, it.longitude_deg = lon, it.altitude_m = alt;
    m.items.push_back(it);
    from.push_back(now);
  };
  auto speed = [&](double v) {
    if (v > 0) add(mav_cmd::kDoChangeSpeed, mav_frame::kMission, {1, v, -1, 0}, 0, 0, 0);
  };
  if (!items_.empty())
    add(mav_cmd::kNavTakeoff, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, home.latitude_deg, home.longitude_deg,
        takeoff_alt_m);
  for (std::size_t i = 0; i < items_.size(); ++i) {
    const PlanItem& p = items_[i];
    now = {ItemOrigin::Kind::kRow, i};
    const std::string where = "item " + std::to_string(i + 1) + " (" + Name(p.action) + ")";
    if (p.action != PlanAction::kSurvey) speed(p.speed_m_s);
    switch (p.action) {
      case PlanAction::kWaypoint:
        add(mav_cmd::kNavWaypoint, mav_frame::kGlobalRelativeAlt, {p.hold_s, 0, 0, p.yaw_deg}, p.latitude_deg,
            p.longitude_deg, p.altitude_m);
        break;
      case PlanAction::kLoiter:
        add(mav_cmd::kNavLoiterTime, mav_frame::kGlobalRelativeAlt, {p.hold_s, 0, 0, nan}, p.latitude_deg,
            p.longitude_deg, p.altitude_m);
        break;
      case PlanAction::kPhoto: add(mav_cmd::kImageStartCapture, mav_frame::kMission, {0, 0, 1, 0}, 0, 0, 0); break;
      case PlanAction::kLand:
        add(mav_cmd::kNavLand, mav_frame::kGlobalRelativeAlt, {0, 0, 0, nan}, p.latitude_deg, p.longitude_deg, 0);
        break;
      case PlanAction::kReturn: add(mav_cmd::kNavReturnToLaunch, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0); break;
      case PlanAction::kCameraStart:
        if (p.camera_distance_m > 0)
          add(mav_cmd::kDoSetCamTriggDist, mav_frame::kMission, {p.camera_distance_m, 0, 1, 0}, 0, 0, 0);
        else
          add(mav_cmd::kImageStartCapture, mav_frame::kMission, {0, p.camera_interval_s, 0, 0}, 0, 0, 0);
        break;
      case PlanAction::kCameraStop: add(mav_cmd::kImageStopCapture, mav_frame::kMission, {0, 0, 0, 0}, 0, 0, 0); break;
      case PlanAction::kSurvey: {
        // The planner's survey mission is take-off, speed, the survey's own items, return: the
        // middle is this item.
        std::string why;
        const auto survey = planner.MakeMission(&why);
        if (!survey || survey->surveys.size() != 1) {
          *error = where + ": " + (why.empty() ? "the survey has no plan" : why);
          return std::nullopt;
        }
        waypoints::SurveyDefinition def = survey->surveys.front();
        speed(p.speed_m_s > 0 ? p.speed_m_s : def.params.speed_m_s);
        const auto first = survey->items.begin() + static_cast<std::ptrdiff_t>(def.first_item);
        def.first_item = m.items.size();
        m.items.insert(m.items.end(), first, first + static_cast<std::ptrdiff_t>(def.item_count));
        from.resize(m.items.size(), now);
        m.surveys.push_back(def);
        break;
      }
    }
  }
  // The fence, as the .plan keeps it: polygons, then circles, then the rally points.
  for (int pass = 0; pass < 2; ++pass)
    for (std::size_t z = 0; z < fences.size(); ++z) {
      const FenceDraft& f = fences[z];
      if (f.circle != (pass == 1)) continue;
      now = {ItemOrigin::Kind::kFence, z};
      const std::string where = ZoneLabel(z);
      if (f.circle) {
        if (f.vertices.empty()) {
          *error = where + ": the circle has no centre (click the map)";
          return std::nullopt;
        }
        add(f.inclusion ? mav_cmd::kNavFenceCircleInclusion : mav_cmd::kNavFenceCircleExclusion,
            mav_frame::kGlobalRelativeAlt, {f.radius_m, 0, 0, 0}, f.vertices[0].latitude_deg, f.vertices[0].longitude_deg, 0);
        continue;
      }
      if (f.vertices.size() < 3) {
        *error = where + ": a polygon needs at least 3 vertices (it has " + std::to_string(f.vertices.size()) + ")";
        return std::nullopt;
      }
      for (const GeodeticPoint& v : f.vertices)
        add(f.inclusion ? mav_cmd::kNavFencePolygonVertexInclusion : mav_cmd::kNavFencePolygonVertexExclusion,
            mav_frame::kGlobalRelativeAlt, {static_cast<double>(f.vertices.size()), 0, 0, 0}, v.latitude_deg,
            v.longitude_deg, 0);
    }
  for (std::size_t k = 0; k < rally.size(); ++k) {
    const GeodeticPoint& r = rally[k];
    now = {ItemOrigin::Kind::kRally, k};
    add(mav_cmd::kNavRallyPoint, mav_frame::kGlobalRelativeAlt, {0, 0, 0, 0}, r.latitude_deg, r.longitude_deg, r.altitude_m);
  }
  try {
    waypoints::ValidateMission(m);
  } catch (const std::exception& e) {
    *error = e.what();
    return std::nullopt;
  }
  if (origins) *origins = std::move(from);
  return m;
}

bool MissionEditor::Load(const Mission& m, SurveyPlanner* planner, std::string* error) {
  std::vector<PlanItem> items;
  double takeoff = takeoff_alt_m;
  double pending_speed = 0;
  const waypoints::SurveyDefinition* survey = nullptr;
  double last_lat = m.home.latitude_deg, last_lon = m.home.longitude_deg, last_alt = takeoff;
  auto above_home = [&](const MissionItem& it) {
    return it.frame == mav_frame::kGlobal ? it.altitude_m - m.home.altitude_m : it.altitude_m;
  };
  std::size_t next_survey = 0;
  std::vector<FenceDraft> fence_drafts;
  std::vector<GeodeticPoint> rally_points;
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    if (waypoints::IsRallyItem(it.command)) {
      rally_points.push_back({it.latitude_deg, it.longitude_deg, above_home(it)});
      continue;
    }
    if (waypoints::IsFenceItem(it.command)) {
      FenceDraft f;
      f.inclusion = it.command == mav_cmd::kNavFencePolygonVertexInclusion || it.command == mav_cmd::kNavFenceCircleInclusion;
      f.circle = it.command == mav_cmd::kNavFenceCircleInclusion || it.command == mav_cmd::kNavFenceCircleExclusion;
      if (f.circle) {
        f.radius_m = it.param[0];
        f.vertices.push_back({it.latitude_deg, it.longitude_deg, 0});
      } else {
        const auto n = static_cast<std::size_t>(it.param[0]);  // validated: the run of vertices
        for (std::size_t k = 0; k < n; ++k) f.vertices.push_back({m.items[i + k].latitude_deg, m.items[i + k].longitude_deg, 0});
        i += n - 1;
      }
      fence_drafts.push_back(std::move(f));
      continue;
    }
    const std::string name = waypoints::CommandName(it.command);
    const std::string where =
        "item " + std::to_string(i) + " (" + (name.empty() ? "command " + std::to_string(it.command) : name) + ")";
    if (next_survey < m.surveys.size() && i == m.surveys[next_survey].first_item) {
      if (survey) {
        *error = where + ": a second survey; this editor holds one (split the mission)";
        return false;
      }
      survey = &m.surveys[next_survey++];
      PlanItem p;
      p.action = PlanAction::kSurvey;
      p.speed_m_s = pending_speed > 0 && pending_speed != survey->params.speed_m_s ? pending_speed : 0;
      pending_speed = 0;
      items.push_back(p);
      i += survey->item_count - 1;
      continue;
    }
    PlanItem p;
    const bool here = it.latitude_deg == 0 && it.longitude_deg == 0;
    p.latitude_deg = here ? last_lat : it.latitude_deg;
    p.longitude_deg = here ? last_lon : it.longitude_deg;
    p.altitude_m = last_alt;
    switch (it.command) {
      case mav_cmd::kNavTakeoff:
        if (i != 0) {
          *error = where + ": a take-off after the first item cannot be edited here";
          return false;
        }
        takeoff = last_alt = above_home(it);
        continue;
      case mav_cmd::kDoChangeSpeed:
        pending_speed = it.param[1];
        continue;
      case mav_cmd::kNavWaypoint:
        p.action = PlanAction::kWaypoint;
        p.altitude_m = above_home(it);
        p.hold_s = std::isnan(it.param[0]) ? 0 : it.param[0];
        p.yaw_deg = it.param[3];
        break;
      case mav_cmd::kNavLoiterTime:
        p.action = PlanAction::kLoiter;
        if (!here) p.altitude_m = above_home(it);
        p.hold_s = std::isnan(it.param[0]) ? 0 : it.param[0];
        break;
      case mav_cmd::kNavLand: p.action = PlanAction::kLand; break;
      case mav_cmd::kNavReturnToLaunch: p.action = PlanAction::kReturn; break;
      case mav_cmd::kImageStartCapture:
        p.action = waypoints::IsSinglePhoto(it) ? PlanAction::kPhoto : PlanAction::kCameraStart;
        p.camera_interval_s = it.param[1];
        break;
      case mav_cmd::kDoSetCamTriggDist:
        p.action = it.param[0] > 0 ? PlanAction::kCameraStart : PlanAction::kCameraStop;
        p.camera_distance_m = it.param[0];
        if (p.action == PlanAction::kCameraStop) {
          *error = where + ": a distance trigger of 0 outside a survey cannot be edited here (use IMAGE_STOP_CAPTURE)";
          return false;
        }
        break;
      case mav_cmd::kImageStopCapture: p.action = PlanAction::kCameraStop; break;
      default:
        *error = where + ": this editor cannot show it (waypoints, loiters, photos, camera on/off, land, return, "
                         "speed changes and surveys)";
        return false;
    }
    p.speed_m_s = pending_speed;
    pending_speed = 0;
    if (p.HasPosition()) last_lat = p.latitude_deg, last_lon = p.longitude_deg, last_alt = p.altitude_m;
    items.push_back(p);
  }
  if (pending_speed > 0) {
    *error = "the mission ends with a speed change that applies to nothing";
    return false;
  }
  // A survey mission as the planner makes it (take off, survey, return) stays a survey only: the
  // survey panel edits it as before.
  const bool plain_survey = survey && items.size() == 2 && items[0].action == PlanAction::kSurvey &&
                            items[1].action == PlanAction::kReturn && items[0].speed_m_s == 0;
  if (survey) planner->SetSurvey(*survey, m.home);
  items_ = plain_survey ? std::vector<PlanItem>{} : std::move(items);
  fences = std::move(fence_drafts);
  rally = std::move(rally_points);
  fence_selected = -1;
  tool = MapTool::kWaypoint;
  takeoff_alt_m = takeoff;
  cruise_speed_m_s = m.cruise_speed_m_s;
  selected = -1;
  return true;
}

}  // namespace uav::gcs
