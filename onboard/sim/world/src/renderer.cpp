// Ray-cast renderer with exact per-pixel ground truth (issue 4).
//
// Each pixel's ray is cast against the ground plane and the primitives binned to its 16x16 tile
// (bounding spheres projected into normalised image coordinates), so the cost per pixel stays a
// few intersections however large the world is. Shading: mip-mapped procedural albedo, Lambert
// sun light reduced under cloud shadows, then auto-exposure, Gaussian read noise and 8-bit
// quantisation. Every random number is a hash of (scene seed, camera, utime, pixel), so renders
// are bit-identical whatever the thread count.
#include "uav/world/renderer.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "scene_impl.hpp"

namespace uav::world {

namespace {
constexpr int kTile = 16;
constexpr int kCloudStep = 8;  // [px] grid of the slowly varying light factors
constexpr double kNear = 1e-3;  // [m] along the optical axis

struct Bounds {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  void Add(const Eigen::Vector2d& p) {
    x0 = std::min(x0, p.x());
    x1 = std::max(x1, p.x());
    y0 = std::min(y0, p.y());
    y1 = std::max(y1, p.y());
  }
  void Add(const Bounds& b) {
    x0 = std::min(x0, b.x0);
    x1 = std::max(x1, b.x1);
    y0 = std::min(y0, b.y0);
    y1 = std::max(y1, b.y1);
  }
  bool Overlaps(double ax0, double ax1, double ay0, double ay1) const {
    return ax0 <= x1 && ax1 >= x0 && ay0 <= y1 && ay1 >= y0;
  }
};

// Unit Gaussian read noise: a fixed table of 2^16 samples (Box-Muller from a fixed seed); each
// image row reads it from a random offset with a random odd stride, so rows and frames differ
// while a pixel costs one load.
constexpr int kNoiseTable = 1 << 16;
const std::vector<float>& NoiseTable() {
  static const std::vector<float> table = [] {
    std::vector<float> t(kNoiseTable);
    uint64_t state = 0x5eed;
    for (int i = 0; i < kNoiseTable; i += 2) {
      state = SplitMix64(state);
      const double u1 = (static_cast<double>(state >> 11) + 1.0) / 9007199254740993.0;
      state = SplitMix64(state);
      const double u2 = Unit(state);
      const double r = std::sqrt(-2.0 * std::log(u1));
      t[i] = static_cast<float>(r * std::cos(2 * M_PI * u2));
      t[i + 1] = static_cast<float>(r * std::sin(2 * M_PI * u2));
    }
    return t;
  }();
  return table;
}
}  // namespace

struct Renderer::Impl {
  const Scene& scene;
  CameraSetup cam;
  int W = 0, H = 0, ss = 1, samples = 1;
  std::vector<Eigen::Vector3f> rays;        // per pixel, per sub-sample: normalised (x, y) and |(x, y, 1)|
  std::vector<Eigen::Vector2d> centre_rays;  // per pixel centre (truth when supersampling)
  int tiles_x = 0, tiles_y = 0;
  std::vector<Bounds> tile_bounds, col_bounds, row_bounds;
  Bounds all_bounds;
  // Cloud shadow and the ground's large-scale brightness change over metres, so they are
  // evaluated on a grid every kCloudStep pixels (where its ray meets the ground) and interpolated.
  int cloud_w = 0, cloud_h = 0;
  std::vector<Eigen::Vector2d> cloud_rays;
  double pixel_angle = 0.0;  // [rad] one pixel at the image centre

