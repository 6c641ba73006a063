#include "uav/wire/messages.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "uavmsg/active_stereo_t.hpp"

namespace uav {
namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("active_stereo_t: " + what);
}
bool Finite(float x) { return std::isfinite(x); }
}  // namespace

ActiveStereoReport FromMessage(const uavmsg::active_stereo_t& m) {
  using M = uavmsg::active_stereo_t;
  Require(m.num_points >= 0 && m.num_points <= M::MAX_POINTS, "num_points " + std::to_string(m.num_points) + " is not 0.." + std::to_string(M::MAX_POINTS));
  Require(m.num_clusters >= 0 && m.num_clusters <= M::MAX_CLUSTERS, "num_clusters " + std::to_string(m.num_clusters) + " is not 0.." + std::to_string(M::MAX_CLUSTERS));
  const std::size_t n = static_cast<std::size_t>(m.num_points), k = static_cast<std::size_t>(m.num_clusters);
  Require(m.u.size() == n && m.v.size() == n && m.down_m.size() == n && m.cluster.size() == n, "point arrays do not have num_points entries");
  Require(m.cluster_x_m.size() == k && m.cluster_y_m.size() == k && m.cluster_z_m.size() == k && m.cluster_down_m.size() == k &&
              m.cluster_spread_m.size() == k && m.cluster_points.size() == k && m.cluster_ground.size() == k,
          "cluster arrays do not have num_clusters entries");
  Require(Finite(m.height_m) && Finite(m.height_sigma_m) && m.height_sigma_m >= 0, "height or its sigma is not finite");
  Require(m.left_dots >= 0 && m.right_dots >= 0 && m.ambiguous >= 0, "negative dot counts");
  Require(m.healthy ? m.height_m > 0 : m.height_m == 0 && n == 0, m.healthy ? "healthy without a positive height" : "unhealthy report carries a height or points");
  ActiveStereoReport r;
  r.utime = m.utime;
  r.camera = m.camera;
  r.healthy = m.healthy;
  r.reason = m.reason;
  r.height_m = m.height_m;
  r.height_sigma_m = m.height_sigma_m;
  r.left_dots = m.left_dots;
  r.right_dots = m.right_dots;
  r.ambiguous = m.ambiguous;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string at = "point " + std::to_string(i) + ": ";
    Require(Finite(m.u[i]) && Finite(m.v[i]) && Finite(m.down_m[i]), at + "a value is not finite");
    Require(m.cluster[i] >= 0 && static_cast<std::size_t>(m.cluster[i]) < k, at + "cluster " + std::to_string(m.cluster[i]) + " does not exist");
    r.dots.push_back({m.u[i], m.v[i], m.down_m[i], m.cluster[i]});
  }
  for (std::size_t j = 0; j < k; ++j) {
    Require(Finite(m.cluster_x_m[j]) && Finite(m.cluster_y_m[j]) && Finite(m.cluster_z_m[j]) && Finite(m.cluster_down_m[j]) &&
                Finite(m.cluster_spread_m[j]) && m.cluster_spread_m[j] >= 0 && m.cluster_points[j] >= 0,
            "cluster " + std::to_string(j) + ": a value is not finite or is negative");
    DotCluster c;
    c.centre_B = Eigen::Vector3d(m.cluster_x_m[j], m.cluster_y_m[j], m.cluster_z_m[j]);
    c.down_m = m.cluster_down_m[j];
    c.spread_m = m.cluster_spread_m[j];
    c.points = m.cluster_points[j];
    c.ground = m.cluster_ground[j];
    r.clusters.push_back(c);
  }
  return r;
}

uavmsg::active_stereo_t ToMessage(const ActiveStereoReport& r) {
  using M = uavmsg::active_stereo_t;
  uavmsg::active_stereo_t m{};
  m.utime = r.utime;
  m.camera = r.camera;
  m.healthy = r.healthy;
  m.reason = r.reason;
  m.height_m = static_cast<float>(r.height_m);
  m.height_sigma_m = static_cast<float>(r.height_sigma_m);
  m.left_dots = static_cast<int16_t>(std::min(r.left_dots, 32767));
  m.right_dots = static_cast<int16_t>(std::min(r.right_dots, 32767));
  m.ambiguous = static_cast<int16_t>(std::min(r.ambiguous, 32767));
  const std::size_t n = std::min<std::size_t>(r.dots.size(), M::MAX_POINTS);
  const std::size_t k = std::min<std::size_t>(r.clusters.size(), M::MAX_CLUSTERS);
  for (std::size_t i = 0; i < n; ++i) {
    if (static_cast<std::size_t>(r.dots[i].cluster) >= k) continue;
    m.u.push_back(static_cast<float>(r.dots[i].u));
    m.v.push_back(static_cast<float>(r.dots[i].v));
    m.down_m.push_back(static_cast<float>(r.dots[i].down_m));
    m.cluster.push_back(static_cast<int8_t>(r.dots[i].cluster));
  }
  m.num_points = static_cast<int16_t>(m.u.size());
  m.num_clusters = static_cast<int8_t>(k);
  for (std::size_t j = 0; j < k; ++j) {
    const DotCluster& c = r.clusters[j];
    m.cluster_x_m.push_back(static_cast<float>(c.centre_B.x()));
    m.cluster_y_m.push_back(static_cast<float>(c.centre_B.y()));
    m.cluster_z_m.push_back(static_cast<float>(c.centre_B.z()));
    m.cluster_down_m.push_back(static_cast<float>(c.down_m));
    m.cluster_spread_m.push_back(static_cast<float>(c.spread_m));
    m.cluster_points.push_back(static_cast<int16_t>(std::min(c.points, 32767)));
    m.cluster_ground.push_back(c.ground);
  }
  return m;
}

}  // namespace uav
