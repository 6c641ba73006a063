#include "uav/vision/map_stitcher.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <stdexcept>
#include <set>
#include <unordered_map>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "homography.hpp"
#include "image_region.hpp"
#include "seamless_render.hpp"

namespace uav::vision {

namespace {
void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("map stitcher: " + what);
}
struct Tile {
  cv::Mat bgr;   // CV_8UC3
  cv::Mat mask;  // CV_8U
};
// tx in the high 32 bits, ty in the low (shifted as unsigned: a tile west or north of the origin
// has a negative index, and shifting a negative value is undefined; UBSan found it).
int64_t TileKey(int tx, int ty) {
  return static_cast<int64_t>((static_cast<uint64_t>(static_cast<uint32_t>(tx)) << 32) | static_cast<uint32_t>(ty));
}
int FloorDiv(int a, int b) { return a >= 0 ? a / b : -((-a + b - 1) / b); }

// An image file decoded in grey at 1/reduce of its size (1, 2, 4 or 8): JPEG scales in its own
// transform, without the work of the full size; other formats are decoded whole and shrunk.
cv::Mat DecodeGrey(const std::vector<uint8_t>& file, int reduce) {
  const int flags = reduce == 2   ? cv::IMREAD_REDUCED_GRAYSCALE_2
                    : reduce == 4 ? cv::IMREAD_REDUCED_GRAYSCALE_4
                    : reduce == 8 ? cv::IMREAD_REDUCED_GRAYSCALE_8
                                  : cv::IMREAD_GRAYSCALE;
  return cv::imdecode(file, flags | cv::IMREAD_IGNORE_ORIENTATION);
}

// Matched points kept per frame pair for the global alignment: enough to fix four unknowns a
// frame many times over, few enough that 1000 frames solve in a second.
constexpr size_t kMatchesPerPair = 60;
// Ground matches a pair needs to constrain the alignment.
constexpr size_t kMinGroundMatches = 10;
// Footprint overlap down to which a frame is matched with earlier frames of its own pass.
constexpr double kAlongOverlap = 0.6;
// Frames the alignment keeps decoded (at registration size), for all its threads.
constexpr size_t kDecodedFrames = 64;

// Decoded frames shared by threads, the least recently used dropped first. Two threads that miss
// the same frame at once both decode it; the cache stays right.
class DecodedFrames {
 public:
  explicit DecodedFrames(std::function<cv::Mat(int)> decode) : decode_(std::move(decode)) {}
  cv::Mat Get(int f) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = frames_.find(f);
      if (it != frames_.end()) {
        it->second.second = ++clock_;
        return it->second.first;
      }
    }
    cv::Mat image = decode_(f);
    std::lock_guard<std::mutex> lock(mutex_);
    if (frames_.size() >= kDecodedFrames) {
      auto oldest = std::min_element(frames_.begin(), frames_.end(),
                                     [](const auto& a, const auto& b) { return a.second.second < b.second.second; });
      frames_.erase(oldest);
    }
    frames_[f] = {image, ++clock_};
    return image;
  }

 private:
  std::function<cv::Mat(int)> decode_;
  std::mutex mutex_;
  std::map<int, std::pair<cv::Mat, uint64_t>> frames_;  // frame -> image, last use
  uint64_t clock_ = 0;
};

// Every stride-th pair of points, at most `most` of them.
void KeepMatches(const std::vector<cv::Point2f>& a, const std::vector<cv::Point2f>& b, size_t most,
                 std::vector<Eigen::Vector2d>* p_a, std::vector<Eigen::Vector2d>* p_b) {
  const size_t stride = std::max<size_t>(1, (a.size() + most - 1) / most);
  for (size_t j = 0; j < a.size(); j += stride) {
    p_a->emplace_back(a[j].x, a[j].y);
    p_b->emplace_back(b[j].x, b[j].y);
  }
}

// The matches on the ground. Two views of a point h above the ground, placed on the ground plane,
// land apart by B h / (H - h) along the baseline (relief displacement: B the baseline, H the
// height above ground), always towards the first camera; ground points land apart only by the
// placements' error, the same for all. So the ground is, of the clusters of displacements that
// enough matches share (a wrong track shares its displacement with nobody), the one displaced
// least along the baseline; then a similarity is fitted to it by RANSAC (the placements'
// rotation and scale errors spread it by a pixel or two). What moved between the two views
// (cloud shadows, vehicles) clusters too, displaced by its motion, in any direction: so a
// cluster is a ground candidate only on the line through the largest cluster along the
// baseline, and with at least a quarter of its matches (shadow edges give a few).
// x_a, x_b: the matches placed on the map by frames a and b; baseline_a_b: camera a minus b.
std::vector<uint8_t> GroundMatches(const std::vector<Eigen::Vector2d>& x_a, const std::vector<Eigen::Vector2d>& x_b,
                                   const Eigen::Vector2d& baseline_a_b, size_t min_count) {
  constexpr double kClusterPx = 2.0;  // [map px] displacements closer than this are one cluster
  constexpr double kGroundPx = 3.0;   // [map px] matches this close to the ground cluster are fitted
  const size_t n = x_a.size();
  std::vector<uint8_t> keep(n, 0);
  if (n < min_count) return keep;
  const Eigen::Vector2d u = baseline_a_b.norm() > 1e-6 ? Eigen::Vector2d(baseline_a_b.normalized()) : Eigen::Vector2d(1, 0);
  std::vector<Eigen::Vector2d> d(n);
  for (size_t j = 0; j < n; ++j) d[j] = x_b[j] - x_a[j];
  std::vector<size_t> near(n, 0);
  size_t largest = 0;
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = 0; j < n; ++j) near[i] += (d[j] - d[i]).norm() <= kClusterPx;
    if (near[i] > near[largest]) largest = i;
  }
  if (near[largest] < std::max<size_t>(8, n / 25)) return keep;
  const Eigen::Vector2d across(-u.y(), u.x());
  size_t ground = largest;
  for (size_t i = 0; i < n; ++i)
    if (4 * near[i] >= near[largest] && std::abs((d[i] - d[largest]).dot(across)) <= kGroundPx &&
        d[i].dot(u) < d[ground].dot(u))
      ground = i;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  int count = 0;
  for (size_t j = 0; j < n; ++j)
    if ((d[j] - d[ground]).norm() <= kClusterPx) {
      centre += d[j];
      ++count;
    }
  centre /= count;
  std::vector<cv::Point2f> from, to;
  std::vector<size_t> index;
  for (size_t j = 0; j < n; ++j)
    if ((d[j] - centre).norm() <= kGroundPx) {
      from.emplace_back(static_cast<float>(x_b[j].x()), static_cast<float>(x_b[j].y()));
      to.emplace_back(static_cast<float>(x_a[j].x()), static_cast<float>(x_a[j].y()));
      index.push_back(j);
    }
  if (from.size() < min_count) return keep;
  std::vector<uint8_t> inlier;
  const cv::Mat M = cv::estimateAffinePartial2D(from, to, inlier, cv::RANSAC, 1.0);
  if (M.empty()) return keep;
  for (size_t j = 0; j < index.size(); ++j) keep[index[j]] = inlier[j];
  return keep;
}

