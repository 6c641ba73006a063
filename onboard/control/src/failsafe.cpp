#include "uav/control/failsafe.hpp"

#include "uav/control/position_attitude_controller.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace uav::control {
namespace {
std::string Format(const char* fmt, double a, double b) {
  char buf[128];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}
}  // namespace

FailsafeParams FailsafeParams::FromParameters(const ParameterSet& ps) {
  FailsafeParams p{ps.Get("fs_link_hold_time"),  ps.Get("fs_link_return_time"), ps.Get("fs_battery_return"),
                   ps.Get("fs_battery_land"),    ps.Get("fs_fence_radius"),     ps.Get("fs_fence_alt"),
                   FailsafeAction::kHold};
  const double action = ps.Get("fs_fence_action");
  if (action != 1.0 && action != 2.0 && action != 3.0)
    throw std::invalid_argument(ps.Describe("fs_fence_action") + " must be 1 (hold), 2 (return) or 3 (land)");
  p.fence_action = action == 1.0 ? FailsafeAction::kHold : action == 2.0 ? FailsafeAction::kReturn : FailsafeAction::kLand;
  p.nav_land_s = ps.Get("fs_nav_land_s");
  if (p.link_return_s <= p.link_hold_s)
    throw std::invalid_argument(ps.Describe("fs_link_return_time") + " must be longer than " + ps.Describe("fs_link_hold_time"));
  if (p.battery_land >= p.battery_return)
    throw std::invalid_argument(ps.Describe("fs_battery_land") + " must be below " + ps.Describe("fs_battery_return"));
  return p;
}

std::string CheckSetpoint(const Setpoint& sp, const FailsafeParams& p, double speed_max_xy, double margin_m) {
  const char* axis[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    if (!std::isfinite(sp.p_N[i])) return std::string("p_N.") + axis[i] + " is not finite";
    if (!std::isfinite(sp.v_ff_N[i])) return std::string("v_ff_N.") + axis[i] + " is not finite";
  }
  if (!std::isfinite(sp.yaw)) return "yaw is not finite";
  if (!std::isfinite(sp.yaw_rate_ff)) return "yaw rate feed-forward is not finite";
  if (sp.descent_rate && !(std::isfinite(*sp.descent_rate) && *sp.descent_rate >= 0 && *sp.descent_rate <= 10))
    return "descent rate is outside [0, 10] m/s";
  if (sp.speed_max_xy && !(std::isfinite(*sp.speed_max_xy) && *sp.speed_max_xy > 0))
    return "speed limit is not a positive number";
  if (sp.speed_max && !(std::isfinite(*sp.speed_max) && *sp.speed_max > 0))
    return "3-D speed limit is not a positive number";
  if (sp.p_N.head<2>().norm() > p.fence_radius_m + margin_m)
    return Format("target %.0f m from home is beyond the %.0f m geofence", sp.p_N.head<2>().norm(), p.fence_radius_m);
  if (-sp.p_N.z() > p.fence_alt_m + margin_m || -sp.p_N.z() < -margin_m)
    return Format("target altitude %.1f m is outside [0, %.0f] m", -sp.p_N.z(), p.fence_alt_m);
  if (sp.v_ff_N.head<2>().norm() > speed_max_xy + 1e-6)
    return Format("feed-forward speed %.1f m/s is above the %.1f m/s limit", sp.v_ff_N.head<2>().norm(), speed_max_xy);
  return "";
}

FailsafeMonitor::FailsafeMonitor(const FailsafeParams& p) : p_(p) {}