  Impl(const Scene& s, const CameraSetup& c) : scene(s), cam(c) {
    ValidateIntrinsics(cam.intrinsics);
    if (cam.supersample < 1 || cam.supersample > 4) throw std::invalid_argument("supersample must be 1..4");
    if (cam.blur_samples < 1 || cam.blur_samples > 16) throw std::invalid_argument("blur_samples must be 1..16");
    if (!(cam.noise_sigma >= 0 && cam.noise_sigma < 50)) throw std::invalid_argument("noise_sigma must be in [0, 50) DN");
    if (!(cam.exposure_s >= 0 && cam.exposure_s < 1)) throw std::invalid_argument("exposure_s must be in [0, 1) s");
    if (!(cam.target_mean > 0 && cam.target_mean < 1)) throw std::invalid_argument("target_mean must be in (0, 1)");
    const CameraIntrinsics& k = cam.intrinsics;
    W = k.width;
    H = k.height;
    ss = cam.supersample;
    samples = ss * ss;
    pixel_angle = 1.0 / std::sqrt(k.fx * k.fy);
    rays.resize(static_cast<size_t>(W) * H * samples);
    centre_rays.resize(static_cast<size_t>(W) * H);
    tiles_x = (W + kTile - 1) / kTile;
    tiles_y = (H + kTile - 1) / kTile;
    tile_bounds.assign(tiles_x * tiles_y, Bounds());
    col_bounds.assign(tiles_x, Bounds());
    row_bounds.assign(tiles_y, Bounds());
    for (int v = 0; v < H; ++v)
      for (int u = 0; u < W; ++u) {
        Bounds& tb = tile_bounds[(v / kTile) * tiles_x + u / kTile];
        centre_rays[v * W + u] = Unproject(k, Eigen::Vector2d(u, v));
        for (int a = 0; a < ss; ++a)
          for (int b = 0; b < ss; ++b) {
            const Eigen::Vector2d uv(u + (b + 0.5) / ss - 0.5, v + (a + 0.5) / ss - 0.5);
            const Eigen::Vector2d r = samples == 1 ? centre_rays[v * W + u] : Unproject(k, uv);
            rays[(static_cast<size_t>(v) * W + u) * samples + a * ss + b] =
                Eigen::Vector3d(r.x(), r.y(), std::sqrt(r.squaredNorm() + 1)).cast<float>();
            tb.Add(r);
          }
      }
    for (int ty = 0; ty < tiles_y; ++ty)
      for (int tx = 0; tx < tiles_x; ++tx) {
        col_bounds[tx].Add(tile_bounds[ty * tiles_x + tx]);
        row_bounds[ty].Add(tile_bounds[ty * tiles_x + tx]);
        all_bounds.Add(tile_bounds[ty * tiles_x + tx]);
      }
    cloud_w = (W - 1) / kCloudStep + 2;
    cloud_h = (H - 1) / kCloudStep + 2;
    for (int gy = 0; gy < cloud_h; ++gy)
      for (int gx = 0; gx < cloud_w; ++gx)
        cloud_rays.push_back(Unproject(k, Eigen::Vector2d(std::min(gx * kCloudStep, W - 1), std::min(gy * kCloudStep, H - 1))));
  }

  // Primitives whose bounds may show in each tile. Each primitive's box in N is taken into C,
  // clipped to the near plane and projected to a rectangle of normalised coordinates, which is
  // tight even for objects that reach above a low-flying camera. Cables thinner than a pixel
  // are widened by the half pixel they are drawn with.
  void Bin(const Eigen::Matrix3d& R_CN, const Eigen::Vector3d& o_N, const PrimitiveMotions& motions,
           std::vector<std::vector<int>>* tiles, std::vector<int>* everywhere) const {
    tiles->assign(tiles_x * tiles_y, {});
    everywhere->clear();
    const auto& prims = scene.impl().prims;
    for (size_t i = 0; i < prims.size(); ++i) {
      const Primitive& p = prims[i];
      Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e300), hi = Eigen::Vector3d::Constant(-1e300);
      for (int corner = 0; corner < 8; ++corner) {
        Eigen::Vector3d q((corner & 1) ? p.box_hi.x() : p.box_lo.x(), (corner & 2) ? p.box_hi.y() : p.box_lo.y(),
                          (corner & 4) ? p.box_hi.z() : p.box_lo.z());
        if (p.mover >= 0 && !motions.T_N_declared.empty()) q = motions.T_N_declared[i] * q;
        const Eigen::Vector3d c = R_CN * (q - o_N);
        lo = lo.cwiseMin(c);
        hi = hi.cwiseMax(c);
      }
      if (p.shape == Shape::kCable) {
        const double pad = 0.5 * pixel_angle * std::max(std::abs(lo.z()), std::abs(hi.z())) * 1.8;
        lo.array() -= pad;
        hi.array() += pad;
      }
      if (hi.z() < kNear) continue;  // behind the camera
      const double z0 = std::max(lo.z(), kNear), z1 = hi.z();
      auto range = [&](double a0, double a1, double* r0, double* r1) {
        *r0 = a0 >= 0 ? a0 / z1 : a0 / z0;
        *r1 = a1 >= 0 ? a1 / z0 : a1 / z1;
      };
      double x0, x1, y0, y1;
      range(lo.x(), hi.x(), &x0, &x1);
      range(lo.y(), hi.y(), &y0, &y1);
      if (!all_bounds.Overlaps(x0, x1, y0, y1)) continue;
      if (x0 <= all_bounds.x0 && x1 >= all_bounds.x1 && y0 <= all_bounds.y0 && y1 >= all_bounds.y1) {
        everywhere->push_back(static_cast<int>(i));
        continue;
      }
      for (int ty = 0; ty < tiles_y; ++ty) {
        const Bounds& rb = row_bounds[ty];
        if (y0 > rb.y1 || y1 < rb.y0) continue;
        for (int tx = 0; tx < tiles_x; ++tx) {
          const Bounds& cb = col_bounds[tx];
          if (x0 > cb.x1 || x1 < cb.x0) continue;
          if (tile_bounds[ty * tiles_x + tx].Overlaps(x0, x1, y0, y1))
            (*tiles)[ty * tiles_x + tx].push_back(static_cast<int>(i));
        }
      }
    }
  }

