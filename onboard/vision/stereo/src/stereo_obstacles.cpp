#include "uav/vision/stereo_obstacles.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "uav/vision/point_cloud.hpp"

namespace uav::vision {

namespace {
// Fraction of a cluster's points left out at each side when measuring its width.
constexpr double kWidthTail = 0.02;

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("stereo obstacles: " + what);
}

double Milliseconds(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - since).count();
}

double Quantile(std::vector<double> v, double q) {
  const auto k = static_cast<std::ptrdiff_t>(std::lround(q * static_cast<double>(v.size() - 1)));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[static_cast<std::size_t>(k)];
}

// A cluster's horizontal mean and its top and bottom (NED z: top is the least).
struct ClusterExtent {
  Eigen::Vector2d mean_W;
  double top_m, bottom_m;
};
ClusterExtent Extent(const std::vector<Eigen::Vector3f>& points_W, const std::vector<int>& cluster) {
  ClusterExtent e{Eigen::Vector2d::Zero(), std::numeric_limits<double>::infinity(),
                  -std::numeric_limits<double>::infinity()};
  for (int i : cluster) {
    const Eigen::Vector3f& q = points_W[static_cast<std::size_t>(i)];
    e.mean_W += q.head<2>().cast<double>();
    e.top_m = std::min(e.top_m, static_cast<double>(q.z()));
    e.bottom_m = std::max(e.bottom_m, static_cast<double>(q.z()));
  }
  e.mean_W /= static_cast<double>(cluster.size());
  return e;
}

// A tree seen whole is one cluster: a thin trunk under a wide crown. As one cylinder it is as
// wide as the crown from the crown's top to the ground, and a map that leaves wide cylinders to
// their own points (the space under a crown is free) loses the trunk, whose few points the rays
// past it clear. Splits a cluster whose lowest part is much thinner than the whole into that
// part (standing on the ground) and the rest above it, in that order; any other cluster is
// returned whole.
std::vector<std::vector<int>> SplitTrunk(const std::vector<Eigen::Vector3f>& points_W, const std::vector<int>& cluster,
                                         const Eigen::Vector2d& p_W_camera, int min_voxels) {
  // [m] height of the bands the width is measured in; a trunk is thinner than this fraction of
  // the cluster's width over at least this height, with this many voxels.
  constexpr double kBand = 0.25, kThin = 0.4, kMinTrunkHeight = 0.75;
  const ClusterExtent extent = Extent(points_W, cluster);
  const Eigen::Vector2d mean = extent.mean_W;
  const double top = extent.top_m, bottom = extent.bottom_m;
  const int bands = static_cast<int>((bottom - top) / kBand) + 1;
  if ((mean - p_W_camera).norm() < 1e-6 || bands < 2) return {cluster};
  // Across the line of sight: the extent stereo measures best.
  const Eigen::Vector2d dir = (mean - p_W_camera).normalized(), lat(-dir.y(), dir.x());
  std::vector<double> lo(bands, std::numeric_limits<double>::infinity()), hi(bands, -lo[0]);
  std::vector<double> s_all;
  auto band_of = [&](const Eigen::Vector3f& q) { return std::min(bands - 1, static_cast<int>((bottom - q.z()) / kBand)); };
  for (int i : cluster) {
    const Eigen::Vector3f& q = points_W[static_cast<std::size_t>(i)];
    const double s = (q.head<2>().cast<double>() - p_W_camera).dot(lat);
    const int b = band_of(q);
    lo[b] = std::min(lo[b], s), hi[b] = std::max(hi[b], s);
    s_all.push_back(s);
  }
  const double width = Quantile(s_all, 1.0 - kWidthTail) - Quantile(s_all, kWidthTail);
  // The trunk: bands from the bottom up that are thin or empty (hidden behind something).
  int trunk_bands = 0;
  while (trunk_bands < bands && !(hi[trunk_bands] - lo[trunk_bands] > kThin * width)) ++trunk_bands;
  if (trunk_bands * kBand < kMinTrunkHeight || trunk_bands == bands) return {cluster};
  std::vector<int> trunk, crown;
  for (int i : cluster) (band_of(points_W[static_cast<std::size_t>(i)]) < trunk_bands ? trunk : crown).push_back(i);
  if (static_cast<int>(trunk.size()) < min_voxels / 2 || static_cast<int>(crown.size()) < min_voxels / 2) return {cluster};
  return {trunk, crown};
}
}  // namespace