FailsafeAction FailsafeMonitor::Update(const FailsafeInputs& in, std::vector<std::string>* events) {
  // GCS link: only once a GCS has been heard.
  FailsafeAction link = FailsafeAction::kNone;
  if (in.gcs_link_age_s >= 0) {
    const double age = in.gcs_link_age_s;
    if (in.airborne && age >= p_.link_return_s) link = FailsafeAction::kReturn;
    else if (in.airborne && age >= p_.link_hold_s) link = FailsafeAction::kHold;
    if (link != FailsafeAction::kNone) link_reason_ = Format("no GCS heartbeat for %.1f s (limit %.0f s)", age, link == FailsafeAction::kReturn ? p_.link_return_s : p_.link_hold_s);
    if (link > link_) events->push_back("failsafe: GCS link lost: " + std::string(Name(link)) + " (" + link_reason_ + ")");
    if (link_ != FailsafeAction::kNone && age < p_.link_hold_s) {
      events->push_back("GCS link regained; the failsafe action continues until the operator commands");
    }
  }
  link_ = link;

  // Battery: latched.
  FailsafeAction battery = battery_;
  if (in.battery_remaining < p_.battery_land) battery = FailsafeAction::kLand;
  else if (in.battery_remaining < p_.battery_return) battery = std::max(battery, FailsafeAction::kReturn);
  if (battery > battery_) {
    // Rounded down, so the message never shows a value at the threshold it is below.
    battery_reason_ = Format("battery %.1f %% below %.0f %%", std::floor(1000 * in.battery_remaining) / 10,
                             100 * (battery == FailsafeAction::kLand ? p_.battery_land : p_.battery_return));
    events->push_back("failsafe: " + battery_reason_ + ": " + std::string(Name(battery)));
  }
  battery_ = battery;

  // Geofence.
  const double dist = in.p_N.head<2>().norm(), alt = -in.p_N.z();
  FailsafeAction fence = FailsafeAction::kNone;
  const std::string zone = fence_zones_.Breach(in.p_N.head<2>());
  if (in.airborne && (dist > p_.fence_radius_m || alt > p_.fence_alt_m || !zone.empty())) {
    fence = p_.fence_action;
    fence_reason_ = dist > p_.fence_radius_m ? Format("%.1f m from home, fence %.0f m", dist, p_.fence_radius_m)
                    : alt > p_.fence_alt_m   ? Format("%.1f m high, fence %.0f m", alt, p_.fence_alt_m)
                                             : zone;
  }
  if (fence > fence_) events->push_back("failsafe: geofence breached (" + fence_reason_ + "): " + std::string(Name(fence)));
  if (fence == FailsafeAction::kNone && fence_ != FailsafeAction::kNone) events->push_back("back inside the geofence");
  fence_ = fence;

  // Position: hold at once, land after nav_land_s; the landing is latched.
  FailsafeAction position = position_ == FailsafeAction::kLand ? FailsafeAction::kLand : FailsafeAction::kNone;
  if (in.airborne && in.position_lost) {
    if (position_lost_since_ < 0) position_lost_since_ = in.t;
    const double lost_s = in.t - position_lost_since_;
    position = std::max(position, lost_s >= p_.nav_land_s ? FailsafeAction::kLand : FailsafeAction::kHold);
    position_reason_ = Format("no position for %.1f s (landing after %.0f s): ", lost_s, p_.nav_land_s) + in.position_lost_reason;
  } else {
    position_lost_since_ = -1;
  }
  if (!in.airborne) position = FailsafeAction::kNone;
  if (position > position_) events->push_back("failsafe: " + position_reason_ + ": " + std::string(Name(position)));
  if (position == FailsafeAction::kNone && position_ == FailsafeAction::kHold) events->push_back("position source regained");
  position_ = position;

  // Obstacle perception: lost in flight with avoidance on (a camera failed), return home on the
  // map alone; latched until landing (a camera that comes back is said, the return goes on).
  FailsafeAction perception = in.airborne ? perception_ : FailsafeAction::kNone;
  if (in.airborne && in.perception_lost && perception == FailsafeAction::kNone) {
    perception = FailsafeAction::kReturn;
    perception_reason_ = "obstacle perception lost: " + in.perception_lost_reason;
    events->push_back("failsafe: " + perception_reason_ + ": return at this altitude through space seen free");
  }
  if (perception != FailsafeAction::kNone && !in.perception_lost && perception_lost_said_)
    events->push_back("obstacle perception regained; the return goes on");
  perception_lost_said_ = perception != FailsafeAction::kNone && in.perception_lost;
  perception_ = perception;

  // Manual override: immediate, level.
  const FailsafeAction manual = in.rc_manual ? FailsafeAction::kManual : FailsafeAction::kNone;
  if (manual != manual_)
    events->push_back(in.rc_manual ? "RC fail-safe switch: pilot has control" : "RC fail-safe switch: autopilot has control");
  manual_ = manual;

  required_ = std::max({link_, battery_, fence_, manual_, position_, perception_});
  reason_ = required_ == manual_ && manual_ != FailsafeAction::kNone ? "RC fail-safe switch"
            : required_ == battery_ && battery_ != FailsafeAction::kNone ? battery_reason_
            : required_ == link_ && link_ != FailsafeAction::kNone     ? link_reason_
            : required_ == position_ && position_ != FailsafeAction::kNone ? position_reason_
            : required_ == fence_ && fence_ != FailsafeAction::kNone   ? fence_reason_
            : required_ == perception_ && perception_ != FailsafeAction::kNone ? perception_reason_
                                                                       : std::string();
  return required_;
}

}  // namespace uav::control