  struct Cast {
    SurfaceHit solid;
    SurfaceHit thin;  // a cable thinner than the pixel in front of `solid`, if any
  };

  inline Cast CastRay(const Eigen::Vector3d& o, const Eigen::Vector3d& d, const std::vector<int>& tile,
                      const std::vector<int>& everywhere, const PrimitiveMotions& motions) const {
    const Scene::Impl& s = scene.impl();
    Cast c;
    s.IntersectGround(o, d, kNear, &c.solid);
    // Solid primitives write straight into the nearest hit (IntersectPrimitive only touches it
    // when nearer); only cables, which may come back thinner than a pixel, need a candidate.
    auto test = [&](int i) {
      const Primitive& prim = s.prims[i];
      if (prim.shape != Shape::kCable) {
        if (s.IntersectMoved(i, motions, o, d, kNear, pixel_angle, &c.solid)) c.solid.prim = i;
        return;
      }
      SurfaceHit cand;
      cand.t = c.solid.t;
      if (!s.IntersectMoved(i, motions, o, d, kNear, pixel_angle, &cand)) return;
      cand.prim = i;
      if (cand.coverage < 1.0f) {
        if (cand.t < c.thin.t) c.thin = cand;
      } else {
        c.solid = cand;
      }
    };
    for (int i : tile) test(i);
    for (int i : everywhere) test(i);
    if (c.thin.t >= c.solid.t) c.thin = SurfaceHit();
    return c;
  }

  // `light`: cloud factor, then the ground's large-scale brightness (BGR).
  // `length` is |d| (known per pixel, so no square root here).
  inline Eigen::Vector3f Shade(const SurfaceHit& h, const Eigen::Vector3d& d, double length,
                               const Eigen::Vector4f& light, Scene::Impl::ParcelCache* cache) const {
    const Scene::Impl& s = scene.impl();
    if (h.object_id == kNoObject) {
      if (!s.sky) return Eigen::Vector3f::Zero();
      // Sky: brighter and whiter towards the horizon. NED: up is -d.
      const double elevation = std::clamp(-d.z() / d.norm(), 0.0, 1.0);
      const float e = static_cast<float>(std::sqrt(elevation));
      return Eigen::Vector3f(0.95f - 0.05f * e, 0.88f - 0.2f * e, 0.80f - 0.35f * e);
    }
    // The pixel's size on the surface: distance * pixel angle / cos(incidence), with grazing
    // angles capped.
    const double nd = std::abs(h.normal.dot(d));
    const double footprint = h.t * length * length * pixel_angle / std::max(0.15 * length, nd);
    Eigen::Vector3f albedo = s.Albedo(h, footprint, cache);
    if (h.object_id == kGroundId) albedo = albedo.cwiseProduct(light.tail<3>());
    const Eigen::Vector3d n = h.normal.dot(d) > 0 ? Eigen::Vector3d(-h.normal) : h.normal;
    const double lambert = std::max(0.0, n.dot(s.sun.to_sun_N));
    return albedo * static_cast<float>(s.sun.ambient + (1.0 - s.sun.ambient) * lambert * light.x());
  }