void ObstacleParams::Validate() const {
  disparity.Validate();
  auto positive = [](double x) { return std::isfinite(x) && x > 0; };
  Require(positive(sigma_d_px), "sigma_d_px must be positive");
  Require(std::isfinite(calibration_px) && calibration_px >= 0, "calibration_px must not be negative");
  Require(positive(max_depth_sigma_m), "max_depth_sigma_m must be positive");
  Require(positive(max_disparity_step_px), "max_disparity_step_px must be positive");
  Require(positive(voxel_leaf_m) && voxel_leaf_m <= 1.0, "voxel_leaf_m must be in (0, 1] m");
  Require(positive(ground_tolerance_m), "ground_tolerance_m must be positive");
  Require(std::isfinite(max_ground_tilt_deg) && max_ground_tilt_deg >= 0 && max_ground_tilt_deg < 45,
          "max_ground_tilt_deg must be 0..45");
  Require(positive(cluster_tolerance_m), "cluster_tolerance_m must be positive");
  Require(min_cluster_voxels >= 3, "min_cluster_voxels must be at least 3");
  Require(std::isfinite(safety_margin_m) && safety_margin_m >= 0, "safety_margin_m must not be negative");
}

struct StereoObstacleDetector::Impl {
  RectifiedGeometry geometry;
  ObstacleParams params;
  DisparityMatcher matcher;
  StereoErrorModel model;
  double gate_depth_m = 0.0;
  cv::Matx44d Q;
  Impl(const RectifiedGeometry& g, const ObstacleParams& p) : geometry(g), params(p), matcher(p.disparity) {}
};

StereoObstacleDetector::StereoObstacleDetector(const RectifiedGeometry& g, const ObstacleParams& p) {
  p.Validate();
  Require(g.width >= 16 && g.height >= 16, "image size must be at least 16x16");
  Require(std::isfinite(g.f_px) && g.f_px > 0, "focal length must be positive");
  Require(std::isfinite(g.baseline_m) && g.baseline_m > 0, "baseline must be positive");
  Require(g.R_L_rect.allFinite(), "rectification rotation must be finite");
  impl_ = std::make_unique<Impl>(g, p);
  const std::array<double, 16> q = g.Q(p.disparity.downscale);
  for (int i = 0; i < 16; ++i) {
    Require(std::isfinite(q[i]), "reprojection matrix Q is not finite");
    impl_->Q(i / 4, i % 4) = q[i];
  }
  impl_->model = g.ErrorModel(p.sigma_d_px, p.calibration_px, p.disparity.downscale);
  impl_->gate_depth_m = impl_->model.DepthWhereSigmaReaches(p.max_depth_sigma_m);
}

StereoObstacleDetector::~StereoObstacleDetector() = default;
StereoObstacleDetector::StereoObstacleDetector(StereoObstacleDetector&&) noexcept = default;

const RectifiedGeometry& StereoObstacleDetector::geometry() const { return impl_->geometry; }
const ObstacleParams& StereoObstacleDetector::params() const { return impl_->params; }
void StereoObstacleDetector::SetSafetyMargin(double margin_m) {
  ObstacleParams p = impl_->params;
  p.safety_margin_m = margin_m;
  p.Validate();
  impl_->params = p;
}
const StereoErrorModel& StereoObstacleDetector::error_model() const { return impl_->model; }
double StereoObstacleDetector::GateDepth() const { return impl_->gate_depth_m; }

Eigen::Isometry3d StereoObstacleDetector::LevelCameraPose() {
  Eigen::Isometry3d T_WL = Eigen::Isometry3d::Identity();
  // Camera axes (x right, y down, z forward) in W (x forward/north, y right/east, z down).
  T_WL.linear() << 0, 0, 1,  //
      1, 0, 0,               //
      0, 1, 0;
  return T_WL;
}

