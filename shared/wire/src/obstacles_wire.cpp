#include "uav/wire/messages.hpp"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "uavmsg/avoidance_t.hpp"
#include "uavmsg/obstacles_t.hpp"
#include "uavmsg/point_cloud_t.hpp"

namespace uav {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument(what);
}
bool Finite(std::initializer_list<float> v) {
  for (float x : v)
    if (!std::isfinite(x)) return false;
  return true;
}

// Points sent as centimetres from an origin (int16: within 327 m of it).
struct Centimetres {
  std::vector<int16_t> north, east, down;
  // Appends p (skipped when it is not finite or too far); false when it was skipped.
  bool Add(const Eigen::Vector3f& p_N, const Eigen::Vector3f& origin_N) {
    const Eigen::Vector3f d = (p_N - origin_N) * 100.0f;
    if (!d.allFinite() || d.cwiseAbs().maxCoeff() > 32700.0f) return false;
    north.push_back(static_cast<int16_t>(std::lround(d.x())));
    east.push_back(static_cast<int16_t>(std::lround(d.y())));
    down.push_back(static_cast<int16_t>(std::lround(d.z())));
    return true;
  }
};

std::vector<Eigen::Vector3f> FromCentimetres(float origin_north_m, float origin_east_m, float origin_down_m,
                                             const std::vector<int16_t>& north, const std::vector<int16_t>& east,
                                             const std::vector<int16_t>& down) {
  std::vector<Eigen::Vector3f> p_N;
  p_N.reserve(north.size());
  for (std::size_t i = 0; i < north.size(); ++i)
    p_N.emplace_back(origin_north_m + 0.01f * north[i], origin_east_m + 0.01f * east[i], origin_down_m + 0.01f * down[i]);
  return p_N;
}
}  // namespace

Obstacles FromMessage(const uavmsg::obstacles_t& m) {
  const std::string what = "obstacles_t: ";
  Require(m.num_obstacles >= 0 && m.num_obstacles <= uavmsg::obstacles_t::MAX_OBSTACLES,
          what + "num_obstacles " + std::to_string(m.num_obstacles) + " outside 0.." +
              std::to_string(uavmsg::obstacles_t::MAX_OBSTACLES));
  Require(static_cast<int>(m.obstacles.size()) == m.num_obstacles, what + "num_obstacles does not match the obstacles sent");
  Require(Finite({m.range_gate_m, m.nearest_m}), what + "range_gate_m or nearest_m is not finite");
  Require(m.healthy || m.num_obstacles == 0, what + "an unhealthy report carries obstacles");
  Obstacles o;
  o.utime = m.utime;
  o.camera = m.camera;
  o.healthy = m.healthy;
  o.reason = m.reason;
  o.range_gate_m = m.range_gate_m;
  o.nearest_m = m.nearest_m < 0 ? -1.0 : m.nearest_m;
  for (int i = 0; i < m.num_obstacles; ++i) {
    const uavmsg::obstacle_t& c = m.obstacles[i];
    const std::string where = what + "obstacle " + std::to_string(i) + ": ";
    Require(Finite({c.north_m, c.east_m, c.top_down_m, c.bottom_down_m, c.radius_m, c.safety_radius_m, c.range_m, c.cov_nn,
                    c.cov_ne, c.cov_ee, c.image_x0, c.image_y0, c.image_x1, c.image_y1}),
            where + "a value is not finite");
    Require(c.top_down_m <= c.bottom_down_m, where + "top is below bottom");
    Require(c.radius_m >= 0 && c.safety_radius_m >= c.radius_m, where + "radius negative or above the safety radius");
    Require(c.cov_nn >= 0 && c.cov_ee >= 0 && c.cov_ne * c.cov_ne <= c.cov_nn * c.cov_ee * 1.0001f + 1e-9f,
            where + "covariance is not positive semi-definite");
    Obstacle b;
    b.p_NE = Eigen::Vector2d(c.north_m, c.east_m);
    b.top_down_m = c.top_down_m;
    b.bottom_down_m = c.bottom_down_m;
    b.radius_m = c.radius_m;
    b.safety_radius_m = c.safety_radius_m;
    b.range_m = c.range_m;
    b.cov_NE << c.cov_nn, c.cov_ne, c.cov_ne, c.cov_ee;
    b.image_box = {c.image_x0, c.image_y0, c.image_x1, c.image_y1};
    o.obstacles.push_back(b);
  }
  return o;
}