  Frame Render(const Eigen::Isometry3d& T_NC, int64_t utime, const std::vector<LaserDot>& dots,
               const Eigen::Vector3d& v_N, const Eigen::Vector3d& w_C) const {
    if (!T_NC.matrix().allFinite()) throw std::invalid_argument("render: camera pose must be finite");
    const Scene::Impl& s = scene.impl();
    Frame f;
    f.utime = utime;
    f.camera = cam.name;
    f.T_NC = T_NC;
    f.image.create(H, W, CV_8UC3);
    f.depth.create(H, W, CV_32F);
    f.object_id.create(H, W, CV_16U);
    const double t_s = utime * 1e-6;
    // Moving objects where they are at mid-exposure (they are not blurred).
    const PrimitiveMotions motions = s.MotionsAt(t_s);
    const int blur = cam.exposure_s > 0 ? cam.blur_samples : 1;
    const int mid = (blur - 1) / 2;
    const bool truth_in_pass = samples == 1 && blur % 2 == 1;
    const float weight = 1.0f / (blur * samples);

    // Per pose across the shutter time: tile bins and the light grid.
    struct Pose {
      Eigen::Matrix3d R_NC;
      Eigen::Vector3d o;
      std::vector<std::vector<int>> tiles;
      std::vector<int> everywhere;
      std::vector<Eigen::Vector4f> light_grid;  // cloud factor, ground macro brightness BGR
    };
    std::vector<Pose> poses(blur);
    for (int k = 0; k < blur; ++k) {
      Pose& p = poses[k];
      Eigen::Isometry3d T = T_NC;
      if (blur > 1) {
        const double tau = ((k + 0.5) / blur - 0.5) * cam.exposure_s;
        T.translation() += v_N * tau;
        const double angle = w_C.norm() * tau;
        if (angle != 0.0) T.linear() = T_NC.linear() * Eigen::AngleAxisd(angle, w_C.normalized()).toRotationMatrix();
      }
      p.R_NC = T.linear();
      p.o = T.translation();
      Bin(p.R_NC.transpose(), p.o, motions, &p.tiles, &p.everywhere);
      p.light_grid.assign(cloud_w * cloud_h, Eigen::Vector4f::Ones());
      if (s.ground.enabled && p.o.z() < 0) {
        cv::parallel_for_(cv::Range(0, static_cast<int>(p.light_grid.size())), [&](const cv::Range& range) {
        for (int i = range.start; i < range.end; ++i) {
          const Eigen::Vector3d d = p.R_NC * Eigen::Vector3d(cloud_rays[i].x(), cloud_rays[i].y(), 1.0);
          if (d.z() <= 1e-9) continue;
          const double t = -p.o.z() / d.z();
          const double n = p.o.x() + t * d.x(), e = p.o.y() + t * d.y();
          p.light_grid[i] << static_cast<float>(s.CloudLight(n, e, t_s)), s.macro_sample(n, e, 0.0);
        }
        });
      }
    }

    // Auto-exposure meters the light-grid rays at mid-exposure (a fixed 8-pixel grid, so it is
    // deterministic), as a camera's metering does before the frame is read out.
    double gain = 1.0;
    if (cam.auto_exposure) {
      const Pose& p = poses[mid];
      Scene::Impl::ParcelCache parcel;
      double sum = 0;
      int count = 0;
      for (int gy = 0; gy < cloud_h; gy += 2) {  // every 16 px: 1200 rays for 640x480
        for (int gx = 0; gx < cloud_w; gx += 2) {
          const int i = gy * cloud_w + gx;
          const Eigen::Vector3d d = p.R_NC * Eigen::Vector3d(cloud_rays[i].x(), cloud_rays[i].y(), 1.0);
          const int tile = (std::min(gy * kCloudStep, H - 1) / kTile) * tiles_x + std::min(gx * kCloudStep, W - 1) / kTile;
          const Cast c = CastRay(p.o, d, p.tiles[tile], p.everywhere, motions);
          sum += Shade(c.solid, d, d.norm(), p.light_grid[i], &parcel).sum() / 3.0;
          ++count;
        }
      }
      const double mean = sum / count;
      gain = mean > 1e-6 ? std::clamp(cam.target_mean / mean, 0.2, 5.0) : 5.0;
    }
    f.exposure_gain = gain;
    const float scale = static_cast<float>(gain * 255.0) * weight;
    const float sigma = static_cast<float>(cam.noise_sigma);
    const uint64_t frame_seed = HashCombine(HashCombine(s.seed, HashString(cam.name)), static_cast<uint64_t>(utime));
    const std::vector<float>& noise = NoiseTable();
    // Ground lighting (normal up, -z in NED): ambient plus Lambert times the cloud factor.
    const float ground_ambient = static_cast<float>(s.sun.ambient);
    const float ground_direct = static_cast<float>((1.0 - s.sun.ambient) * std::max(0.0, -s.sun.to_sun_N.z()));

    cv::parallel_for_(cv::Range(0, tiles_y), [&](const cv::Range& range) {
      Scene::Impl::ParcelCache parcel;
      for (int ty = range.start; ty < range.end; ++ty) {
        for (int v = ty * kTile; v < std::min(H, (ty + 1) * kTile); ++v) {
          uint8_t* out = f.image.ptr<uint8_t>(v);
          float* depth = f.depth.ptr<float>(v);
          uint16_t* ids = f.object_id.ptr<uint16_t>(v);
          const uint64_t h = HashCombine(frame_seed, static_cast<uint64_t>(v));
          const uint32_t noise_start = static_cast<uint32_t>(h), noise_stride = static_cast<uint32_t>(h >> 32) | 1u;
          const int gy = v / kCloudStep;
          const float fy = static_cast<float>(v - gy * kCloudStep) / kCloudStep;
          for (int u = 0; u < W; ++u) {
            const int tile = ty * tiles_x + u / kTile;
            const int gx = u / kCloudStep;
            const float fx = static_cast<float>(u - gx * kCloudStep) / kCloudStep;
            Eigen::Vector3f sum = Eigen::Vector3f::Zero();
            for (int k = 0; k < blur; ++k) {
              const Pose& p = poses[k];
              const Eigen::Vector4f* cl = &p.light_grid[gy * cloud_w + gx];
              const Eigen::Vector4f light = (cl[0] * (1 - fx) + cl[1] * fx) * (1 - fy) +
                                            (cl[cloud_w] * (1 - fx) + cl[cloud_w + 1] * fx) * fy;
              const bool ground_only = p.tiles[tile].empty() && p.everywhere.empty() && s.ground.enabled;
              for (int a = 0; a < samples; ++a) {
                const Eigen::Vector3f& r = rays[(static_cast<size_t>(v) * W + u) * samples + a];
                const Eigen::Vector3d d = p.R_NC * Eigen::Vector3d(r.x(), r.y(), 1.0);
                if (ground_only && d.z() > 0 && p.o.z() < -kNear * d.z()) {
                  // Nothing but the ground can show in this tile: the plane hit and its shading
                  // without the general cast (the same arithmetic as IntersectGround and Shade).
                  const double t = -p.o.z() / d.z();
                  const double length = r.z();
                  const double footprint = t * length * length * pixel_angle / std::max(0.15 * length, d.z());
                  sum += s.GroundAlbedo(p.o.x() + t * d.x(), p.o.y() + t * d.y(), footprint, &parcel)
                             .cwiseProduct(light.tail<3>()) *
                         (ground_ambient + ground_direct * light.x());
                  if (truth_in_pass && k == mid) {
                    depth[u] = static_cast<float>(t);
                    ids[u] = static_cast<uint16_t>(kGroundId);
                  }
                  continue;
                }
                const Cast c = CastRay(p.o, d, p.tiles[tile], p.everywhere, motions);
                Eigen::Vector3f colour = Shade(c.solid, d, r.z(), light, &parcel);
                if (c.thin.object_id != kNoObject)
                  colour = (1.0f - c.thin.coverage) * colour + c.thin.coverage * Shade(c.thin, d, r.z(), light, &parcel);
                sum += colour;
                if (truth_in_pass && k == mid) {
                  const bool thin_wins = c.thin.object_id != kNoObject && c.thin.coverage >= 0.5f;
                  const SurfaceHit& hit = thin_wins ? c.thin : c.solid;
                  depth[u] = hit.object_id == kNoObject ? 0.0f : static_cast<float>(hit.t);
                  ids[u] = static_cast<uint16_t>(hit.object_id);
                }
              }
            }
            for (int ch = 0; ch < 3; ++ch) {
              const float n = noise[(noise_start + static_cast<uint32_t>(u * 3 + ch) * noise_stride) & (kNoiseTable - 1)];
              out[u * 3 + ch] = static_cast<uint8_t>(std::clamp(sum[ch] * scale + sigma * n + 0.5f, 0.0f, 255.0f));
            }
          }
        }
      }
    });
    if (!truth_in_pass) RenderTruth(T_NC, motions, &f);
    DrawLaserDots(dots, T_NC, t_s, &f);
    return f;
  }