// A registration of frames decoded at 1/reduce, in the full frames' pixels.
Registration InFullPixels(Registration r, int reduce) {
  if (reduce == 1) return r;
  const Eigen::Matrix3d E = Enlarge(reduce);
  r.H_prev_cur = E * r.H_prev_cur * E.inverse();
  r.H_prev_cur /= r.H_prev_cur(2, 2);
  r.translation_px *= reduce;
  for (auto* points : {&r.tracked_prev, &r.tracked_cur})
    for (cv::Point2f& q : *points) q = cv::Point2f(reduce * q.x + 0.5f * (reduce - 1), reduce * q.y + 0.5f * (reduce - 1));
  return r;
}

// A placed frame as the final map needs it.
struct KeptFrame {
  int64_t utime = 0;
  bool registered = false;
  Eigen::Matrix3d H = Eigen::Matrix3d::Identity();  // image pixel -> map pixel (adjusted after Align)
  std::optional<Eigen::Matrix3d> H_nav;             // the navigation solution's placement
  std::vector<uint8_t> jpeg;                        // the undistorted image (JPEG, or the input's own file)
  cv::Mat thumbnail;                                // grey, for the final render's exposure gains
};
}  // namespace

struct MapStitcher::Impl {
  CameraIntrinsics k;
  StitcherParams p;
  FrameRegistration registration;
  FrameRegistration preparing;       // Prepare's own: it may run beside Add
  cv::Mat undistort_x, undistort_y;  // empty for a distortion-free lens
  int reduce = 1;                    // frames are registered at 1/reduce of their size
  double gsd = 0.0;
  double north0 = 0.0, east0 = 0.0;  // map pixel (0, 0) centre
  bool started = false;
  bool georeferenced = false;
  cv::Mat prev_grey;
  FrameFeatures prev_features;
  Eigen::Matrix3d H_map_prev = Eigen::Matrix3d::Identity();
  Eigen::Matrix3d C_prev = Eigen::Matrix3d::Identity();  // the previous frame's correction
  std::vector<KeptFrame> kept;  // every placed frame
  std::unordered_map<int64_t, Tile> tiles;
  std::set<int64_t> changed;  // tiles written since TakeChangedTiles

  explicit Impl(const CameraIntrinsics& cam, const StitcherParams& params)
      : k(cam), p(params), registration(params.registration), preparing(params.registration) {}

  // A map whose pixel (0, 0) is map pixel `origin`. Map pixel (c, r) is centred on
  // east0 + c gsd, north0 - r gsd: the outer edges are half a pixel beyond the first centres.
  Mosaic MosaicAt(const cv::Point& origin) const {
    Mosaic out;
    out.gsd_m = gsd;
    out.georeferenced = georeferenced;
    out.north_top_m = north0 - (origin.y - 0.5) * gsd;
    out.east_left_m = east0 + (origin.x - 0.5) * gsd;
    return out;
  }

  Eigen::Vector2d MapPixel(double north, double east) const { return {(east - east0) / gsd, (north0 - north) / gsd}; }
  Eigen::Vector2d GroundNE(const Eigen::Vector2d& map_px) const {
    return {north0 - map_px.y() * gsd, east0 + map_px.x() * gsd};
  }

  // Ground (north, east) seen at undistorted pixel (u, v) from pose T_NC; false above the horizon.
  bool GroundPoint(const Eigen::Isometry3d& T_NC, double u, double v, Eigen::Vector2d* ne) const {
    const Eigen::Vector3d d = T_NC.linear() * Eigen::Vector3d((u - k.cx) / k.fx, (v - k.cy) / k.fy, 1.0);
    const Eigen::Vector3d o = T_NC.translation();
    if (d.z() <= 1e-6) return false;
    const double t = (p.ground_down_m - o.z()) / d.z();
    if (!(t > 0)) return false;
    *ne = Eigen::Vector2d(o.x() + t * d.x(), o.y() + t * d.y());
    return true;
  }

  // The navigation placement: the image's corners projected onto the ground plane.
  bool NavPlacement(const Eigen::Isometry3d& T_NC, Eigen::Matrix3d* H) const {
    const double w = k.width - 1, h = k.height - 1;
    const cv::Point2f img[4] = {{0, 0}, {float(w), 0}, {float(w), float(h)}, {0, float(h)}};
    cv::Point2f map[4];
    for (int i = 0; i < 4; ++i) {
      Eigen::Vector2d ne;
      if (!GroundPoint(T_NC, img[i].x, img[i].y, &ne)) return false;
      const Eigen::Vector2d m = MapPixel(ne.x(), ne.y());
      map[i] = cv::Point2f(static_cast<float>(m.x()), static_cast<float>(m.y()));
    }
    cv::cv2eigen(cv::getPerspectiveTransform(img, map), *H);
    return H->allFinite();
  }

