// Scene geometry: building the world and exact ray intersections.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "scene_impl.hpp"

namespace uav::world {

namespace {

void RequireFinite(const Eigen::Vector3d& v, const std::string& what) {
  if (!v.allFinite()) throw std::invalid_argument(what + " must be finite");
}
void RequirePositive(double v, const std::string& what) {
  if (!(std::isfinite(v) && v > 0.0)) throw std::invalid_argument(what + " must be positive and finite");
}

double Smoothstep(double a, double b, double x) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Catenary parameter a for a level span L with mid-span sag: sag = a (cosh(L / 2a) - 1).
double CatenaryParameter(double span, double sag) {
  double lo = 1e-3, hi = 1e9;  // sag decreases as a grows
  for (int i = 0; i < 200; ++i) {
    const double mid = std::sqrt(lo * hi);
    const double s = mid * (std::cosh(std::min(span / (2 * mid), 700.0)) - 1.0);
    (s > sag ? lo : hi) = mid;
  }
  return std::sqrt(lo * hi);
}

}  // namespace

// ---- Cable, chessboard ------------------------------------------------------------------------

Eigen::Vector3d Cable::PointAt(double s) const {
  // The level-span catenary's drop below the chord, added to the chord (exact for level spans;
  // for unequal heights this is the usual inclined-span approximation).
  const Eigen::Vector3d chord = b_N - a_N;
  const double span = chord.head<2>().norm();
  const double x = s * span - span / 2;
  const double drop = sag_m <= 0 ? 0.0 : catenary_a * (std::cosh(span / (2 * catenary_a)) - std::cosh(x / catenary_a));
  return a_N + s * chord + Eigen::Vector3d(0, 0, drop);
}

double Cable::Distance(const Eigen::Vector3d& p_N) const {
  const std::vector<Eigen::Vector3d>& pts = curve_N;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i + 1 < pts.size(); ++i) {
    const Eigen::Vector3d ab = pts[i + 1] - pts[i];
    const double t = std::clamp((p_N - pts[i]).dot(ab) / std::max(ab.squaredNorm(), 1e-12), 0.0, 1.0);
    best = std::min(best, (pts[i] + t * ab - p_N).norm() - radius_m);
  }
  return std::max(0.0, best);
}

std::vector<Eigen::Vector3d> Cable::Sample(int n) const {
  std::vector<Eigen::Vector3d> out;
  n = std::max(n, 2);
  for (int i = 0; i < n; ++i) out.push_back(PointAt(static_cast<double>(i) / (n - 1)));
  return out;
}

std::vector<Eigen::Vector3d> Chessboard::CornersInBoard() const {
  std::vector<Eigen::Vector3d> out;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c) out.emplace_back(c * square_m, r * square_m, 0.0);
  return out;
}

// ---- Intersections ----------------------------------------------------------------------------