uavmsg::obstacles_t ToMessage(const Obstacles& o) {
  uavmsg::obstacles_t m;
  m.utime = o.utime;
  m.camera = o.camera;
  m.healthy = o.healthy;
  m.reason = o.reason;
  m.range_gate_m = static_cast<float>(o.range_gate_m);
  m.nearest_m = static_cast<float>(o.nearest_m);
  for (const Obstacle& b : o.obstacles) {
    if (!o.healthy || static_cast<int>(m.obstacles.size()) >= uavmsg::obstacles_t::MAX_OBSTACLES) break;
    uavmsg::obstacle_t c;
    c.north_m = static_cast<float>(b.p_NE.x());
    c.east_m = static_cast<float>(b.p_NE.y());
    c.top_down_m = static_cast<float>(b.top_down_m);
    c.bottom_down_m = static_cast<float>(b.bottom_down_m);
    c.radius_m = static_cast<float>(b.radius_m);
    c.safety_radius_m = static_cast<float>(b.safety_radius_m);
    c.range_m = static_cast<float>(b.range_m);
    c.cov_nn = static_cast<float>(b.cov_NE(0, 0));
    c.cov_ne = static_cast<float>(b.cov_NE(0, 1));
    c.cov_ee = static_cast<float>(b.cov_NE(1, 1));
    c.image_x0 = static_cast<float>(b.image_box[0]);
    c.image_y0 = static_cast<float>(b.image_box[1]);
    c.image_x1 = static_cast<float>(b.image_box[2]);
    c.image_y1 = static_cast<float>(b.image_box[3]);
    m.obstacles.push_back(c);
  }
  m.num_obstacles = static_cast<int16_t>(m.obstacles.size());
  return m;
}

PointCloud FromMessage(const uavmsg::point_cloud_t& m) {
  const std::string what = "point_cloud_t: ";
  Require(m.num_points >= 0 && m.num_points <= uavmsg::point_cloud_t::MAX_POINTS,
          what + "num_points " + std::to_string(m.num_points) + " outside 0.." + std::to_string(uavmsg::point_cloud_t::MAX_POINTS));
  const auto n = static_cast<std::size_t>(m.num_points);
  Require(m.north_cm.size() == n && m.east_cm.size() == n && m.down_cm.size() == n,
          what + "point arrays do not match num_points");
  Require(Finite({m.origin_north_m, m.origin_east_m, m.origin_down_m}), what + "origin is not finite");
  PointCloud c;
  c.utime = m.utime;
  c.origin_N = Eigen::Vector3d(m.origin_north_m, m.origin_east_m, m.origin_down_m);
  c.p_N = FromCentimetres(m.origin_north_m, m.origin_east_m, m.origin_down_m, m.north_cm, m.east_cm, m.down_cm);
  return c;
}

uavmsg::point_cloud_t ToMessage(const PointCloud& c) {
  const Eigen::Vector3d& origin_N = c.origin_N;
  uavmsg::point_cloud_t m;
  m.utime = c.utime;
  m.origin_north_m = static_cast<float>(origin_N.x());
  m.origin_east_m = static_cast<float>(origin_N.y());
  m.origin_down_m = static_cast<float>(origin_N.z());
  const std::size_t step = c.p_N.size() / uavmsg::point_cloud_t::MAX_POINTS + 1;
  Centimetres cm;
  for (std::size_t i = 0; i < c.p_N.size(); i += step) cm.Add(c.p_N[i], origin_N.cast<float>());
  m.north_cm = std::move(cm.north);
  m.east_cm = std::move(cm.east);
  m.down_cm = std::move(cm.down);
  m.num_points = static_cast<int32_t>(m.north_cm.size());
  return m;
}