  // The placement is the navigation placement corrected by a rigid motion C in map space:
  // H_k = C_k H_nav_k. Image registration gives C_k: the rotation and shift that carry the
  // current frame's matched corners, placed by navigation, onto where the previous frame's
  // placement put them. C_k is then shrunk towards the identity by the anchor gain, so a
  // correction (from navigation noise or registration drift) decays over ~1/gain frames instead
  // of adding up. Chaining corrections rather than homographies (Eq. 6.4) keeps perspective and
  // scale from the attitude and the height above ground, where they cannot accumulate: on the
  // village survey, chained homographies drifted 13 % in scale over a turn (matches on roofs and
  // trees bias the scale of each step) and a fitted scale in C still reached 4.5 %.
  bool Correction(const Registration& r, const Eigen::Matrix3d& H_nav, Eigen::Matrix3d* C) const {
    // Ground corners agree with the correction carried from the previous frame; corners on
    // roofs and tree crowns do not (parallax: a roof 10 m up, seen from 30 m while moving 1 m
    // per frame, is off by half a metre) and would drag the map along the track. So the fit
    // uses the corners within kGroundGatePx of the carried correction, when there are enough.
    constexpr double kGroundGatePx = 3.0;
    std::vector<cv::Point2f> from, to, near_from, near_to;
    // Every tracked corner is a candidate for the gate: over a village the homography's
    // inliers may be the roofs' plane rather than the ground.
    for (size_t i = 0; i < r.tracked_cur.size(); ++i) {
      const Eigen::Vector2d a = Apply(H_nav, Eigen::Vector2d(r.tracked_cur[i].x, r.tracked_cur[i].y));
      const Eigen::Vector2d b = Apply(H_map_prev, Eigen::Vector2d(r.tracked_prev[i].x, r.tracked_prev[i].y));
      const cv::Point2f fa(static_cast<float>(a.x()), static_cast<float>(a.y()));
      const cv::Point2f fb(static_cast<float>(b.x()), static_cast<float>(b.y()));
      if (r.inlier[i]) {
        from.push_back(fa);
        to.push_back(fb);
      }
      if ((Apply(C_prev, a) - b).norm() <= kGroundGatePx) {
        near_from.push_back(fa);
        near_to.push_back(fb);
      }
    }
    if (static_cast<int>(near_from.size()) >= p.registration.min_inliers / 2) {
      from.swap(near_from);
      to.swap(near_to);
    }
    const cv::Mat M = cv::estimateAffinePartial2D(from, to, cv::noArray(), cv::RANSAC, 1.5);
    if (M.empty()) return false;
    const double keep = 1.0 - p.nav_anchor_gain;
    const double angle = keep * std::atan2(M.at<double>(1, 0), M.at<double>(0, 0));
    const Eigen::Vector2d c = Apply(H_nav, Eigen::Vector2d(k.cx, k.cy));
    const Eigen::Vector2d moved(M.at<double>(0, 0) * c.x() + M.at<double>(0, 1) * c.y() + M.at<double>(0, 2),
                                M.at<double>(1, 0) * c.x() + M.at<double>(1, 1) * c.y() + M.at<double>(1, 2));
    const Eigen::Vector2d target = c + keep * (moved - c);
    C->setIdentity();
    C->topLeftCorner<2, 2>() = Eigen::Rotation2Dd(angle).toRotationMatrix();
    C->topRightCorner<2, 1>() = target - C->topLeftCorner<2, 2>() * c;
    return C->allFinite();
  }

  // Why a chained placement (photos without poses) cannot be drawn, or "" when it can. The first
  // frame's pixels are the map's, so its footprint is the image; a chained footprint must stay a
  // convex quadrilateral in front of the camera (no corner at or beyond the horizon) of between
  // a quarter and four times that area: beyond, the chain has stopped describing the ground.
  std::string ChainProblem(const Eigen::Matrix3d& H) const {
    if (!H.allFinite()) return "the chained placement is not finite";
    const std::array<Eigen::Vector2d, 4> corners = ImageCorners(cv::Size(k.width, k.height));
    std::array<Eigen::Vector2d, 4> q;
    for (int i = 0; i < 4; ++i) {
      if (H.row(2).dot(Eigen::Vector3d(corners[i].x(), corners[i].y(), 1.0)) <= 1e-9 * std::abs(H(2, 2)))
        return "the chained placement puts a corner beyond the horizon (the camera is not looking down at the ground)";
      q[i] = Apply(H, corners[i]);
    }
    double area2 = 0.0;
    int turns = 0;
    for (int i = 0; i < 4; ++i) {
      const Eigen::Vector2d a = q[(i + 1) % 4] - q[i], b = q[(i + 2) % 4] - q[(i + 1) % 4];
      turns += a.x() * b.y() - a.y() * b.x() > 0 ? 1 : -1;
      area2 += q[i].x() * q[(i + 1) % 4].y() - q[(i + 1) % 4].x() * q[i].y();
    }
    if (std::abs(turns) != 4) return "the chained placement folds the frame over (it is no longer a view of the ground)";
    const double growth = std::abs(area2) / 2.0 / (static_cast<double>(k.width - 1) * (k.height - 1));
    if (growth > 4.0 || growth < 0.25) {
      char text[160];
      std::snprintf(text, sizeof text,
                    "the chained placement is out of scale (%.2f times the first frame's area: the camera is not "
                    "looking straight down at a plane)", growth);
      return text;
    }
    return "";
  }

  // Map pixels per image pixel at image point q (square root of the Jacobian's determinant).
  static double PixelScale(const Eigen::Matrix3d& H, const Eigen::Vector2d& q) {
    const Eigen::Vector2d a = Apply(H, q);
    Eigen::Matrix2d J;
    J.col(0) = Apply(H, q + Eigen::Vector2d(1, 0)) - a;
    J.col(1) = Apply(H, q + Eigen::Vector2d(0, 1)) - a;
    return std::sqrt(std::abs(J.determinant()));
  }

  Tile& TileAt(int tx, int ty) {
    Tile& t = tiles[TileKey(tx, ty)];
    if (t.bgr.empty()) {
      t.bgr = cv::Mat::zeros(p.tile_px, p.tile_px, CV_8UC3);
      t.mask = cv::Mat::zeros(p.tile_px, p.tile_px, CV_8U);
    }
    return t;
  }

  // Copies between the tiles and a map-aligned patch whose top-left map pixel is `origin`.
  template <class F>
  void ForTiles(const cv::Point& origin, const cv::Size& size, bool create, F&& f) {
    const int T = p.tile_px;
    for (int ty = FloorDiv(origin.y, T); ty <= FloorDiv(origin.y + size.height - 1, T); ++ty)
      for (int tx = FloorDiv(origin.x, T); tx <= FloorDiv(origin.x + size.width - 1, T); ++tx) {
        const cv::Rect tile_rect(tx * T, ty * T, T, T);
        const cv::Rect overlap = tile_rect & cv::Rect(origin, size);
        if (overlap.empty()) continue;
        auto it = tiles.find(TileKey(tx, ty));
        if (it == tiles.end() && !create) continue;
        Tile& tile = it == tiles.end() ? TileAt(tx, ty) : it->second;
        f(tile, overlap - tile_rect.tl(), overlap - origin);
      }
  }