bool IntersectPrimitive(const Primitive& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        double t_min, double pixel_angle, SurfaceHit* hit) {
  switch (p.shape) {
    case Shape::kBox:
    case Shape::kRoom: {
      const Eigen::Vector3d w = o - p.c;
      const double lo[3] = {p.cos_yaw * w.x() + p.sin_yaw * w.y(), -p.sin_yaw * w.x() + p.cos_yaw * w.y(), w.z()};
      const double ld[3] = {p.cos_yaw * d.x() + p.sin_yaw * d.y(), -p.sin_yaw * d.x() + p.cos_yaw * d.y(), d.z()};
      double t_near = -1e300, t_far = 1e300;
      int axis_near = -1, axis_far = -1;
      for (int i = 0; i < 3; ++i) {
        if (std::abs(ld[i]) < 1e-15) {
          if (std::abs(lo[i]) > p.h[i]) return false;
          continue;
        }
        double t1 = (-p.h[i] - lo[i]) / ld[i], t2 = (p.h[i] - lo[i]) / ld[i];
        if (t1 > t2) std::swap(t1, t2);
        if (t1 > t_near) { t_near = t1; axis_near = i; }
        if (t2 < t_far) { t_far = t2; axis_far = i; }
      }
      if (t_near > t_far) return false;
      double t;
      int axis;
      if (p.shape == Shape::kBox) {
        t = t_near;
        axis = axis_near;
      } else {
        t = t_far;  // seen from inside
        axis = axis_far;
      }
      if (!(t > t_min && t < hit->t) || axis < 0) return false;
      double nl[3] = {0, 0, 0};
      nl[axis] = ld[axis] > 0 ? -1.0 : 1.0;  // facing the ray
      const double px = lo[0] + t * ld[0], py = lo[1] + t * ld[1], pz = lo[2] + t * ld[2];
      hit->t = t;
      hit->normal = Eigen::Vector3d(p.cos_yaw * nl[0] - p.sin_yaw * nl[1], p.sin_yaw * nl[0] + p.cos_yaw * nl[1], nl[2]);
      if (axis == 0) { hit->u = py; hit->v = pz; }
      else if (axis == 1) { hit->u = px; hit->v = pz; }
      else { hit->u = px; hit->v = py; }
      hit->material = (axis == 2 && nl[2] < 0) ? p.top_material : p.material;
      hit->object_id = p.object_id;
      hit->coverage = 1.0f;
      return true;
    }
    case Shape::kCylinder: {
      const double z_bottom = p.c.z(), z_top = p.c.z() - p.height;  // NED: up is -d
      double best = hit->t;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      double u = 0, v = 0;
      const double wx = o.x() - p.c.x(), wy = o.y() - p.c.y();
      const double a = d.x() * d.x() + d.y() * d.y();
      if (a > 1e-18) {
        const double b = wx * d.x() + wy * d.y();
        const double c = wx * wx + wy * wy - p.radius * p.radius;
        const double disc = b * b - a * c;
        if (disc >= 0) {
          const double sq = std::sqrt(disc);
          for (double t : {(-b - sq) / a, (-b + sq) / a}) {
            if (t > t_min && t < best) {
              const double z = o.z() + t * d.z();
              if (z <= z_bottom && z >= z_top) {
                best = t;
                const double nx = (wx + t * d.x()) / p.radius, ny = (wy + t * d.y()) / p.radius;
                normal = Eigen::Vector3d(nx, ny, 0);
                u = TextureAtan2(ny, nx) * p.radius;
                v = z;
                break;
              }
            }
          }
        }
      }
      if (std::abs(d.z()) > 1e-18) {
        for (double zc : {z_top, z_bottom}) {
          const double t = (zc - o.z()) / d.z();
          if (t > t_min && t < best) {
            const double x = wx + t * d.x(), y = wy + t * d.y();
            if (x * x + y * y <= p.radius * p.radius) {
              best = t;
              normal = Eigen::Vector3d(0, 0, zc == z_top ? -1.0 : 1.0);
              u = x;
              v = y;
            }
          }
        }
      }
      if (!(best < hit->t)) return false;
      hit->t = best;
      hit->normal = normal;
      hit->u = u;
      hit->v = v;
      hit->material = p.material;
      hit->object_id = p.object_id;
      hit->coverage = 1.0f;
      return true;
    }
    case Shape::kSphere: {
      const Eigen::Vector3d w = o - p.c;
      const double a = d.squaredNorm(), b = w.dot(d), c = w.squaredNorm() - p.radius * p.radius;
      const double disc = b * b - a * c;
      if (disc < 0) return false;
      const double sq = std::sqrt(disc);
      double t = (-b - sq) / a;
      if (!(t > t_min)) t = (-b + sq) / a;
      if (!(t > t_min && t < hit->t)) return false;
      const Eigen::Vector3d n = (w + t * d) / p.radius;
      hit->t = t;
      hit->normal = n;
      hit->u = TextureAtan2(n.y(), n.x()) * p.radius;
      hit->v = TextureAtan2(n.z(), std::sqrt(std::max(0.0, 1.0 - n.z() * n.z()))) * p.radius;  // asin
      hit->material = p.material;
      hit->object_id = p.object_id;
      hit->coverage = 1.0f;
      return true;
    }
    case Shape::kCable: {
      // Closest approach between the ray and the segment c .. c + h.
      const Eigen::Vector3d w = o - p.c;
      const double A = d.squaredNorm(), B = d.dot(p.h), C = p.h.squaredNorm(), D = d.dot(w), E = p.h.dot(w);
      const double den = A * C - B * B;
      double q = den > 1e-18 ? (A * E - B * D) / den : 0.0;
      q = std::clamp(q, 0.0, 1.0);
      const double s = (q * B - D) / A;
      if (!(s > t_min && s < hit->t)) return false;
      const Eigen::Vector3d gap = w + s * d - q * p.h;
      const double dist = gap.norm();
      const double half_pixel = 0.5 * pixel_angle * s * std::sqrt(A);
      const double reach = std::max(p.radius, half_pixel);
      if (dist >= reach) return false;
      float coverage = 1.0f;
      double t = s;
      if (half_pixel > p.radius) {
        coverage = static_cast<float>(p.radius / half_pixel);  // thinner than a pixel: faint
      } else {
        t = s - std::sqrt(std::max(0.0, p.radius * p.radius - dist * dist) / A);
        if (!(t > t_min)) return false;
      }
      hit->t = t;
      hit->normal = dist > 1e-12 ? Eigen::Vector3d(gap / dist) : Eigen::Vector3d(-d.normalized());
      hit->u = q;
      hit->v = 0;
      hit->material = p.material;
      hit->object_id = p.object_id;
      hit->coverage = coverage;
      return true;
    }
    case Shape::kBoard: {
      const Eigen::Vector3d n = p.R.col(2);
      const double dn = d.dot(n);
      if (std::abs(dn) < 1e-15) return false;
      const double t = (p.c - o).dot(n) / dn;
      if (!(t > t_min && t < hit->t)) return false;
      const Eigen::Vector3d q = o + t * d - p.c;
      const double x = q.dot(p.R.col(0)), y = q.dot(p.R.col(1));
      // h holds the board's extent: x in [h.x, h.y], y in [h.z, radius] (see AddChessboard).
      if (x < p.h.x() || x > p.h.y() || y < p.h.z() || y > p.height) return false;
      hit->t = t;
      hit->normal = n;
      hit->u = x;
      hit->v = y;
      hit->material = kBoardMaterial;
      hit->object_id = p.object_id;
      hit->coverage = 1.0f;
      return true;
    }
  }
  return false;
}

