#pragma once
// Internal: the scene's primitives, textures and ray intersections, shared by scene.cpp and
// renderer.cpp so the hot loop can inline them. Not installed.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <smmintrin.h>  // SSE4.1: the world library is built for x86-64-v2

#include "uav/world/scene.hpp"

namespace uav::world {

inline uint64_t SplitMix64(uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}
inline uint64_t HashCombine(uint64_t a, uint64_t b) { return SplitMix64(a ^ SplitMix64(b)); }
inline uint64_t HashString(const std::string& s) {
  uint64_t h = 1469598103934665603ull;  // FNV-1a
  for (unsigned char c : s) h = (h ^ c) * 1099511628211ull;
  return h;
}
// Uniform in [0, 1) from a hash.
inline double Unit(uint64_t h) { return (h >> 11) * (1.0 / 9007199254740992.0); }

// floor() without a libm call (the x86-64 baseline has no rounding instruction).
inline int64_t FastFloor(double x) {
  const int64_t i = static_cast<int64_t>(x);
  return i - (static_cast<double>(i) > x);
}

// atan2 for texture coordinates: a degree-11 odd minimax polynomial on [0, 1] with octant
// folding, max error 2e-6 rad (1 um on a 0.3 m trunk, far below a 1 cm texel), without the
// libm call that dominated cylinder shading.
inline double TextureAtan2(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double lo = ax < ay ? ax : ay, hi = ax < ay ? ay : ax;
  if (hi == 0.0) return 0.0;
  const double a = lo / hi, s = a * a;
  double r = ((((-0.0117212 * s + 0.05265332) * s - 0.11643287) * s + 0.19354346) * s - 0.33262347) * s + 0.99997726;
  r *= a;
  if (ay > ax) r = 1.57079632679489662 - r;
  if (x < 0) r = 3.14159265358979324 - r;
  return y < 0 ? -r : r;
}

// A tileable, mip-mapped BGR texture covering size * texel_m metres before it repeats.
struct Texture {
  Texture() = default;
  Texture(Texture&&) = default;  // level_data points into levels, which a move keeps
  Texture& operator=(Texture&&) = default;
  Texture(const Texture&) = delete;

  int size = 0;        // level-0 texels per side, a power of two
  double texel_m = 0.01;
  std::vector<std::vector<uint8_t>> levels;  // BGRx (4 bytes per texel), row-major, size >> level per side
  // Filled by Finish(): per level, texels per metre and the data, so sampling divides nothing.
  double inv_texel = 100.0;
  std::vector<double> level_scale;
  std::vector<const uint8_t*> level_data;
  // Featureless materials (plain walls, dark paint) have one colour: sampling returns it.
  bool uniform = false;
  Eigen::Vector3f uniform_colour = Eigen::Vector3f::Zero();
  void Finish() {
    inv_texel = 1.0 / texel_m;
    uniform = true;
    const std::vector<uint8_t>& base = levels.front();
    for (size_t i = 4; i < base.size() && uniform; ++i) uniform = base[i] == base[i % 4];
    uniform_colour = Eigen::Vector3f(base[0], base[1], base[2]) / 255.0f;
    level_scale.clear();
    level_data.clear();
    for (size_t l = 0; l < levels.size(); ++l) {
      level_scale.push_back(1.0 / (texel_m * (1 << l)));
      level_data.push_back(levels[l].data());
    }
  }