  void Write(const cv::Mat& image, const Eigen::Matrix3d& H_map_img) {
    double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
    for (const Eigen::Vector2d& q : ImageCorners(cv::Size(k.width, k.height))) {
      const Eigen::Vector2d m = Apply(H_map_img, q);
      x0 = std::min(x0, m.x());
      y0 = std::min(y0, m.y());
      x1 = std::max(x1, m.x());
      y1 = std::max(y1, m.y());
    }
    const cv::Point origin(static_cast<int>(std::floor(x0)), static_cast<int>(std::floor(y0)));
    const cv::Size size(static_cast<int>(std::ceil(x1)) - origin.x + 1, static_cast<int>(std::ceil(y1)) - origin.y + 1);
    if (size.width > 20000 || size.height > 20000) return;  // a degenerate placement; never allocate that
    Eigen::Matrix3d shift = Eigen::Matrix3d::Identity();
    shift(0, 2) = -origin.x;
    shift(1, 2) = -origin.y;
    cv::Mat H;
    cv::eigen2cv(Eigen::Matrix3d(shift * H_map_img), H);
    cv::Mat warped, new_mask;
    cv::warpPerspective(image, warped, H, size, cv::INTER_LINEAR, cv::BORDER_CONSTANT);
    cv::warpPerspective(cv::Mat(image.size(), CV_8U, cv::Scalar(255)), new_mask, H, size, cv::INTER_NEAREST,
                        cv::BORDER_CONSTANT);
    // Drop the border pixels that were interpolated with the black outside. The frame's edge
    // often lies on the patch's edge, so the patch's outside must count as empty (OpenCV's
    // default erodes nothing there, which left 1 px dark lines across the map).
    cv::erode(new_mask, new_mask, cv::Mat(), cv::Point(-1, -1), 2, cv::BORDER_CONSTANT, cv::Scalar(0));

    // The map under the patch.
    cv::Mat old = cv::Mat::zeros(size, CV_8UC3), old_mask = cv::Mat::zeros(size, CV_8U);
    ForTiles(origin, size, false, [&](Tile& t, const cv::Rect& in_tile, const cv::Rect& in_patch) {
      t.bgr(in_tile).copyTo(old(in_patch));
      t.mask(in_tile).copyTo(old_mask(in_patch));
    });
    if (p.gain_compensation) Compensate(old, old_mask, new_mask, &warped);
    // Newest on top (Eq. 6.5), feathered: within feather_px of the new frame's edge it fades
    // into the map already there, so the edge leaves no seam; beyond that it replaces it.
    if (p.feather_px > 0) {
      cv::Mat distance;
      cv::distanceTransform(new_mask, distance, cv::DIST_L2, 3);
      for (int v = 0; v < size.height; ++v) {
        const float* dist = distance.ptr<float>(v);
        const uint8_t* had = old_mask.ptr<uint8_t>(v);
        const uint8_t* in = new_mask.ptr<uint8_t>(v);
        const cv::Vec3b* src = warped.ptr<cv::Vec3b>(v);
        cv::Vec3b* dst = old.ptr<cv::Vec3b>(v);
        for (int u = 0; u < size.width; ++u) {
          if (!in[u]) continue;
          const float w = had[u] ? std::min(1.0f, dist[u] / static_cast<float>(p.feather_px)) : 1.0f;
          for (int c = 0; c < 3; ++c)
            dst[u][c] = static_cast<uint8_t>(w * src[u][c] + (1.0f - w) * dst[u][c] + 0.5f);
        }
      }
    } else {
      warped.copyTo(old, new_mask);
    }
    cv::bitwise_or(old_mask, new_mask, old_mask);
    ForTiles(origin, size, true, [&](Tile& t, const cv::Rect& in_tile, const cv::Rect& in_patch) {
      old(in_patch).copyTo(t.bgr(in_tile), new_mask(in_patch));
      old_mask(in_patch).copyTo(t.mask(in_tile));
      // in_patch + origin is the overlap in map pixels, inside this tile.
      changed.insert(TileKey(FloorDiv(in_patch.x + origin.x, p.tile_px), FloorDiv(in_patch.y + origin.y, p.tile_px)));
    });
  }

  // Block-wise gain: per block of the patch and channel, the ratio of the map's brightness to the
  // new frame's over their overlap; blocks without overlap take the frame's overall gain; the
  // grid is interpolated bilinearly across the patch so no block edge shows.
  void Compensate(const cv::Mat& old, const cv::Mat& old_mask, const cv::Mat& new_mask, cv::Mat* warped) const {
    cv::Mat overlap;
    cv::bitwise_and(old_mask, new_mask, overlap);
    const int total = cv::countNonZero(overlap);
    if (total < 500) return;
    const cv::Scalar old_mean = cv::mean(old, overlap), new_mean = cv::mean(*warped, overlap);
    cv::Vec3f global;
    for (int c = 0; c < 3; ++c) global[c] = static_cast<float>(std::clamp((old_mean[c] + 1) / (new_mean[c] + 1), 0.5, 2.0));
    const int B = p.gain_blocks;
    cv::Mat grid(B, B, CV_32FC3);
    for (int by = 0; by < B; ++by)
      for (int bx = 0; bx < B; ++bx) {
        const cv::Rect block(bx * old.cols / B, by * old.rows / B, (bx + 1) * old.cols / B - bx * old.cols / B,
                             (by + 1) * old.rows / B - by * old.rows / B);
        const cv::Mat m = overlap(block);
        cv::Vec3f g = global;
        if (cv::countNonZero(m) > block.area() / 20) {
          const cv::Scalar a = cv::mean(old(block), m), b = cv::mean((*warped)(block), m);
          for (int c = 0; c < 3; ++c) g[c] = static_cast<float>(std::clamp((a[c] + 1) / (b[c] + 1), 0.5, 2.0));
        }
        grid.at<cv::Vec3f>(by, bx) = g;
      }
    cv::Mat gain;
    cv::resize(grid, gain, warped->size(), 0, 0, cv::INTER_LINEAR);
    cv::Mat f;
    warped->convertTo(f, CV_32FC3);
    cv::multiply(f, gain, f);
    f.convertTo(*warped, CV_8UC3);
  }
};