// ---- Scene::Impl -----------------------------------------------------------------------------

int Scene::Impl::Material(const std::string& material_name) {
  for (size_t i = 0; i < material_names.size(); ++i)
    if (material_names[i] == material_name) return static_cast<int>(i);
  textures.push_back(MakeMaterialTexture(material_name, seed));  // throws for unknown names
  material_names.push_back(material_name);
  return static_cast<int>(material_names.size()) - 1;
}

void Scene::Impl::AddPrimitive(Primitive p) {
  switch (p.shape) {
    case Shape::kBox:
    case Shape::kRoom: {
      const double ex = std::abs(p.cos_yaw) * p.h.x() + std::abs(p.sin_yaw) * p.h.y();
      const double ey = std::abs(p.sin_yaw) * p.h.x() + std::abs(p.cos_yaw) * p.h.y();
      p.box_lo = p.c - Eigen::Vector3d(ex, ey, p.h.z());
      p.box_hi = p.c + Eigen::Vector3d(ex, ey, p.h.z());
      break;
    }
    case Shape::kCylinder:
      p.box_lo = p.c - Eigen::Vector3d(p.radius, p.radius, p.height);
      p.box_hi = p.c + Eigen::Vector3d(p.radius, p.radius, 0);
      break;
    case Shape::kSphere:
      p.box_lo = p.c - Eigen::Vector3d::Constant(p.radius);
      p.box_hi = p.c + Eigen::Vector3d::Constant(p.radius);
      break;
    case Shape::kCable:
      p.box_lo = p.c.cwiseMin(p.c + p.h) - Eigen::Vector3d::Constant(p.radius);
      p.box_hi = p.c.cwiseMax(p.c + p.h) + Eigen::Vector3d::Constant(p.radius);
      break;
    case Shape::kBoard: {
      p.box_lo = Eigen::Vector3d::Constant(1e300);
      p.box_hi = Eigen::Vector3d::Constant(-1e300);
      for (double x : {p.h.x(), p.h.y()})
        for (double y : {p.h.z(), p.height}) {
          const Eigen::Vector3d q = p.c + x * p.R.col(0) + y * p.R.col(1);
          p.box_lo = p.box_lo.cwiseMin(q);
          p.box_hi = p.box_hi.cwiseMax(q);
        }
      break;
    }
  }
  prims.push_back(p);
}

double Scene::Impl::CloudLight(double n, double e, double t_s) const {
  if (!clouds.enabled) return 1.0;
  const double x = (n - clouds.velocity_NE.x() * t_s) / clouds.scale_m;
  const double y = (e - clouds.velocity_NE.y() * t_s) / clouds.scale_m;
  const double v = 0.65 * ValueNoise2(x, y, seed) + 0.35 * ValueNoise2(2.03 * x + 17.1, 2.03 * y - 5.3, seed + 1);
  return 1.0 - clouds.darkness * Smoothstep(cloud_threshold - 0.03, cloud_threshold + 0.03, v);
}