  // Bilinear sample at (u, v) metres from the level whose texel matches `footprint_m` (the
  // pixel's size on the surface); colours in 0..1. Texels are BGRx words so the four taps are
  // four 32-bit loads widened and blended in SSE registers.
  inline Eigen::Vector3f Sample(double u, double v, double footprint_m) const {
    if (uniform) return uniform_colour;
    int level = 0;
    const int top = static_cast<int>(level_data.size()) - 1;
    for (double ratio = footprint_m * inv_texel; ratio >= 2.0 && level < top; ratio *= 0.5) ++level;
    const int n = size >> level;
    const int mask = n - 1;
    const double scale = level_scale[level];
    const double x = u * scale - 0.5, y = v * scale - 0.5;
    const int64_t ix = FastFloor(x), iy = FastFloor(y);
    const float ax = static_cast<float>(x - ix), ay = static_cast<float>(y - iy);
    const int x0 = static_cast<int>(ix & mask), x1 = static_cast<int>((ix + 1) & mask);
    const int y0 = static_cast<int>(iy & mask), y1 = static_cast<int>((iy + 1) & mask);
    const uint8_t* d = level_data[level];
    auto tap = [&](int xi, int yi) {
      int32_t word;
      std::memcpy(&word, d + (yi * n + xi) * 4, 4);
      return _mm_cvtepi32_ps(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(word)));
    };
    constexpr float k = 1.0f / 255.0f;
    const float bx = 1 - ax, by = (1 - ay) * k;
    const float cy = ay * k;
    __m128 acc = _mm_mul_ps(tap(x0, y0), _mm_set1_ps(bx * by));
    acc = _mm_add_ps(acc, _mm_mul_ps(tap(x1, y0), _mm_set1_ps(ax * by)));
    acc = _mm_add_ps(acc, _mm_mul_ps(tap(x0, y1), _mm_set1_ps(bx * cy)));
    acc = _mm_add_ps(acc, _mm_mul_ps(tap(x1, y1), _mm_set1_ps(ax * cy)));
    alignas(16) float out[4];
    _mm_store_ps(out, acc);
    return Eigen::Vector3f(out[0], out[1], out[2]);
  }
};

// Builds the named material's texture from the seed. Throws std::invalid_argument for an
// unknown name.
Texture MakeMaterialTexture(const std::string& name, uint64_t seed);
// Large-scale brightness variation of the ground (0.75..1.25), 128 m period.
Texture MakeMacroTexture(uint64_t seed);
// Smooth non-periodic value noise in [0, 1] (cloud shadows).
double ValueNoise2(double x, double y, uint64_t seed);

enum class Shape : uint8_t { kBox, kRoom, kCylinder, kSphere, kCable, kBoard };

struct Primitive {
  Shape shape = Shape::kBox;
  int object_id = 0;
  int material = 0;
  int top_material = 0;  // boxes: material of the face pointing up
  Eigen::Vector3d c = Eigen::Vector3d::Zero();  // box/room/sphere centre, cylinder base, cable end a
  Eigen::Vector3d h = Eigen::Vector3d::Zero();  // box/room half extents; cable b - a
  double radius = 0.0;
  double height = 0.0;
  double cos_yaw = 1.0, sin_yaw = 0.0;
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();  // board: columns x, y, normal in N
  int board = -1;        // index into chessboards
  int mover = -1;        // index into Scene::Impl::movers when the object moves
  Eigen::Vector3d box_lo = Eigen::Vector3d::Zero();  // axis-aligned bounds in N
  Eigen::Vector3d box_hi = Eigen::Vector3d::Zero();
};

constexpr int kBoardMaterial = -1;
constexpr int kSkyMaterial = -2;

struct SurfaceHit {
  double t = std::numeric_limits<double>::infinity();
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();  // unit, not yet flipped to face the ray
  double u = 0.0, v = 0.0;  // texture coordinates [m]
  int material = kSkyMaterial;
  int object_id = kNoObject;
  int prim = -1;          // primitive index, -1 for the ground
  float coverage = 1.0f;  // thin cables: fraction of the pixel covered
};

// Ray against one primitive; updates `hit` when nearer than hit.t and beyond t_min.
// `pixel_angle` > 0 widens cables to half a pixel and reports their coverage instead.
bool IntersectPrimitive(const Primitive& p, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        double t_min, double pixel_angle, SurfaceHit* hit);