MapStitcher::MapStitcher(const CameraIntrinsics& camera, const StitcherParams& params)
    : impl_(std::make_unique<Impl>(camera, params)) {
  ValidateIntrinsics(camera);
  Require(std::isfinite(params.gsd_m) && params.gsd_m >= 0 && params.gsd_m < 100, "gsd_m must be in [0, 100) m");
  Require(params.tile_px >= 32 && params.tile_px <= 4096, "tile_px must be 32..4096");
  Require(params.nav_anchor_gain >= 0 && params.nav_anchor_gain <= 1, "nav_anchor_gain must be in [0, 1]");
  Require(std::isfinite(params.ground_down_m), "ground_down_m must be finite");
  Require(params.gain_blocks >= 1 && params.gain_blocks <= 32, "gain_blocks must be 1..32");
  Require(params.feather_px >= 0 && params.feather_px <= 500, "feather_px must be 0..500");
  ValidateAlignmentParams(params.alignment);
  Require(params.cross_pairs_per_frame >= 0 && params.cross_pairs_per_frame <= 8, "cross_pairs_per_frame must be 0..8");
  Require(params.cross_min_overlap > 0 && params.cross_min_overlap <= 1, "cross_min_overlap must be in (0, 1]");
  Require(params.blend_bands >= 1 && params.blend_bands <= 8, "blend_bands must be 1..8");
  Require(params.kept_jpeg_quality >= 50 && params.kept_jpeg_quality <= 100, "kept_jpeg_quality must be 50..100");
  Require(params.registration_width_px >= 160 && params.registration_width_px <= 20000,
          "registration_width_px must be 160..20000");
  while (impl_->reduce < 8 && camera.width > impl_->reduce * params.registration_width_px) impl_->reduce *= 2;
  const auto& d = camera.distortion;
  if (d[0] != 0 || d[1] != 0 || d[2] != 0 || d[3] != 0 || d[4] != 0) {
    const cv::Mat K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
    const cv::Mat D = (cv::Mat_<double>(1, 5) << d[0], d[1], d[2], d[3], d[4]);
    cv::initUndistortRectifyMap(K, D, cv::Mat(), K, cv::Size(camera.width, camera.height), CV_32FC1,
                                impl_->undistort_x, impl_->undistort_y);
  }
}
MapStitcher::~MapStitcher() = default;
MapStitcher::MapStitcher(MapStitcher&&) noexcept = default;

StitchStep MapStitcher::Add(const StitchInput& frame) { return Add(Prepare(frame)); }