ObjectPlacement Mover::At(double t_s) const {
  ObjectPlacement out;
  const double total = cumulative.back();
  double along = std::max(0.0, t_s - path.start_s) * path.speed_mps;
  bool backwards = false;
  if (path.loop) {
    along = std::fmod(along, total);
  } else {
    along = std::fmod(along, 2 * total);
    if (along > total) along = 2 * total - along, backwards = true;
  }
  std::size_t leg = 0;
  while (leg + 2 < points.size() && cumulative[leg + 1] <= along) ++leg;
  const Eigen::Vector2d a = points[leg], b = points[leg + 1];
  const double length = cumulative[leg + 1] - cumulative[leg];
  const Eigen::Vector2d p = a + (b - a) * std::clamp((along - cumulative[leg]) / length, 0.0, 1.0);
  Eigen::Vector2d dir = (b - a) / length;
  if (backwards) dir = -dir;
  out.base_N = Eigen::Vector3d(p.x(), p.y(), base_N.z());
  out.heading_rad = std::atan2(dir.y(), dir.x());
  out.velocity_NE = t_s >= path.start_s ? Eigen::Vector2d(dir * path.speed_mps) : Eigen::Vector2d::Zero();
  return out;
}

Eigen::Isometry3d Mover::Motion(double t_s) const {
  const Eigen::Vector2d first = points[1] - points[0];
  const ObjectPlacement now = At(t_s);
  const double yaw = now.heading_rad - std::atan2(first.y(), first.x());
  // x = R (x0 - base) + now.base: turn about the declared footprint centre, then move.
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  T.translation() = now.base_N - T.linear() * base_N;
  return T;
}

PrimitiveMotions Scene::Impl::MotionsAt(double t_s) const {
  PrimitiveMotions m;
  if (movers.empty()) return m;
  std::vector<Eigen::Isometry3d> per_mover;
  for (const Mover& mv : movers) per_mover.push_back(mv.Motion(t_s));
  m.T_N_declared.assign(prims.size(), Eigen::Isometry3d::Identity());
  m.T_declared_N.assign(prims.size(), Eigen::Isometry3d::Identity());
  for (std::size_t i = 0; i < prims.size(); ++i)
    if (prims[i].mover >= 0) {
      m.T_N_declared[i] = per_mover[static_cast<std::size_t>(prims[i].mover)];
      m.T_declared_N[i] = m.T_N_declared[i].inverse();
    }
  return m;
}

// ---- Scene ------------------------------------------------------------------------------------

Scene::Scene(uint64_t seed) : impl_(std::make_unique<Impl>()) {
  impl_->seed = seed;
  impl_->ground.enabled = false;
  impl_->macro = MakeMacroTexture(seed);
  impl_->ComputeCloudThreshold();
}
Scene::~Scene() = default;
Scene::Scene(Scene&&) noexcept = default;
Scene& Scene::operator=(Scene&&) noexcept = default;

uint64_t Scene::seed() const { return impl_->seed; }
const std::string& Scene::name() const { return impl_->name; }
void Scene::SetName(const std::string& name) { impl_->name = name; }

void Scene::SetGround(const GroundSpec& g) {
  Impl& s = *impl_;
  if (g.layout == GroundSpec::Layout::kFields) {
    if (g.parcel_materials.empty()) throw std::invalid_argument("ground: parcel_materials must not be empty");
    RequirePositive(g.parcel_m, "ground parcel_m");
    if (!(std::isfinite(g.road_width_m) && g.road_width_m >= 0 && g.road_width_m < g.parcel_m))
      throw std::invalid_argument("ground road_width_m must be in [0, parcel_m)");
    if (g.road_every < 0) throw std::invalid_argument("ground road_every must be >= 0");
    if (!std::isfinite(g.grid_yaw)) throw std::invalid_argument("ground grid_yaw must be finite");
  }
  s.ground = g;
  s.grid_cos = std::cos(g.grid_yaw);
  s.grid_sin = std::sin(g.grid_yaw);
  s.inv_parcel = 1.0 / g.parcel_m;
  s.inv_road_every = g.road_every > 0 ? 1.0 / g.road_every : 0.0;
  s.ground_material = s.Material(g.layout == GroundSpec::Layout::kUniform ? g.material : "asphalt");
  s.road_material = s.Material("asphalt");
  s.parcel_materials.clear();
  for (const auto& m : g.parcel_materials) s.parcel_materials.push_back(s.Material(m));
}

void Scene::SetSun(const SunLight& sun) {
  if (!(sun.to_sun_N.allFinite() && sun.to_sun_N.norm() > 1e-9))
    throw std::invalid_argument("sun direction must be finite and non-zero");
  if (!(sun.ambient >= 0 && sun.ambient <= 1)) throw std::invalid_argument("sun ambient must be in [0, 1]");
  impl_->sun = sun;
  impl_->sun.to_sun_N.normalize();
}