// A moving object's path, prepared: cumulative leg lengths.
struct Mover {
  int object_id = 0;
  ObjectPath path;
  std::vector<Eigen::Vector2d> points;  // waypoints, closed (first repeated) when looping
  std::vector<double> cumulative;       // [m] distance to each point
  Eigen::Vector3d base_N = Eigen::Vector3d::Zero();  // as declared
  // Placement at t_s, and the rigid motion taking the declared object to it (x = R x0 + t).
  ObjectPlacement At(double t_s) const;
  Eigen::Isometry3d Motion(double t_s) const;
};

// Per primitive, the motion of its object at one instant (identity for static ones); the
// renderer intersects a moving primitive with the ray taken back into its declared pose.
struct PrimitiveMotions {
  std::vector<Eigen::Isometry3d> T_N_declared;  // indexed by primitive; empty when nothing moves
  std::vector<Eigen::Isometry3d> T_declared_N;
};

struct Scene::Impl {
  uint64_t seed = 0;
  std::string name = "unnamed";
  GroundSpec ground;
  int ground_material = -1;
  int road_material = -1;
  std::vector<int> parcel_materials;
  SunLight sun;
  CloudShadows clouds;
  bool sky = true;
  std::vector<std::string> material_names;  // index = material id
  std::vector<Texture> textures;
  Texture macro;
  std::vector<Primitive> prims;
  std::vector<Obstacle> obstacles;
  std::vector<Cable> cables;
  std::vector<Chessboard> boards;
  std::optional<CameraSetup> downward;
  std::optional<StereoSetup> stereo;     // the first of stereo_rigs
  std::vector<StereoSetup> stereo_rigs;
  std::optional<CameraSetup> gimbal;
  std::vector<Mover> movers;
  int next_id = 2;
  double cloud_threshold = 2.0;
  double grid_cos = 1.0, grid_sin = 0.0;  // ground parcel grid orientation
  double inv_parcel = 1.0, inv_road_every = 0.0;  // noise level above which the ground is in cloud shadow

  void ComputeCloudThreshold();
  inline Eigen::Vector3f macro_sample(double n, double e, double footprint_m) const {
    return 2.0f * macro.Sample(n, e, footprint_m);  // stored halved
  }

  int Material(const std::string& name);  // builds the texture on first use
  PrimitiveMotions MotionsAt(double t_s) const;
  // Ray against primitive i, moved as `motions` says; the hit's normal comes back in N.
  inline bool IntersectMoved(int i, const PrimitiveMotions& motions, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                             double t_min, double pixel_angle, SurfaceHit* hit) const {
    const Primitive& p = prims[static_cast<size_t>(i)];
    if (p.mover < 0 || motions.T_N_declared.empty()) return IntersectPrimitive(p, o, d, t_min, pixel_angle, hit);
    const Eigen::Isometry3d& T = motions.T_declared_N[static_cast<size_t>(i)];
    if (!IntersectPrimitive(p, T * o, T.linear() * d, t_min, pixel_angle, hit)) return false;
    hit->normal = motions.T_N_declared[static_cast<size_t>(i)].linear() * hit->normal;
    return true;
  }
  void AddPrimitive(Primitive p);
  void AddCylinderPrimitive(int id, const Eigen::Vector3d& base_N, double radius, double height, const std::string& material);
  void AddSpherePrimitive(int id, const Eigen::Vector3d& center_N, double radius, const std::string& material);
  // Obstacle of a cylinder-like object (tree, pole, person, sphere): footprint centre, radius, height.
  void AddRoundObstacle(int id, const std::string& kind, const Eigen::Vector3d& base_N, double radius, double height);

  // Ground: plane d = 0 seen from above.
  inline bool IntersectGround(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double t_min,
                              SurfaceHit* hit) const {
    if (!ground.enabled || d.z() == 0.0) return false;
    const double t = -o.z() / d.z();
    if (!(t > t_min && t < hit->t)) return false;
    hit->t = t;
    hit->normal = Eigen::Vector3d(0, 0, -1);
    hit->u = o.x() + t * d.x();
    hit->v = o.y() + t * d.y();
    hit->material = ground_material;  // kFields picks per parcel when shading
    hit->object_id = kGroundId;
    hit->prim = -1;
    hit->coverage = 1.0f;
    return true;
  }