PreparedFrame MapStitcher::Prepare(StitchInput frame) const {
  const Impl& m = *impl_;
  const auto start = std::chrono::steady_clock::now();
  Require(!frame.T_NC || frame.T_NC->matrix().allFinite(), "pose must be finite");
  const auto size_problem = [&](const cv::Size& size) {
    return "image is " + std::to_string(size.width) + "x" + std::to_string(size.height) + ", the camera's is " +
           std::to_string(m.k.width) + "x" + std::to_string(m.k.height) + " (another camera?)";
  };
  const cv::Size grey_size(m.k.width / m.reduce, m.k.height / m.reduce);  // the registration's
  PreparedFrame out;
  out.utime = frame.utime;
  out.T_NC = frame.T_NC;
  cv::Mat image = frame.image;
  if (image.empty()) {
    Require(!frame.encoded.empty(), "no image (neither pixels nor a file)");
    if (!m.p.live_map && m.undistort_x.empty()) {
      // Only the grey registration image is needed now; the colours wait for the final render.
      out.grey = DecodeGrey(frame.encoded, m.reduce);
      Require(!out.grey.empty(), "not an image");
      // A JPEG's reduced size rounds up, another format's down; the registration's rounds down
      // (the pixels they share are the same).
      const auto fits = [&](int got, int full) { return got == full / m.reduce || got == (full + m.reduce - 1) / m.reduce; };
      if (!fits(out.grey.cols, m.k.width) || !fits(out.grey.rows, m.k.height))
        Require(false, size_problem(cv::imdecode(frame.encoded, cv::IMREAD_UNCHANGED).size()));
      out.grey = out.grey(cv::Rect(cv::Point(0, 0), grey_size));
    } else {
      image = cv::imdecode(frame.encoded, cv::IMREAD_COLOR | cv::IMREAD_IGNORE_ORIENTATION);
      Require(!image.empty(), "not an image");
    }
  }
  if (out.grey.empty()) {
    Require(image.type() == CV_8UC3, "image must be 8-bit BGR");
    Require(image.size() == cv::Size(m.k.width, m.k.height), size_problem(image.size()));
    if (!m.undistort_x.empty()) {
      cv::Mat undistorted;
      cv::remap(image, undistorted, m.undistort_x, m.undistort_y, cv::INTER_LINEAR);
      image = undistorted;
    }
    cv::cvtColor(image, out.grey, cv::COLOR_BGR2GRAY);
    if (m.reduce > 1) cv::resize(out.grey, out.grey, grey_size, 0, 0, cv::INTER_AREA);
    if (m.p.live_map) out.image = image;
  }
  out.features = m.preparing.Features(out.grey);
  const int thumbnail = ThumbnailReduction(cv::Size(m.k.width, m.k.height));
  cv::resize(out.grey, out.thumbnail, cv::Size(m.k.width / thumbnail, m.k.height / thumbnail), 0, 0, cv::INTER_AREA);
  if (m.undistort_x.empty() && !frame.encoded.empty()) out.kept = std::move(frame.encoded);
  else cv::imencode(".jpg", image, out.kept, {cv::IMWRITE_JPEG_QUALITY, m.p.kept_jpeg_quality});
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

StitchStep MapStitcher::Add(PreparedFrame frame) {
  Impl& m = *impl_;
  const auto start = std::chrono::steady_clock::now();
  Require(!frame.grey.empty() && !frame.thumbnail.empty() && !frame.kept.empty() && (frame.image.empty() != m.p.live_map),
          "the frame was not made by this stitcher's Prepare");
  const cv::Mat& grey = frame.grey;

  StitchStep step;
  if (!m.started) {
    Eigen::Vector2d centre;
    if (!frame.T_NC) {
      // No pose: the map is the first frame's pixel grid.
      m.gsd = 1.0;
      m.georeferenced = false;
    } else if (!m.GroundPoint(*frame.T_NC, m.k.cx, m.k.cy, &centre)) {
      step.failure = "the camera does not see the ground";
      return step;
    } else {
      // The map's scale and origin come from the first frame (6.3.1).
      const double range =
          (frame.T_NC->translation() - Eigen::Vector3d(centre.x(), centre.y(), m.p.ground_down_m)).norm();
      m.gsd = m.p.gsd_m > 0 ? m.p.gsd_m : range / std::sqrt(m.k.fx * m.k.fy);
      m.north0 = centre.x();
      m.east0 = centre.y();
      m.georeferenced = true;
    }
  }
  Eigen::Matrix3d H_nav;
  const bool have_nav = m.georeferenced && frame.T_NC && m.NavPlacement(*frame.T_NC, &H_nav);
  Eigen::Matrix3d H;
  if (m.started) {
    step.registration = InFullPixels(m.registration.Register(m.prev_grey, m.prev_features, grey), m.reduce);
    step.registered = step.registration.ok;
    step.failure = step.registration.failure;
  }
  Eigen::Matrix3d C;
  if (step.registered && have_nav && m.Correction(step.registration, H_nav, &C)) {
    H = C * H_nav;
    m.C_prev = C;
  } else if (step.registered && !have_nav) {
    H = m.H_map_prev * step.registration.H_prev_cur;  // Eq. 6.4 alone
    if (const std::string problem = m.ChainProblem(H); !problem.empty()) {
      // Each step is sane (Algorithm 1's gates) but their product is not: a camera that is not
      // looking straight down at a plane (an oblique or panning video) piles perspective up until
      // the footprint crosses the horizon. Such a frame is not placed, and the chain goes on from
      // it, so the frames after it are judged by the same chain.
      step.failure = problem;
      step.registered = false;
      m.H_map_prev = H;
      m.prev_grey = grey;
      m.prev_features = std::move(frame.features);
      step.seconds = frame.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      return step;
    }
  } else if (have_nav) {
    if (step.registered) step.failure = "no similarity between the placements";
    step.registered = false;
    H = H_nav;  // first frame, or Algorithm 1's fallback
    m.C_prev.setIdentity();
  } else if (!m.started && !frame.T_NC) {
    H.setIdentity();  // the first frame defines the pixel map
  } else {
    if (step.failure.empty()) step.failure = "the camera does not see the ground";
    // The next frame registers against this one and chains from the last placement.
    m.prev_grey = grey;
    m.prev_features = std::move(frame.features);
    step.seconds = frame.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return step;
  }
  step.placed = true;
  m.started = true;
  if (m.p.live_map) m.Write(frame.image, H);
  m.H_map_prev = H;
  KeptFrame kept;
  kept.utime = frame.utime;
  kept.registered = step.registered;
  kept.H = H;
  if (have_nav) kept.H_nav = H_nav;
  kept.jpeg = std::move(frame.kept);
  kept.thumbnail = frame.thumbnail;
  m.kept.push_back(std::move(kept));
  m.prev_grey = grey;
  m.prev_features = std::move(frame.features);
  step.seconds = frame.seconds + std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return step;
}

Mosaic MapStitcher::Render() const {
  const Impl& m = *impl_;
  if (m.tiles.empty()) return m.MosaicAt({0, 0});
  const int T = m.p.tile_px;
  cv::Rect content;
  bool any = false;
  for (const auto& [key, tile] : m.tiles) {
    const int tx = static_cast<int>(key >> 32), ty = static_cast<int32_t>(key & 0xffffffff);
    const cv::Rect r = cv::boundingRect(tile.mask);
    if (r.empty()) continue;
    const cv::Rect global(r.x + tx * T, r.y + ty * T, r.width, r.height);
    content = any ? (content | global) : global;
    any = true;
  }
  if (!any) return m.MosaicAt({0, 0});
  Mosaic out = m.MosaicAt(content.tl());
  out.bgr = cv::Mat::zeros(content.size(), CV_8UC3);
  out.mask = cv::Mat::zeros(content.size(), CV_8U);
  for (const auto& [key, tile] : m.tiles) {
    const int tx = static_cast<int>(key >> 32), ty = static_cast<int32_t>(key & 0xffffffff);
    const cv::Rect tile_rect(tx * T, ty * T, T, T);
    const cv::Rect overlap = tile_rect & content;
    if (overlap.empty()) continue;
    tile.bgr(overlap - tile_rect.tl()).copyTo(out.bgr(overlap - content.tl()));
    tile.mask(overlap - tile_rect.tl()).copyTo(out.mask(overlap - content.tl()));
  }
  return out;
}

std::vector<MapTile> MapStitcher::TakeChangedTiles() {
  Impl& m = *impl_;
  std::vector<MapTile> out;
  for (int64_t key : m.changed) {
    const Tile& t = m.tiles.at(key);
    MapTile tile;
    tile.tx = static_cast<int>(key >> 32);
    tile.ty = static_cast<int32_t>(key & 0xffffffff);
    tile.bgr = t.bgr.clone();
    tile.mask = t.mask.clone();
    out.push_back(std::move(tile));
  }
  m.changed.clear();
  return out;
}

MapGrid MapStitcher::grid() const {
  const Impl& m = *impl_;
  return {m.gsd, m.north0, m.east0, m.p.tile_px, m.georeferenced};
}

int MapStitcher::frames() const { return static_cast<int>(impl_->kept.size()); }

Eigen::Vector2d MapStitcher::PlacedCentreNE(int k) const {
  const Impl& m = *impl_;
  return m.GroundNE(Apply(m.kept.at(k).H, Eigen::Vector2d(m.k.cx, m.k.cy)));
}

double MapStitcher::PlacedPixelSize(int k) const {
  const Impl& m = *impl_;
  return Impl::PixelScale(m.kept.at(k).H, Eigen::Vector2d(m.k.cx, m.k.cy)) * m.gsd;
}

AlignmentReport MapStitcher::Align() {
  Impl& m = *impl_;
  AlignmentReport report;
  const int n = static_cast<int>(m.kept.size());
  report.frames = n;
  if (n < 2) {
    report.message = "fewer than two frames";
    return report;
  }
  const auto start = std::chrono::steady_clock::now();
  std::vector<FrameMatches> tracked;  // every pair's tracked points, before the ground gate
  // Pairs of frames to match:
  //  - along the track, the two farthest earlier frames that still overlap by kAlongOverlap: a
  //    long baseline separates the ground from what stands on it (relief displacement grows with
  //    it), and few links between the ends of a line let little bias add up; two neighbouring
  //    partners keep every frame tied to every other;
  //  - across passes, frames that overlap although the path flown between them is much longer
  //    than the distance between them (a neighbouring survey line, a second visit): there the
  //    live map's chain has had the time to drift, so they are what the joint adjustment needs.
  std::vector<std::vector<cv::Point2f>> outline(n);
  std::vector<cv::Rect2f> box(n);
  std::vector<double> area(n), path(n, 0.0);
  std::vector<Eigen::Vector2d> centre(n);
  double short_side = 1e18;
  for (int k = 0; k < n; ++k) {
    for (const Eigen::Vector2d& q : ImageCorners(cv::Size(m.k.width, m.k.height))) {
      const Eigen::Vector2d p = Apply(m.kept[k].H, q);
      outline[k].emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
    }
    box[k] = cv::Rect2f(cv::boundingRect(outline[k]));
    area[k] = cv::contourArea(outline[k]);
    centre[k] = Apply(m.kept[k].H, Eigen::Vector2d(m.k.cx, m.k.cy));
    if (k > 0) path[k] = path[k - 1] + (centre[k] - centre[k - 1]).norm();
    short_side = std::min({short_side, static_cast<double>(box[k].width), static_cast<double>(box[k].height)});
  }
  auto overlap = [&](int a, int b) {
    if ((box[a] & box[b]).empty()) return 0.0;
    std::vector<cv::Point2f> inter;
    return static_cast<double>(cv::intersectConvexConvex(outline[a], outline[b], inter)) / std::min(area[a], area[b]);
  };
  const int reduce = m.reduce;
  const Eigen::Matrix3d R = Enlarge(reduce);
  auto is_cross = [&](int k, int i) { return path[k] - path[i] > (centre[k] - centre[i]).norm() + short_side; };
  std::vector<std::vector<std::pair<int, bool>>> partners_of(n);  // frame, across passes
  for (int k = 1; k < n; ++k) {
    std::vector<std::pair<int, bool>>& partners = partners_of[k];
    int far = k - 1;
    while (far > 0 && !is_cross(k, far - 1) && overlap(k, far - 1) >= kAlongOverlap) --far;
    partners.emplace_back(far, false);
    if (far + 1 < k) partners.emplace_back(far + 1, false);
    // Cross candidates, grouped into runs of consecutive frames (one pass); the best of each run.
    std::vector<std::pair<double, int>> best_of_run;
    int run_end = -2;
    for (int i = 0; i < k; ++i) {
      const bool cross = is_cross(k, i);
      const double o = cross ? overlap(k, i) : 0.0;
      if (o < m.p.cross_min_overlap) continue;
      if (i != run_end + 1) best_of_run.emplace_back(o, i);
      else if (o > best_of_run.back().first) best_of_run.back() = {o, i};
      run_end = i;
    }
    std::sort(best_of_run.rbegin(), best_of_run.rend());
    if (best_of_run.size() > static_cast<size_t>(m.p.cross_pairs_per_frame)) best_of_run.resize(m.p.cross_pairs_per_frame);
    for (const auto& [o, i] : best_of_run) partners.emplace_back(i, true);
  }
  // Every frame's pairs are matched independently, a frame at a time on whichever core is free:
  // neighbouring frames share partners, decoded once into a cache all threads use. Collected in
  // order.
  std::vector<std::vector<FrameMatches>> tracked_of(n);
  DecodedFrames decoded([&](int f) { return DecodeGrey(m.kept[f].jpeg, reduce); });
  cv::parallel_for_(cv::Range(1, n), [&](const cv::Range& range) {
    // Each frame's features are found once, for all its partners. A pair uses no more corners
    // than the ground gate keeps, the strongest where the two frames overlap: so four times
    // that many are found over the frame (a cross-line overlap can be a quarter of it), down
    // to a tenth of the registration's corner quality (relative to the frame's strongest, and
    // the overlap can be its plainest part: at the registration's own quality, 10 of 77
    // cross-line pairs were lost on the village).
    // Descriptor detectors give their keypoints unordered: a pair uses all in the overlap.
    const bool corners = m.p.registration.detector == Detector::kGfttKlt;
    const size_t pair_corners = 4 * kMatchesPerPair;
    RegistrationParams pair_params = m.p.registration;
    pair_params.max_corners = static_cast<int>(corners ? 4 * pair_corners : pair_corners);
    pair_params.corner_quality = 0.1 * m.p.registration.corner_quality;
    const FrameRegistration registration(pair_params);
    for (int k = range.start; k < range.end; ++k) {
      const cv::Mat grey_k = decoded.Get(k);
      const FrameFeatures features_k = registration.Features(grey_k);
      for (const auto& [i, cross] : partners_of[k]) {
        // Frame i warped into frame k's pixels by the live placements, so registration sees two
        // views that differ by the placements' error only (any heading, any line direction);
        // frame k's features are used where the two overlap, a tracking window inside.
        const Eigen::Matrix3d W = m.kept[k].H.inverse() * m.kept[i].H;  // i pixel -> k pixel
        const Eigen::Matrix3d W_small = R.inverse() * W * R;
        const Eigen::Matrix3d W_small_inverse = W_small.inverse();
        const double margin = m.p.registration.klt_window_px;
        const FrameFeatures overlap = features_k.Select(
            [&](const cv::Point2f& p) {
              const Eigen::Vector2d q = Apply(W_small_inverse, Eigen::Vector2d(p.x, p.y));
              return q.x() >= margin && q.y() >= margin && q.x() <= grey_k.cols - 1 - margin &&
                     q.y() <= grey_k.rows - 1 - margin;
            },
            corners ? pair_corners : features_k.points.size());
        cv::Mat W_cv, warped;
        cv::eigen2cv(W_small, W_cv);
        cv::warpPerspective(decoded.Get(i), warped, W_cv, grey_k.size());
        const FeatureMatches r = registration.Match(grey_k, overlap, warped);
        if (!r.failure.empty()) continue;
        FrameMatches fm;
        fm.a = i;
        fm.b = k;
        fm.cross = cross;
        std::vector<Eigen::Vector2d> in_k, in_warped;
        KeepMatches(r.prev, r.cur, pair_corners, &in_k, &in_warped);
        const Eigen::Matrix3d to_i = W.inverse() * R;
        for (size_t j = 0; j < in_k.size(); ++j) {
          fm.p_b.push_back(Apply(R, in_k[j]));
          fm.p_a.push_back(Apply(to_i, in_warped[j]));
        }
        tracked_of[k].push_back(std::move(fm));
      }
    }
  });
  for (std::vector<FrameMatches>& t : tracked_of)
    for (FrameMatches& fm : t) tracked.push_back(std::move(fm));
  // The ground matches of every pair, placed by the live map.
  std::vector<FrameMatches> matches;
  for (const FrameMatches& t : tracked) {
    std::vector<Eigen::Vector2d> x_a, x_b;
    for (size_t j = 0; j < t.p_a.size(); ++j) {
      x_a.push_back(Apply(m.kept[t.a].H, t.p_a[j]));
      x_b.push_back(Apply(m.kept[t.b].H, t.p_b[j]));
    }
    const std::vector<uint8_t> ground =
        GroundMatches(x_a, x_b, centre[t.a] - centre[t.b], kMinGroundMatches);
    FrameMatches g{t.a, t.b, t.cross, {}, {}};
    std::vector<cv::Point2f> ga, gb;
    for (size_t j = 0; j < ground.size(); ++j)
      if (ground[j]) {
        ga.emplace_back(static_cast<float>(t.p_a[j].x()), static_cast<float>(t.p_a[j].y()));
        gb.emplace_back(static_cast<float>(t.p_b[j].x()), static_cast<float>(t.p_b[j].y()));
      }
    if (ga.size() < kMinGroundMatches) continue;
    KeepMatches(ga, gb, kMatchesPerPair, &g.p_a, &g.p_b);
    matches.push_back(std::move(g));
  }
  const auto matched = std::chrono::steady_clock::now();
  report.seconds_matching = std::chrono::duration<double>(matched - start).count();

  std::vector<AlignmentFrame> frames(n);
  std::vector<Eigen::Matrix3d> before(n);
  for (int k = 0; k < n; ++k) {
    const KeptFrame& f = m.kept[k];
    frames[k].H_base = f.H_nav ? *f.H_nav : f.H;
    frames[k].H_start = f.H;
    frames[k].centre_px = Eigen::Vector2d(m.k.cx, m.k.cy);
    frames[k].focal_px = std::sqrt(m.k.fx * m.k.fy);
    frames[k].nav_prior = f.H_nav.has_value();
    before[k] = f.H;
  }
  const AlignmentSolution solution = AlignFrames(frames, matches, m.gsd, m.p.alignment);
  report.seconds_solving = std::chrono::duration<double>(std::chrono::steady_clock::now() - matched).count();
  report.message = solution.message;
  report.iterations = solution.iterations;
  report.matches_dropped = solution.matches_dropped;
  report.pairs_rejected = solution.pairs_rejected;
  // The residuals over the pairs the solve used (a rejected pair matched something that moved).
  std::vector<FrameMatches> used;
  for (size_t i = 0; i < matches.size(); ++i)
    if (solution.pair_used.empty() || solution.pair_used[i]) used.push_back(std::move(matches[i]));
  for (const FrameMatches& g : used) (g.cross ? report.cross_pairs : report.consecutive_pairs) += 1;
  report.cross_before = MatchResiduals(before, used, true);
  report.all_before = MatchResiduals(before, used, false);
  if (!solution.ok) {
    report.cross_after = report.cross_before;
    report.all_after = report.all_before;
    return report;
  }
  for (int k = 0; k < n; ++k) m.kept[k].H = solution.H_map_img[k];
  report.cross_after = MatchResiduals(solution.H_map_img, used, true);
  report.all_after = MatchResiduals(solution.H_map_img, used, false);
  report.adjusted = true;
  return report;
}

Mosaic MapStitcher::RenderSeamless() const {
  const Impl& m = *impl_;
  if (m.kept.empty()) return m.MosaicAt({0, 0});
  std::vector<SeamlessFrame> frames;
  for (const KeptFrame& f : m.kept) frames.push_back({f.H, f.thumbnail});
  const SeamlessMap map = vision::RenderSeamless(frames, cv::Size(m.k.width, m.k.height), cv::Point2d(m.k.cx, m.k.cy),
                                                 m.p.blend_bands,
                                                 [&](int k, const cv::Rect& region, cv::Point* origin) {
                                                   return DecodeRegion(m.kept[k].jpeg, region, origin);
                                                 });
  Mosaic out = m.MosaicAt(map.origin);
  out.bgr = map.bgr;
  out.mask = map.mask;
  return out;
}

std::vector<FramePlacement> MapStitcher::Placements() const {
  const Impl& m = *impl_;
  std::vector<FramePlacement> out;
  for (const KeptFrame& f : m.kept) {
    FramePlacement p;
    p.utime = f.utime;
    p.registered = f.registered;
    p.H_map_img = f.H;
    int i = 0;
    for (const Eigen::Vector2d& q : ImageCorners(cv::Size(m.k.width, m.k.height))) {
      const Eigen::Vector2d px = Apply(f.H, q);
      p.corners_NE[i++] = m.georeferenced ? m.GroundNE(px) : px;
    }
    out.push_back(p);
  }
  return out;
}

size_t MapStitcher::tiles() const { return impl_->tiles.size(); }
size_t MapStitcher::memory_bytes() const {
  size_t kept = 0;
  for (const KeptFrame& f : impl_->kept) kept += f.jpeg.size() + f.thumbnail.total() + sizeof(KeptFrame);
  return impl_->tiles.size() * static_cast<size_t>(impl_->p.tile_px) * impl_->p.tile_px * 4 + kept;
}

}  // namespace uav::vision