void Scene::SetClouds(const CloudShadows& c) {
  if (c.enabled) {
    if (!(c.coverage >= 0 && c.coverage <= 1)) throw std::invalid_argument("clouds coverage must be in [0, 1]");
    if (!(c.darkness >= 0 && c.darkness <= 1)) throw std::invalid_argument("clouds darkness must be in [0, 1]");
    RequirePositive(c.scale_m, "clouds scale_m");
    if (!c.velocity_NE.allFinite()) throw std::invalid_argument("clouds velocity must be finite");
  }
  impl_->clouds = c;
  impl_->ComputeCloudThreshold();
}

void Scene::Impl::ComputeCloudThreshold() {
  // The noise is not uniform: find the level that `coverage` of the ground exceeds.
  std::vector<double> v;
  for (int i = 0; i < 4096; ++i) {
    const double x = Unit(SplitMix64(seed + 2 * i)) * 1000, y = Unit(SplitMix64(seed + 2 * i + 1)) * 1000;
    v.push_back(0.65 * ValueNoise2(x, y, seed) + 0.35 * ValueNoise2(2.03 * x + 17.1, 2.03 * y - 5.3, seed + 1));
  }
  std::sort(v.begin(), v.end());
  const double q = std::clamp(1.0 - clouds.coverage, 0.0, 1.0);
  cloud_threshold = v[std::min<size_t>(v.size() - 1, static_cast<size_t>(q * v.size()))];
  if (clouds.coverage <= 0) cloud_threshold = 2.0;
}

void Scene::SetSky(bool visible) { impl_->sky = visible; }
bool Scene::sky() const { return impl_->sky; }

int Scene::AddBox(const std::string& kind, const Eigen::Vector3d& center_N, const Eigen::Vector3d& size,
                  double yaw, const std::string& material, const std::string& top_material) {
  RequireFinite(center_N, kind + " centre");
  RequirePositive(size.minCoeff(), kind + " size");
  RequireFinite(size, kind + " size");
  if (!std::isfinite(yaw)) throw std::invalid_argument(kind + " yaw must be finite");
  Impl& s = *impl_;
  Primitive p;
  p.shape = Shape::kBox;
  p.object_id = s.next_id++;
  p.material = s.Material(material);
  p.top_material = s.Material(top_material.empty() ? material : top_material);
  p.c = center_N;
  p.h = size / 2;
  p.cos_yaw = std::cos(yaw);
  p.sin_yaw = std::sin(yaw);
  s.AddPrimitive(p);
  Obstacle o;
  o.id = p.object_id;
  o.kind = kind;
  o.base_N = center_N + Eigen::Vector3d(0, 0, size.z() / 2);
  o.height = size.z();
  o.size = size;
  o.yaw = yaw;
  o.radius = size.head<2>().norm() / 2;
  s.obstacles.push_back(o);
  return p.object_id;
}

void Scene::Impl::AddCylinderPrimitive(int id, const Eigen::Vector3d& base_N, double radius, double height,
                                       const std::string& material_name) {
  Primitive p;
  p.shape = Shape::kCylinder;
  p.object_id = id;
  p.material = Material(material_name);
  p.c = base_N;
  p.radius = radius;
  p.height = height;
  AddPrimitive(p);
}

void Scene::Impl::AddSpherePrimitive(int id, const Eigen::Vector3d& center_N, double radius,
                                     const std::string& material_name) {
  Primitive p;
  p.shape = Shape::kSphere;
  p.object_id = id;
  p.material = Material(material_name);
  p.c = center_N;
  p.radius = radius;
  AddPrimitive(p);
}

void Scene::Impl::AddRoundObstacle(int id, const std::string& kind, const Eigen::Vector3d& base_N, double radius,
                                   double height) {
  Obstacle o;
  o.id = id;
  o.kind = kind;
  o.base_N = base_N;
  o.radius = radius;
  o.height = height;
  obstacles.push_back(o);
}

int Scene::AddCylinder(const std::string& kind, const Eigen::Vector3d& base_N, double radius,
                       double height, const std::string& material) {
  RequireFinite(base_N, kind + " base");
  RequirePositive(radius, kind + " radius");
  RequirePositive(height, kind + " height");
  Impl& s = *impl_;
  const int id = s.next_id++;
  s.AddCylinderPrimitive(id, base_N, radius, height, material);
  s.AddRoundObstacle(id, kind, base_N, radius, height);
  return id;
}

int Scene::AddSphere(const std::string& kind, const Eigen::Vector3d& center_N, double radius,
                     const std::string& material) {
  RequireFinite(center_N, kind + " centre");
  RequirePositive(radius, kind + " radius");
  Impl& s = *impl_;
  const int id = s.next_id++;
  s.AddSpherePrimitive(id, center_N, radius, material);
  s.AddRoundObstacle(id, kind, center_N + Eigen::Vector3d(0, 0, radius), radius, 2 * radius);
  return id;
}