  // Depth and ids from the pixel centres at the mid-exposure pose.
  void RenderTruth(const Eigen::Isometry3d& T_NC, const PrimitiveMotions& motions, Frame* f) const {
    std::vector<std::vector<int>> tiles;
    std::vector<int> everywhere;
    const Eigen::Matrix3d R_NC = T_NC.linear();
    const Eigen::Vector3d o = T_NC.translation();
    Bin(R_NC.transpose(), o, motions, &tiles, &everywhere);
    cv::parallel_for_(cv::Range(0, H), [&](const cv::Range& range) {
      for (int v = range.start; v < range.end; ++v) {
        float* depth = f->depth.ptr<float>(v);
        uint16_t* ids = f->object_id.ptr<uint16_t>(v);
        for (int u = 0; u < W; ++u) {
          const Eigen::Vector2d& r = centre_rays[v * W + u];
          const Eigen::Vector3d d = R_NC * Eigen::Vector3d(r.x(), r.y(), 1.0);
          // Tile lists were binned over all sub-samples, which cover the centre ray.
          const Cast c = CastRay(o, d, tiles[(v / kTile) * tiles_x + u / kTile], everywhere, motions);
          const bool thin_wins = c.thin.object_id != kNoObject && c.thin.coverage >= 0.5f;
          const SurfaceHit& h = thin_wins ? c.thin : c.solid;
          depth[u] = h.object_id == kNoObject ? 0.0f : static_cast<float>(h.t);
          ids[u] = static_cast<uint16_t>(h.object_id);
        }
      }
    });
  }