// Obstacle avoidance's plan and map: the same obstacles, as the vehicle's map keeps them.
AvoidanceReport FromMessage(const uavmsg::avoidance_t& m) {
  const std::string what = "avoidance_t: ";
  const std::optional<AvoidState> state = AvoidStateFromWire(m.state);
  Require(state == AvoidState::kClear || state == AvoidState::kAvoiding || state == AvoidState::kNoPath,
          what + "state " + std::to_string(m.state) + " is not one the planner sends (clear, avoiding, no path)");
  Require(m.num_path >= 0 && m.num_path <= uavmsg::avoidance_t::MAX_PATH,
          what + "num_path " + std::to_string(m.num_path) + " outside 0.." + std::to_string(uavmsg::avoidance_t::MAX_PATH));
  const auto n_path = static_cast<std::size_t>(m.num_path);
  Require(m.path_north_m.size() == n_path && m.path_east_m.size() == n_path && m.path_down_m.size() == n_path,
          what + "path arrays do not match num_path");
  Require(m.num_cells >= 0 && m.num_cells <= uavmsg::avoidance_t::MAX_CELLS,
          what + "num_cells " + std::to_string(m.num_cells) + " outside 0.." + std::to_string(uavmsg::avoidance_t::MAX_CELLS));
  const auto n_cells = static_cast<std::size_t>(m.num_cells);
  Require(m.cell_north_cm.size() == n_cells && m.cell_east_cm.size() == n_cells && m.cell_down_cm.size() == n_cells,
          what + "cell arrays do not match num_cells");
  Require(Finite({m.goal_north_m, m.goal_east_m, m.goal_down_m, m.origin_north_m, m.origin_east_m, m.origin_down_m}),
          what + "goal or origin is not finite");
  Require(std::isfinite(m.seen_free_m) && m.seen_free_m >= 0, what + "seen_free_m is not a finite non-negative length");
  Require(std::isfinite(m.planning_ms) && m.planning_ms >= 0, what + "planning_ms is not a finite non-negative time");
  Require(m.map_cells >= 0, what + "map_cells is negative");
  Require(std::isfinite(m.cell_m) && m.cell_m >= 0.05f && m.cell_m <= 2.0f, what + "cell_m is not in 0.05..2 m");
  AvoidanceReport r;
  r.utime = m.utime;
  r.state = *state;
  r.reason = m.reason;
  r.goal_N = Eigen::Vector3d(m.goal_north_m, m.goal_east_m, m.goal_down_m);
  for (std::size_t i = 0; i < n_path; ++i) {
    Require(Finite({m.path_north_m[i], m.path_east_m[i], m.path_down_m[i]}), what + "path point " + std::to_string(i) + " is not finite");
    r.path_N.emplace_back(m.path_north_m[i], m.path_east_m[i], m.path_down_m[i]);
  }
  r.seen_free_m = m.seen_free_m;
  r.planning_ms = m.planning_ms;
  r.map_cells = m.map_cells;
  r.origin_N = Eigen::Vector3d(m.origin_north_m, m.origin_east_m, m.origin_down_m);
  r.cell_m = m.cell_m;
  r.occupied_N = FromCentimetres(m.origin_north_m, m.origin_east_m, m.origin_down_m, m.cell_north_cm, m.cell_east_cm, m.cell_down_cm);
  return r;
}

uavmsg::avoidance_t ToMessage(const AvoidanceReport& r) {
  uavmsg::avoidance_t m;
  m.utime = r.utime;
  m.state = static_cast<int8_t>(r.state);
  m.reason = r.reason;
  m.goal_north_m = static_cast<float>(r.goal_N.x());
  m.goal_east_m = static_cast<float>(r.goal_N.y());
  m.goal_down_m = static_cast<float>(r.goal_N.z());
  for (std::size_t i = 0; i < r.path_N.size() && i < static_cast<std::size_t>(uavmsg::avoidance_t::MAX_PATH); ++i) {
    m.path_north_m.push_back(static_cast<float>(r.path_N[i].x()));
    m.path_east_m.push_back(static_cast<float>(r.path_N[i].y()));
    m.path_down_m.push_back(static_cast<float>(r.path_N[i].z()));
  }
  m.num_path = static_cast<int16_t>(m.path_north_m.size());
  m.seen_free_m = static_cast<float>(r.seen_free_m);
  m.planning_ms = static_cast<float>(r.planning_ms);
  m.map_cells = static_cast<int32_t>(std::min<int64_t>(r.map_cells, INT32_MAX));
  m.origin_north_m = static_cast<float>(r.origin_N.x());
  m.origin_east_m = static_cast<float>(r.origin_N.y());
  m.origin_down_m = static_cast<float>(r.origin_N.z());
  m.cell_m = static_cast<float>(r.cell_m);
  Centimetres cm;
  for (const Eigen::Vector3f& c : r.occupied_N) {
    if (cm.north.size() >= static_cast<std::size_t>(uavmsg::avoidance_t::MAX_CELLS)) break;
    cm.Add(c, r.origin_N.cast<float>());
  }
  m.cell_north_cm = std::move(cm.north);
  m.cell_east_cm = std::move(cm.east);
  m.cell_down_cm = std::move(cm.down);
  m.num_cells = static_cast<int32_t>(m.cell_north_cm.size());
  return m;
}

}  // namespace uav