int Scene::AddTree(const Eigen::Vector3d& base_N, double height, double crown_radius) {
  RequireFinite(base_N, "tree base");
  RequirePositive(height, "tree height");
  RequirePositive(crown_radius, "tree crown_radius");
  if (!(2 * crown_radius < height)) throw std::invalid_argument("tree crown diameter must be below its height");
  Impl& s = *impl_;
  const int id = s.next_id++;
  s.AddCylinderPrimitive(id, base_N, std::max(0.08, 0.06 * crown_radius), height - crown_radius, "bark");
  s.AddSpherePrimitive(id, base_N - Eigen::Vector3d(0, 0, height - crown_radius), crown_radius, "foliage");
  s.AddRoundObstacle(id, "tree", base_N, crown_radius, height);
  return id;
}

int Scene::AddPerson(const Eigen::Vector3d& base_N, double height, const std::string& clothing) {
  RequireFinite(base_N, "person base");
  if (!(height >= 1.0 && height <= 2.3)) throw std::invalid_argument("person height must be 1.0..2.3 m");
  Impl& s = *impl_;
  const int id = s.next_id++;
  const double head = 0.11 * height / 1.75;
  s.AddCylinderPrimitive(id, base_N, 0.2, height - 2.2 * head, clothing);
  s.AddSpherePrimitive(id, base_N - Eigen::Vector3d(0, 0, height - head), head, "soil");
  s.AddRoundObstacle(id, "person", base_N, 0.2, height);
  return id;
}

int Scene::AddRoom(const Eigen::Vector3d& center_N, const Eigen::Vector3d& size, const std::string& material,
                   const std::string& floor_material) {
  RequireFinite(center_N, "room centre");
  RequirePositive(size.minCoeff(), "room size");
  Impl& s = *impl_;
  Primitive p;
  p.shape = Shape::kRoom;
  p.object_id = s.next_id++;
  p.material = s.Material(material);
  p.top_material = s.Material(floor_material.empty() ? material : floor_material);  // seen from inside, the top face is the floor
  p.c = center_N;
  p.h = size / 2;
  s.AddPrimitive(p);
  return p.object_id;
}

int Scene::AddCable(const Eigen::Vector3d& a_N, const Eigen::Vector3d& b_N, double sag_m, double radius_m) {
  RequireFinite(a_N, "cable end a");
  RequireFinite(b_N, "cable end b");
  RequirePositive(radius_m, "cable radius");
  const double span = (b_N - a_N).head<2>().norm();
  if (!(span > 0.5)) throw std::invalid_argument("cable span must be more than 0.5 m horizontally");
  if (!(std::isfinite(sag_m) && sag_m >= 0 && sag_m < span / 2))
    throw std::invalid_argument("cable sag must be in [0, span/2)");
  Impl& s = *impl_;
  Cable c;
  c.id = s.next_id++;
  c.a_N = a_N;
  c.b_N = b_N;
  c.sag_m = sag_m;
  c.radius_m = radius_m;
  c.catenary_a = sag_m > 0 ? CatenaryParameter(span, sag_m) : 0.0;
  c.curve_N = c.Sample(64);
  // Rendered as a chain of straight pieces; 64 pieces put the chord within sag/1000 of the curve.
  constexpr int kPieces = 64;
  const int material = s.Material("dark");
  Eigen::Vector3d prev = c.PointAt(0);
  for (int i = 1; i <= kPieces; ++i) {
    const Eigen::Vector3d next = c.PointAt(static_cast<double>(i) / kPieces);
    Primitive p;
    p.shape = Shape::kCable;
    p.object_id = c.id;
    p.material = material;
    p.c = prev;
    p.h = next - prev;
    p.radius = radius_m;
    s.AddPrimitive(p);
    prev = next;
  }
  s.cables.push_back(c);
  return c.id;
}

int Scene::AddChessboard(int cols, int rows, double square_m, const Eigen::Isometry3d& T_N_board) {
  if (cols < 2 || cols > 50 || rows < 2 || rows > 50)
    throw std::invalid_argument("chessboard needs 2..50 inner corners per side");
  RequirePositive(square_m, "chessboard square");
  if (!T_N_board.matrix().allFinite()) throw std::invalid_argument("chessboard pose must be finite");
  Impl& s = *impl_;
  Chessboard b;
  b.id = s.next_id++;
  b.cols = cols;
  b.rows = rows;
  b.square_m = square_m;
  b.T_N_board = T_N_board;
  Primitive p;
  p.shape = Shape::kBoard;
  p.object_id = b.id;
  p.material = kBoardMaterial;
  p.c = T_N_board.translation();
  p.R = T_N_board.linear();
  // Extent in board coordinates: one square of checkers beyond the corners plus a white margin.
  p.h = Eigen::Vector3d(-2 * square_m, (cols + 1) * square_m, -2 * square_m);
  p.height = (rows + 1) * square_m;
  p.board = static_cast<int>(s.boards.size());
  s.boards.push_back(b);
  s.AddPrimitive(p);
  return b.id;
}