  void DrawLaserDots(const std::vector<LaserDot>& dots, const Eigen::Isometry3d& T_NC, double t_s, Frame* f) const {
    const Eigen::Isometry3d T_CN = T_NC.inverse();
    const Eigen::Vector3d o = T_NC.translation();
    f->laser_dots = dots;
    for (LaserDot& dot : f->laser_dots) {
      dot.visible = false;
      if (!dot.hit) continue;
      const Eigen::Vector3d p_C = T_CN * dot.p_N;
      if (p_C.z() <= kNear) continue;
      const Eigen::Vector2d px = Project(cam.intrinsics, p_C);
      if (!(px.x() >= 0 && px.x() <= W - 1 && px.y() >= 0 && px.y() <= H - 1)) continue;
      // Occluded when anything lies between the camera and the spot.
      if (scene.Intersect(o, dot.p_N - o, 1e-9, 1.0 - 1e-6, t_s)) continue;
      dot.visible = true;
      dot.pixel = px;
      const double sigma = std::max(0.7, cam.intrinsics.fx * dot.spot_radius_m / p_C.z());
      const int reach = static_cast<int>(std::ceil(3 * sigma));
      const int cu = static_cast<int>(std::lround(px.x())), cv_ = static_cast<int>(std::lround(px.y()));
      for (int v = std::max(0, cv_ - reach); v <= std::min(H - 1, cv_ + reach); ++v) {
        uint8_t* row = f->image.ptr<uint8_t>(v);
        for (int u = std::max(0, cu - reach); u <= std::min(W - 1, cu + reach); ++u) {
          const double r2 = (u - px.x()) * (u - px.x()) + (v - px.y()) * (v - px.y());
          const double add = dot.intensity * std::exp(-r2 / (2 * sigma * sigma));
          const double weights[3] = {0.35, 1.0, 0.35};  // green laser, bright enough to bloom
          for (int k = 0; k < 3; ++k)
            row[u * 3 + k] = static_cast<uint8_t>(std::min(255.0, row[u * 3 + k] + weights[k] * add));
        }
      }
    }
  }
};