StereoObstacles StereoObstacleDetector::Process(const cv::Mat& left_rect, const cv::Mat& right_rect,
                                                const Eigen::Isometry3d& T_WL) const {
  const Impl& m = *impl_;
  const ObstacleParams& P = m.params;
  const RectifiedGeometry& g = m.geometry;
  Require(T_WL.matrix().allFinite(), "camera pose is not finite");
  for (const cv::Mat* image : {&left_rect, &right_rect})
    Require(image->cols == g.width && image->rows == g.height,
            "image is " + std::to_string(image->cols) + "x" + std::to_string(image->rows) + ", the calibration is " +
                std::to_string(g.width) + "x" + std::to_string(g.height));
  StereoObstacles out;
  out.gate_depth_m = m.gate_depth_m;
  out.ground_z_m = std::numeric_limits<double>::quiet_NaN();

  auto t0 = std::chrono::steady_clock::now();
  out.disparity = m.matcher.Compute(left_rect, right_rect);
  out.times.disparity_ms = Milliseconds(t0);

  // Eq. 3.11: (X, Y, Z, W) = Q (u, v, d, 1) in the rectified left frame, then into the left
  // camera frame. Invalid disparities (negative) are skipped.
  t0 = std::chrono::steady_clock::now();
  cv::Mat disparity_px, xyz;
  out.disparity.d16.convertTo(disparity_px, CV_32F, 1.0 / 16.0);
  cv::reprojectImageTo3D(disparity_px, xyz, m.Q, false, CV_32F);
  const Eigen::Matrix3f R_L_rect = g.R_L_rect.cast<float>();
  const Eigen::Matrix3f R_WL = T_WL.linear().cast<float>();
  const Eigen::Vector3f p_W_L = T_WL.translation().cast<float>();
  const double min_depth = m.matcher.MinDepth(g.f_px, g.baseline_m);
  std::vector<Eigen::Vector3f> gated_W;
  out.points_L.reserve(static_cast<std::size_t>(disparity_px.total()) / 2);
  // Depth edges: a step larger than max_disparity_step_px to a 4-neighbour. A pixel whose
  // matching window reaches across such an edge (within half a window of it) matched both
  // surfaces at once: the nearer one bleeds outwards (foreground fattening) and points land
  // between the two, bridging an obstacle to what stands behind it. Those pixels are dropped.
  const float jump = static_cast<float>(P.max_disparity_step_px);
  const int rows = disparity_px.rows, cols = disparity_px.cols;
  cv::Mat edge = cv::Mat::zeros(disparity_px.size(), CV_8U);
  for (int v = 0; v < rows; ++v) {
    const float* d = disparity_px.ptr<float>(v);
    const float* down = disparity_px.ptr<float>(std::min(v + 1, rows - 1));
    uint8_t* e = edge.ptr<uint8_t>(v);
    uint8_t* e_down = edge.ptr<uint8_t>(std::min(v + 1, rows - 1));
    for (int u = 0; u < cols; ++u) {
      if (!(d[u] > 0)) continue;
      if (u + 1 < cols && d[u + 1] > 0 && std::abs(d[u + 1] - d[u]) > jump) e[u] = e[u + 1] = 1;
      if (v + 1 < rows && down[u] > 0 && std::abs(down[u] - d[u]) > jump) e[u] = e_down[u] = 1;
    }
  }
  const int half_window = P.disparity.block_size / 2;
  cv::dilate(edge, edge, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * half_window + 1, 2 * half_window + 1)));
  for (int v = 0; v < rows; ++v) {
    const float* d = disparity_px.ptr<float>(v);
    const uint8_t* e = edge.ptr<uint8_t>(v);
    const cv::Vec3f* p = xyz.ptr<cv::Vec3f>(v);
    for (int u = 0; u < cols; ++u) {
      if (!(d[u] > 0)) continue;
      const Eigen::Vector3f p_L = R_L_rect * Eigen::Vector3f(p[u][0], p[u][1], p[u][2]);
      out.points_L.push_back(p_L);
      if (e[u]) continue;
      // Range gate (thesis 3.5 step 3) where the model's depth error passes its limit.
      if (p[u][2] <= m.gate_depth_m && p[u][2] >= min_depth) gated_W.push_back(R_WL * p_L + p_W_L);
    }
  }
  out.times.reproject_ms = Milliseconds(t0);

  t0 = std::chrono::steady_clock::now();
  out.cloud_W = VoxelDownsample(gated_W, static_cast<float>(P.voxel_leaf_m));
  out.times.voxel_ms = Milliseconds(t0);

  // The ground (or floor) is the largest near-horizontal plane below the camera; objects standing
  // on it would otherwise join into one cluster through it.
  t0 = std::chrono::steady_clock::now();
  std::vector<char> is_ground(out.cloud_W.size(), 0);
  const std::vector<int> ground = PlaneInliers(out.cloud_W, Eigen::Vector3f::UnitZ(),
                                               P.max_ground_tilt_deg * M_PI / 180.0, P.ground_tolerance_m,
                                               std::max(P.min_cluster_voxels, static_cast<int>(out.cloud_W.size() / 10)));
  if (!ground.empty()) {
    std::vector<double> z;
    for (int i : ground) z.push_back(out.cloud_W[static_cast<std::size_t>(i)].z());
    const double ground_z = Quantile(z, 0.5);
    if (ground_z > p_W_L.z() + 2 * P.ground_tolerance_m) {
      out.ground_z_m = ground_z;
      // Everything within the tolerance of the plane's height is ground, inliers or not.
      for (std::size_t i = 0; i < out.cloud_W.size(); ++i)
        if (out.cloud_W[i].z() > ground_z - P.ground_tolerance_m) is_ground[i] = 1;
    }
  }
  std::vector<Eigen::Vector3f> above;
  for (std::size_t i = 0; i < out.cloud_W.size(); ++i)
    if (!is_ground[i]) above.push_back(out.cloud_W[i]);
  out.times.ground_ms = Milliseconds(t0);

  t0 = std::chrono::steady_clock::now();
  const std::vector<std::vector<int>> clusters = EuclideanClusters(above, P.cluster_tolerance_m, P.min_cluster_voxels);
  out.times.cluster_ms = Milliseconds(t0);

  t0 = std::chrono::steady_clock::now();
  const Eigen::Vector2d c = p_W_L.head<2>().cast<double>();
  auto fit = [&](const std::vector<int>& cluster, bool on_trunk) {
    const ClusterExtent extent = Extent(above, cluster);
    const Eigen::Vector2d mean = extent.mean_W;
    const double top = extent.top_m;
    double bottom = extent.bottom_m;
    if ((mean - c).norm() < 1e-6) return;
    // Along the line of sight (t) and across it (s), horizontally.
    const Eigen::Vector2d dir = (mean - c).normalized();
    const Eigen::Vector2d lat(-dir.y(), dir.x());
    std::vector<double> t, s;
    for (int i : cluster) {
      const Eigen::Vector2d q = above[static_cast<std::size_t>(i)].head<2>().cast<double>() - c;
      t.push_back(q.dot(dir));
      s.push_back(q.dot(lat));
    }
    // The width between the 2nd and 98th percentiles: a few voxels left by fattening at the
    // silhouette, or from a surface touching it, would widen the extremes (a 15 cm pole at 3.7 m
    // read 23 cm with min/max, 18 cm with percentiles).
    const double s_lo = Quantile(s, kWidthTail), s_hi = Quantile(s, 1.0 - kWidthTail);
    double radius = 0.5 * (s_hi - s_lo);
    const double s_mid = 0.5 * (s_hi + s_lo);
    // Stereo sees the near side only. For a round object the visible points lie at depth
    // centre - sqrt(r^2 - s^2), whose mean over the width is centre - (pi/4) r: the axis sits
    // (pi/4) r behind the median depth. A cluster deeper than it is wide (a wall seen at a
    // slant, a row of crates) is bounded by its depth extent instead.
    const double t_near = Quantile(t, 0.05), t_far = Quantile(t, 0.95);
    double t_mid = Quantile(t, 0.5) + M_PI / 4.0 * radius;
    const double width = 2.0 * radius;
    if (t_far - t_near > 2.0 * radius) {
      radius = 0.5 * (t_far - t_near);
      t_mid = 0.5 * (t_far + t_near);
    }
    // Eq. 3.6-3.7 along the line of sight, Eq. 3.4-3.5 across it, at the centre's depth.
    const double sigma_t = m.model.DepthSigma(t_mid), sigma_s = m.model.LateralSigma(t_mid);
    // A crown is round: the near half seen of a ball spans about 0.4 of its width in depth
    // (between the 5th and 95th percentiles), and depth noise of sigma_t widens that by 3.3
    // sigma_t. A part above a trunk that is deeper than it is wide, beyond that noise, is
    // several objects joined at range (a thin pole and a tree crown behind it, two poles 2.4 m
    // apart: 1/12 fields' seeds 77 and 31 drew them as one crown 5 m across, over the goal).
    const bool round = t_far - t_near <= width + 2.0 * 1.645 * sigma_t;
    // And not flat: the near cap of a ball stands off the line through its points, seen from
    // above, by 0.14-0.29 of its radius (RMS; the least for crowns near the range gate, of which
    // the view holds the lower part), while a flat face (a wall or a box's side, seen square or
    // at a slant, whose lower part the image's bottom edge cuts away so that it reads as a narrow
    // trunk under a wide top) lies on that line within its depth noise after the voxel grid
    // (0.04-0.08 of the radius: 8-15 cm at 4-7 m). The bar sits between them, nearer the faces:
    // a crown taken for a face loses its far side in the map, a face taken for a crown only
    // widens it (a wall 8 m wide, seen banked, read as a crown 1.2-2.9 m in radius behind itself).
    constexpr double kFlatOffLinePerRadius = 0.10;
    auto flat = [&] {
      double s_mean = 0.0, t_mean = 0.0;
      for (std::size_t i = 0; i < s.size(); ++i) s_mean += s[i], t_mean += t[i];
      s_mean /= static_cast<double>(s.size()), t_mean /= static_cast<double>(t.size());
      Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
      for (std::size_t i = 0; i < s.size(); ++i) {
        const Eigen::Vector2d q(s[i] - s_mean, t[i] - t_mean);
        scatter += q * q.transpose();
      }
      scatter /= static_cast<double>(s.size());
      const double spread_across = 0.5 * (scatter(0, 0) + scatter(1, 1)) -
                                   std::hypot(0.5 * (scatter(0, 0) - scatter(1, 1)), scatter(0, 1));  // the smaller eigenvalue
      return std::sqrt(std::max(0.0, spread_across)) < kFlatOffLinePerRadius * 0.5 * width;
    };
    ObstacleCylinder o;
    o.centre_W.head<2>() = c + t_mid * dir + s_mid * lat;
    // Standing on the ground: the cylinder reaches down to it.
    if (std::isfinite(out.ground_z_m) && bottom > out.ground_z_m - 3 * P.ground_tolerance_m) bottom = out.ground_z_m;
    o.top_m = top;
    o.bottom_m = bottom;
    o.centre_W.z() = 0.5 * (top + bottom);
    o.radius_m = radius;
    o.safety_radius_m = radius + P.safety_margin_m;
    o.range_m = std::max(0.0, t_mid - radius);
    Eigen::Matrix2d R;
    R.col(0) = dir;
    R.col(1) = lat;
    o.cov_xy = R * Eigen::Vector2d(sigma_t * sigma_t, sigma_s * sigma_s).asDiagonal() * R.transpose();
    o.voxels = static_cast<int>(cluster.size());
    o.on_trunk = on_trunk && round && !flat();
    out.obstacles.push_back(o);
  };
  for (const std::vector<int>& cluster : clusters) {
    const std::vector<std::vector<int>> parts = SplitTrunk(above, cluster, c, P.min_cluster_voxels);
    for (std::size_t k = 0; k < parts.size(); ++k) fit(parts[k], k == 1);
  }
  std::sort(out.obstacles.begin(), out.obstacles.end(),
            [](const ObstacleCylinder& a, const ObstacleCylinder& b) { return a.range_m < b.range_m; });
  out.times.cylinders_ms = Milliseconds(t0);
  return out;
}

}  // namespace uav::vision