void Scene::SetPath(int id, const ObjectPath& path) {
  Impl& s = *impl_;
  const auto obstacle = std::find_if(s.obstacles.begin(), s.obstacles.end(), [&](const Obstacle& o) { return o.id == id; });
  if (obstacle == s.obstacles.end())
    throw std::invalid_argument("path: object " + std::to_string(id) + " is not a box, cylinder, sphere or person");
  for (const Mover& m : s.movers)
    if (m.object_id == id) throw std::invalid_argument("path: object " + std::to_string(id) + " already has a path");
  if (path.waypoints_NE.size() < 2) throw std::invalid_argument("path needs at least two waypoints");
  if (!(std::isfinite(path.speed_mps) && path.speed_mps > 0 && path.speed_mps <= 50))
    throw std::invalid_argument("path speed must be in (0, 50] m/s");
  if (!std::isfinite(path.start_s)) throw std::invalid_argument("path start must be finite");
  Mover m;
  m.object_id = id;
  m.path = path;
  m.points = path.waypoints_NE;
  if (path.loop) m.points.push_back(path.waypoints_NE.front());
  m.cumulative.push_back(0.0);
  for (std::size_t i = 1; i < m.points.size(); ++i) {
    if (!m.points[i].allFinite()) throw std::invalid_argument("path waypoint " + std::to_string(i) + " is not finite");
    const double leg = (m.points[i] - m.points[i - 1]).norm();
    if (!(leg > 1e-3)) throw std::invalid_argument("path waypoints " + std::to_string(i - 1) + " and " + std::to_string(i % path.waypoints_NE.size()) + " coincide");
    m.cumulative.push_back(m.cumulative.back() + leg);
  }
  m.base_N = obstacle->base_N;
  for (Primitive& p : s.prims)
    if (p.object_id == id) p.mover = static_cast<int>(s.movers.size());
  s.movers.push_back(std::move(m));
}

std::vector<int> Scene::MovingObjects() const {
  std::vector<int> ids;
  for (const Mover& m : impl_->movers) ids.push_back(m.object_id);
  return ids;
}

ObjectPlacement Scene::PlacementAt(int id, double t_s) const {
  for (const Mover& m : impl_->movers)
    if (m.object_id == id) return m.At(t_s);
  for (const Obstacle& o : impl_->obstacles)
    if (o.id == id) {
      ObjectPlacement p;
      p.base_N = o.base_N;
      p.heading_rad = o.yaw;
      return p;
    }
  throw std::invalid_argument("no object " + std::to_string(id));
}

const std::vector<Obstacle>& Scene::obstacles() const { return impl_->obstacles; }
const std::vector<Cable>& Scene::cables() const { return impl_->cables; }

std::string Scene::Describe(int object_id) const {
  char text[160];
  for (const Cable& c : impl_->cables)
    if (c.id == object_id) {
      std::snprintf(text, sizeof text, "a cable %.1f m long, %.1f-%.1f m high", (c.b_N - c.a_N).norm(), -c.a_N.z(), -c.b_N.z());
      return text;
    }
  for (const Obstacle& o : impl_->obstacles) {
    if (o.id != object_id) continue;
    if (o.size.x() > 0 && o.size.y() > 0)
      std::snprintf(text, sizeof text, "a %s %.1f x %.1f m, %.1f m high, turned %.0f deg, at (%.1f, %.1f)", o.kind.c_str(), o.size.x(),
                    o.size.y(), o.size.z(), o.yaw * 180 / M_PI, o.base_N.x(), o.base_N.y());
    else
      std::snprintf(text, sizeof text, "a %s of radius %.2f m, %.1f m high, at (%.1f, %.1f)", o.kind.c_str(), o.radius, o.height,
                    o.base_N.x(), o.base_N.y());
    return text;
  }
  return "nothing";
}
const std::vector<Chessboard>& Scene::chessboards() const { return impl_->boards; }
const std::optional<CameraSetup>& Scene::downward_camera() const { return impl_->downward; }
const std::optional<StereoSetup>& Scene::stereo_camera() const { return impl_->stereo; }
const std::optional<CameraSetup>& Scene::gimbal_camera() const { return impl_->gimbal; }
void Scene::SetGimbalCamera(const CameraSetup& c) {
  ValidateIntrinsics(c.intrinsics);
  impl_->gimbal = c;
}
void Scene::SetDownwardCamera(const CameraSetup& c) {
  ValidateIntrinsics(c.intrinsics);
  impl_->downward = c;
}
void Scene::SetStereoCamera(const StereoSetup& st) {
  ValidateIntrinsics(st.left.intrinsics);
  impl_->stereo = st;
  impl_->stereo_rigs = {st};
}
void Scene::AddStereoRig(const StereoSetup& st) {
  ValidateIntrinsics(st.left.intrinsics);
  for (const StereoSetup& other : impl_->stereo_rigs)
    if (other.left.name == st.left.name)
      throw std::invalid_argument("two stereo rigs named '" + st.left.name.substr(0, st.left.name.size() - 5) + "'");
  if (!impl_->stereo) impl_->stereo = st;
  impl_->stereo_rigs.push_back(st);
}
const std::vector<StereoSetup>& Scene::stereo_rigs() const { return impl_->stereo_rigs; }

