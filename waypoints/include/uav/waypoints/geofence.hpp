#pragma once
// The geofence and rally points uploaded with a mission (MAVLink's fence and rally items,
// QGroundControl's .plan geoFence and rallyPoints), in the vehicle's NED frame at home. As PX4:
// the vehicle must be inside at least one inclusion zone (when there is one) and inside no
// exclusion zone; the circle around home and the ceiling of the vehicle file (fs_fence_radius,
// fs_fence_alt) hold as well. A return goes to the nearest rally point when there is one.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "uav/shared/geodesy.hpp"
#include "uav/waypoints/mission.hpp"
#include "uav/waypoints/polygon.hpp"

namespace uav::waypoints {

// A zone as operators and the mission editor name it: "keep-out polygon 2" is the second keep-out
// polygon in upload order (a .plan file keeps polygons and circles apart; counting each kind on its
// own names a zone the same in either order).
std::string ZoneName(bool inclusion, bool circle, int number);
// The zone or rally point mission item i belongs to ("keep-out polygon 1", "rally point 2"); ""
// for an item of the mission proper.
std::string FenceItemOwner(const Mission& m, std::size_t i);

struct FenceZone {
  std::string name;  // ZoneName's
  bool inclusion = true;
  Polygon2 polygon_N;                             // north, east [m]; empty for a circle
  Eigen::Vector2d centre_N = Eigen::Vector2d::Zero();
  double radius_m = 0;                            // a circle's
  bool Contains(const Eigen::Vector2d& p_N) const;
};

struct Geofence {
  std::vector<FenceZone> zones;
  std::vector<Eigen::Vector3d> rally_N;  // NED [m] (z: minus the altitude above home)
  bool empty() const { return zones.empty() && rally_N.empty(); }
  // "" when p_N is allowed, else why not ("inside keep-out polygon 2", "outside every keep-in
  // zone").
  std::string Breach(const Eigen::Vector2d& p_N) const;
  // The rally point nearest p_N, or nullptr when there is none.
  const Eigen::Vector3d* NearestRally(const Eigen::Vector2d& p_N) const;
};

// The fence and rally items of a validated mission, in the NED frame at `home`. Throws
// std::invalid_argument naming the zone and item: a polygon's vertex count (param1) that is below 3 or
// does not match the run of vertices, a polygon that crosses itself or has no area, a circle
// radius that is not positive.
Geofence CompileGeofence(const Mission& m, const LocalNedFrame& home);

}  // namespace uav::waypoints