std::vector<LaserDot> CastLaser(const Scene& scene, const LaserEmitter& laser, const Eigen::Isometry3d& T_NE, double t_s) {
  std::vector<LaserDot> dots;
  if (!laser.enabled) return dots;
  if (laser.rows < 1 || laser.cols < 1 || laser.rows * laser.cols > 10000)
    throw std::invalid_argument("laser grid must have 1..10000 beams");
  const Eigen::Vector3d o = T_NE.translation();
  for (int i = 0; i < laser.beam_count(); ++i) {
    LaserDot dot;
    dot.beam = i;
    const Eigen::Vector3d d = T_NE.linear() * laser.BeamDirection(i);
    if (const auto hit = scene.Intersect(o, d, 1e-6, 1e4, t_s)) {
      dot.hit = true;
      dot.p_N = hit->p_N;
      dot.range_m = hit->t;
      dot.spot_radius_m = laser.spot_radius_m + laser.divergence_rad * hit->t;
      dot.intensity = laser.intensity;
    }
    dots.push_back(dot);
  }
  return dots;
}

cv::Rect ObjectBox(const Frame& frame, int object_id) {
  int u0 = frame.object_id.cols, v0 = frame.object_id.rows, u1 = -1, v1 = -1;
  for (int v = 0; v < frame.object_id.rows; ++v) {
    const uint16_t* ids = frame.object_id.ptr<uint16_t>(v);
    for (int u = 0; u < frame.object_id.cols; ++u)
      if (ids[u] == object_id) u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
  }
  return u1 < 0 ? cv::Rect() : cv::Rect(u0, v0, u1 - u0 + 1, v1 - v0 + 1);
}

Renderer::Renderer(const Scene& scene, const CameraSetup& camera) : impl_(std::make_unique<Impl>(scene, camera)) {}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
const CameraSetup& Renderer::camera() const { return impl_->cam; }

Frame Renderer::Render(const Eigen::Isometry3d& T_NC, int64_t utime, const std::vector<LaserDot>& dots,
                       const Eigen::Vector3d& v_N, const Eigen::Vector3d& w_C) const {
  return impl_->Render(T_NC, utime, dots, v_N, w_C);
}

StereoRenderer::StereoRenderer(const Scene& scene, const StereoSetup& setup)
    : scene_(scene), setup_(setup), left_(scene, setup.left), right_(scene, setup.right) {}

StereoFrame StereoRenderer::Render(const Eigen::Isometry3d& T_NB, int64_t utime, bool laser_on) const {
  const std::vector<LaserDot> dots =
      laser_on ? CastLaser(scene_, setup_.laser, T_NB * setup_.T_BE, utime * 1e-6) : std::vector<LaserDot>();
  StereoFrame out;
  out.left = left_.Render(T_NB * setup_.left.T_BC, utime, dots);
  out.right = right_.Render(T_NB * setup_.right.T_BC, utime, dots);
  const double fb = setup_.left.intrinsics.fx * setup_.baseline_m;
  out.disparity.create(out.left.depth.size(), CV_32F);
  for (int v = 0; v < out.disparity.rows; ++v) {
    const float* z = out.left.depth.ptr<float>(v);
    float* d = out.disparity.ptr<float>(v);
    for (int u = 0; u < out.disparity.cols; ++u) d[u] = z[u] > 0 ? static_cast<float>(fb / z[u]) : 0.0f;
  }
  return out;
}

}  // namespace uav::world