std::optional<RayHit> Scene::Intersect(const Eigen::Vector3d& origin_N, const Eigen::Vector3d& direction_N,
                                       double t_min, double t_max, double t_s) const {
  const Impl& s = *impl_;
  const PrimitiveMotions motions = s.MotionsAt(t_s);
  SurfaceHit hit;
  hit.t = t_max;
  s.IntersectGround(origin_N, direction_N, t_min, &hit);
  for (size_t i = 0; i < s.prims.size(); ++i)
    if (s.IntersectMoved(static_cast<int>(i), motions, origin_N, direction_N, t_min, 0.0, &hit)) hit.prim = static_cast<int>(i);
  if (hit.object_id == kNoObject) return std::nullopt;
  RayHit out;
  out.t = hit.t;
  out.p_N = origin_N + hit.t * direction_N;
  out.normal_N = hit.normal.dot(direction_N) > 0 ? Eigen::Vector3d(-hit.normal) : hit.normal;
  out.object_id = hit.object_id;
  return out;
}

double Scene::Clearance(const Eigen::Vector3d& p_N, double t_s, int* nearest_id) const {
  const Impl& s = *impl_;
  const PrimitiveMotions motions = s.MotionsAt(t_s);
  double best = std::numeric_limits<double>::infinity();
  if (nearest_id) *nearest_id = kNoObject;
  for (size_t i = 0; i < s.prims.size(); ++i) {
    const Primitive& q = s.prims[i];
    const Eigen::Vector3d p = q.mover >= 0 && !motions.T_declared_N.empty() ? Eigen::Vector3d(motions.T_declared_N[i] * p_N) : p_N;
    double d = best;
    switch (q.shape) {
      case Shape::kBox: {
        // Into the box's own axes (yaw about d), then the distance to an axis-aligned box.
        const Eigen::Vector3d r = p - q.c;
        const Eigen::Vector3d local(q.cos_yaw * r.x() + q.sin_yaw * r.y(), -q.sin_yaw * r.x() + q.cos_yaw * r.y(), r.z());
        const Eigen::Vector3d out = (local.cwiseAbs() - q.h).cwiseMax(0.0);
        d = out.norm();
        break;
      }
      case Shape::kRoom: {
        const Eigen::Vector3d inside = q.h - (p - q.c).cwiseAbs();
        d = inside.minCoeff() > 0 ? inside.minCoeff() : 0.0;
        break;
      }
      case Shape::kCylinder: {
        const double radial = std::max(0.0, std::hypot(p.x() - q.c.x(), p.y() - q.c.y()) - q.radius);
        const double top = q.c.z() - q.height;  // down is positive: the top is above the base
        const double vertical = p.z() < top ? top - p.z() : (p.z() > q.c.z() ? p.z() - q.c.z() : 0.0);
        d = std::hypot(radial, vertical);
        break;
      }
      case Shape::kSphere: d = std::max(0.0, (p - q.c).norm() - q.radius); break;
      case Shape::kCable:
      case Shape::kBoard: break;  // cables below, from their catenaries; boards are calibration targets
    }
    if (d < best) {
      best = d;
      if (nearest_id) *nearest_id = q.object_id;
    }
  }
  for (const Cable& c : s.cables)
    if (const double d = c.Distance(p_N); d < best) {
      best = d;
      if (nearest_id) *nearest_id = c.id;
    }
  return std::isfinite(best) ? best : -1.0;
}

}  // namespace uav::world
