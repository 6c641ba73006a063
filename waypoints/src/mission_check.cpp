// A mission against what the vehicle may fly: its speed limit, its ceiling and range (the
// fs_fence_* parameters) and the geofence uploaded with the mission itself.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "uav/shared/parameters.hpp"
#include "uav/shared/vehicle_enums.hpp"
#include "uav/waypoints/geofence.hpp"
#include "uav/waypoints/mission.hpp"

namespace uav::waypoints {
namespace {

std::string Fixed(double v, int decimals) {
  char s[48];
  std::snprintf(s, sizeof s, "%.*f", decimals, v);
  return s;
}

// A distance as an operator reads it: metres up to 10 km, kilometres beyond.
std::string Distance(double m) { return m < 10000 ? Fixed(m, 0) + " m" : Fixed(m / 1000.0, 1) + " km"; }

bool IsPoint(const MissionItem& it) {
  const bool here = it.latitude_deg == 0 && it.longitude_deg == 0;
  switch (it.command) {
    case mav_cmd::kNavWaypoint: return true;
    case mav_cmd::kNavLoiterTime:
    case mav_cmd::kNavLand: return !here;  // latitude/longitude 0: where the vehicle is
    default: return false;
  }
}

double AboveHome(const Mission& m, const MissionItem& it) {
  return it.frame == mav_frame::kGlobal ? it.altitude_m - m.home.altitude_m : it.altitude_m;
}

// The first zone a straight leg a -> b enters that it must not ("crosses keep-out polygon 1",
// "leaves the keep-in zones"), or "". Sampled every metre or so: a leg is at most the vehicle's
// range, and a zone thinner than the spacing is not one a multicopter could be held out of anyway.
std::string LegBreach(const Geofence& fence, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  // An end in a zone is the point's own problem, named once.
  if (fence.zones.empty() || !fence.Breach(a).empty() || !fence.Breach(b).empty()) return "";
  const double length = (b - a).norm();
  const int samples = std::clamp(static_cast<int>(std::ceil(length / 1.0)), 1, 20000);
  for (int k = 1; k < samples; ++k) {
    const Eigen::Vector2d p = a + (b - a) * (static_cast<double>(k) / samples);
    std::string why = fence.Breach(p);
    if (why.empty()) continue;
    if (why.rfind("inside ", 0) == 0) return "crosses " + why.substr(7);
    return "leaves the keep-in zones " + Distance((p - a).norm()) + " after its start";
  }
  return "";
}

}  // namespace

VehicleLimits VehicleLimits::Of(const std::function<double(const std::string&)>& value) {
  const ParameterSet defaults = ParameterSet::Defaults(VehicleParameterSchema());
  auto get = [&](const std::string& name) {
    const double v = value(name);
    return std::isfinite(v) ? v : defaults.Get(name);
  };
  VehicleLimits l;
  l.max_speed_m_s = get("ctl_speed_max_xy");
  // A tail-sitter on its wing flies at its cruise speed: a mission may ask for up to that.
  if (get("vehicle_type") == static_cast<double>(VehicleType::kTailSitter))
    l.max_speed_m_s = std::max(l.max_speed_m_s, get("ts_cruise_speed"));
  l.ceiling_m = get("fs_fence_alt");
  l.range_m = get("fs_fence_radius");
  return l;
}

std::string ItemLabel(const Mission& m, std::size_t i) {
  const std::string owner = FenceItemOwner(m, i);
  if (!owner.empty()) return owner + " (item " + std::to_string(i) + ")";
  std::string s = "item " + std::to_string(i) + " (";
  const char* name = i < m.items.size() ? CommandName(m.items[i].command) : "";
  s += *name ? std::string(name) : "command " + std::to_string(i < m.items.size() ? m.items[i].command : -1);
  return s + ")";
}

std::string DescribeProblems(const std::vector<MissionProblem>& problems) {
  if (problems.empty()) return "";
  std::string s = problems.front().text;
  if (problems.size() > 1)
    s += " (and " + std::to_string(problems.size() - 1) + " more problem" + (problems.size() > 2 ? "s" : "") + ")";
  return s;
}

std::vector<MissionProblem> CheckMission(const Mission& m, const VehicleLimits& limits) {
  std::vector<MissionProblem> out;
  auto speed_problem = [&](std::size_t item, const std::string& what, double v) {
    if (v > limits.max_speed_m_s)
      out.push_back({item, what + ": " + Fixed(v, 1) + " m/s is above the vehicle's " +
                               Fixed(limits.max_speed_m_s, 1) + " m/s (ctl_speed_max_xy)"});
  };
  speed_problem(MissionProblem::kCruise, "cruise speed", m.cruise_speed_m_s);
  const LocalNedFrame frame(m.home);
  Geofence fence;
  try {
    fence = CompileGeofence(m, frame);
  } catch (const std::invalid_argument& e) {
    out.push_back({MissionProblem::kCruise, std::string("geofence: ") + e.what()});
  }
  auto at = [&](const MissionItem& it) {
    return Eigen::Vector2d(frame.ToNed({it.latitude_deg, it.longitude_deg, m.home.altitude_m}).head<2>());
  };
  // A point against the ceiling, the range and the zones.
  auto point_problems = [&](std::size_t i, const Eigen::Vector2d& p_N, double above_home, bool check_zones) {
    if (above_home > limits.ceiling_m)
      out.push_back({i, ItemLabel(m, i) + ": " + Fixed(above_home, 1) + " m above home, above the vehicle's " +
                            Fixed(limits.ceiling_m, 0) + " m ceiling (fs_fence_alt)"});
    if (p_N.norm() > limits.range_m)
      out.push_back({i, ItemLabel(m, i) + ": " + Distance(p_N.norm()) + " from home, beyond the vehicle's " +
                            Distance(limits.range_m) + " range (fs_fence_radius)"});
    if (check_zones)
      if (const std::string why = fence.Breach(p_N); !why.empty())
        out.push_back({i, ItemLabel(m, i) + ": " + why});
  };
  Eigen::Vector2d last = Eigen::Vector2d::Zero();  // the vehicle takes off at home
  std::size_t last_item = MissionProblem::kCruise;
  auto leg_to = [&](std::size_t i, const Eigen::Vector2d& p_N) {
    if (const std::string why = LegBreach(fence, last, p_N); !why.empty())
      out.push_back({i, ItemLabel(m, i) + ": the leg from " +
                            (last_item == MissionProblem::kCruise ? std::string("home") : "item " + std::to_string(last_item)) +
                            " " + why});
    last = p_N;
    last_item = i;
  };
  for (std::size_t i = 0; i < m.items.size(); ++i) {
    const MissionItem& it = m.items[i];
    if (it.command == mav_cmd::kDoChangeSpeed) speed_problem(i, ItemLabel(m, i), it.param[1]);
    if (IsRallyItem(it.command)) point_problems(i, at(it), AboveHome(m, it), true);
    if (it.command == mav_cmd::kNavTakeoff) point_problems(i, last, AboveHome(m, it), false);
    if (it.command == mav_cmd::kNavReturnToLaunch) {
      // Straight back to the nearest rally point, else home (TaskManager's return).
      const Eigen::Vector3d* rally = fence.NearestRally(last);
      leg_to(i, rally ? Eigen::Vector2d(rally->head<2>()) : Eigen::Vector2d::Zero());
    }
    if (!IsPoint(it)) continue;
    const Eigen::Vector2d p_N = at(it);
    point_problems(i, p_N, it.command == mav_cmd::kNavLand ? 0.0 : AboveHome(m, it), true);
    leg_to(i, p_N);
  }
  return out;
}

}  // namespace uav::waypoints