  // What GroundAlbedo derives from a parcel's hash; neighbouring pixels share a parcel.
  struct ParcelCache {
    int64_t i = INT64_MIN, j = INT64_MIN;
    int material = 0;
    double ox = 0, oy = 0;
    bool turn = false;
    float tint = 1.0f;
  };
  // Ground colour at (n, e) for the parcel layout, before lighting and before the large-scale
  // brightness variation macro_sample(), which the renderer applies.
  Eigen::Vector3f GroundAlbedo(double n, double e, double footprint_m, ParcelCache* cache) const;
  // Cloud shadow light factor at ground point (n, e) at time t_s.
  double CloudLight(double n, double e, double t_s) const;
  // Albedo of a hit (board squares, textures).
  Eigen::Vector3f Albedo(const SurfaceHit& hit, double footprint_m, ParcelCache* cache) const;
};

// Inline: the renderer calls these once per pixel.
inline Eigen::Vector3f Scene::Impl::GroundAlbedo(double n, double e, double footprint_m, ParcelCache* cache) const {
  if (ground.layout == GroundSpec::Layout::kUniform) return textures[ground_material].Sample(n, e, footprint_m);
  const double gx = grid_cos * n + grid_sin * e, gy = -grid_sin * n + grid_cos * e;
  const double P = ground.parcel_m;
  const int64_t i = FastFloor(gx * inv_parcel), j = FastFloor(gy * inv_parcel);
  const double lx = gx - i * P, ly = gy - j * P;
  if (ground.road_every > 0) {
    const int64_t k = ground.road_every;
    const bool road_i = i - k * FastFloor(i * inv_road_every) == 0;
    const bool road_j = j - k * FastFloor(j * inv_road_every) == 0;
    if ((road_i && lx < ground.road_width_m) || (road_j && ly < ground.road_width_m))
      return textures[road_material].Sample(gx, gy, footprint_m);
  }
  ParcelCache& c = *cache;
  if (c.i != i || c.j != j) {
    const uint64_t h = HashCombine(seed, (static_cast<uint64_t>(i) << 32) ^ static_cast<uint32_t>(j));
    c.i = i;
    c.j = j;
    c.material = parcel_materials[((h >> 32) * parcel_materials.size()) >> 32];
    c.ox = (h & 0xffff) * (5.12 / 65536.0);
    c.oy = ((h >> 16) & 0xffff) * (5.12 / 65536.0);
    c.turn = (h >> 60) & 1;
    c.tint = 0.85f + 0.3f * static_cast<float>((h >> 48) & 0xfff) / 4096.0f;
  }
  const Texture& t = textures[c.material];
  return c.tint * (c.turn ? t.Sample(ly + c.ox, lx + c.oy, footprint_m) : t.Sample(lx + c.ox, ly + c.oy, footprint_m));
}

inline Eigen::Vector3f Scene::Impl::Albedo(const SurfaceHit& hit, double footprint_m, ParcelCache* cache) const {
  if (hit.material == kBoardMaterial) {
    const Chessboard& b = boards[prims[hit.prim].board];
    const double s = b.square_m;
    const double x = hit.u / s, y = hit.v / s;
    const bool inside = x >= -1 && x < b.cols && y >= -1 && y < b.rows;
    if (!inside) return Eigen::Vector3f::Constant(0.85f);  // white margin
    const int64_t i = FastFloor(x) + 1, j = FastFloor(y) + 1;
    return Eigen::Vector3f::Constant(((i + j) % 2 == 0) ? 0.04f : 0.85f);
  }
  if (hit.object_id == kGroundId) return GroundAlbedo(hit.u, hit.v, footprint_m, cache);
  return textures[hit.material].Sample(hit.u, hit.v, footprint_m);
}

}  // namespace uav::world
