#include "uav/vision/mono_depth.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <opencv2/calib3d.hpp>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace uav::vision {
namespace {

[[noreturn]] void Bad(const std::string& what) { throw std::invalid_argument("mono depth: " + what); }

std::string Format(const char* fmt, double a, double b = 0.0) {
  char buf[160];
  std::snprintf(buf, sizeof buf, fmt, a, b);
  return buf;
}

}  // namespace

void MonoDepthParams::Validate() const {
  auto need = [](bool ok, const char* what) {
    if (!ok) Bad(what);
  };
  need(max_features >= 12 && max_features <= 5000, "max_features must be 12..5000");
  need(feature_quality > 0 && feature_quality < 1, "feature_quality must be in (0, 1)");
  need(min_feature_distance_px >= 1, "min_feature_distance_px must be at least 1");
  need(border_px >= 0, "border_px must not be negative");
  need(lk_window_px >= 5 && lk_levels >= 0 && lk_levels <= 6, "lk_window_px must be >= 5 and lk_levels 0..6");
  need(max_forward_backward_px > 0, "max_forward_backward_px must be positive");
  need(flow_noise_px > 0 && process_noise >= 0, "flow_noise_px must be positive and process_noise not negative");
  need(gate_sigma > 0 && max_outliers >= 1, "gate_sigma must be positive and max_outliers at least 1");
  need(min_parallax_px >= 0, "min_parallax_px must not be negative");
  need(converged_rel_sigma > 0 && converged_updates >= 1, "converged_rel_sigma must be positive, converged_updates >= 1");
  need(max_measurement_age_s > 0, "max_measurement_age_s must be positive");
  need(grid_cols >= 1 && grid_rows >= 1 && grid_cols * grid_rows <= 64, "the grid must have 1..64 cells");
  need(min_cell_features >= 1, "min_cell_features must be at least 1");
  need(std::isfinite(obstacle_depth_m) && obstacle_depth_m > 0, "obstacle_depth_m must be positive");
}

struct MonoDepthEstimator::Impl {
  struct Feature {
    cv::Point2f px;
    bool initialised = false;
    double z = 0.0, p = 0.0;  // EKF state Z [m] (camera frame, along the optical axis) and its variance
    int updates = 0, outliers = 0;
    int64_t last_measured_utime = 0;
  };
  CameraIntrinsics k;
  MonoDepthParams p;
  cv::Mat K, dist;
  cv::Mat prev_gray;
  int64_t prev_utime = -1;
  std::optional<Eigen::Isometry3d> prev_T_NC;
  std::optional<Eigen::Vector3d> prev_v_N;
  std::vector<Feature> tracks;
  std::vector<DepthFeature> published;

  int CellOf(const cv::Point2f& q) const {
    const int c = std::clamp(static_cast<int>(q.x * p.grid_cols / k.width), 0, p.grid_cols - 1);
    const int r = std::clamp(static_cast<int>(q.y * p.grid_rows / k.height), 0, p.grid_rows - 1);
    return r * p.grid_cols + c;
  }

  std::vector<cv::Point2f> Normalised(const std::vector<cv::Point2f>& px) const {
    std::vector<cv::Point2f> n;
    if (!px.empty()) cv::undistortPoints(px, n, K, dist);
    return n;
  }

  // Fills every cell up to its share of max_features with new corners away from the tracked ones.
  void Replenish(const cv::Mat& gray) {
    const int cells = p.grid_cols * p.grid_rows;
    const int share = std::max(1, p.max_features / cells);
    std::vector<int> count(cells, 0);
    for (const Feature& f : tracks) ++count[CellOf(f.px)];
    cv::Mat mask(gray.size(), CV_8U, cv::Scalar(0));
    cv::rectangle(mask, cv::Rect(p.border_px, p.border_px, gray.cols - 2 * p.border_px, gray.rows - 2 * p.border_px),
                  cv::Scalar(255), cv::FILLED);
    for (const Feature& f : tracks) cv::circle(mask, f.px, static_cast<int>(p.min_feature_distance_px), cv::Scalar(0), cv::FILLED);
    for (int c = 0; c < cells; ++c) {
      const int missing = share - count[c];
      if (missing <= share / 4) continue;  // top up only when a quarter is gone
      const int col = c % p.grid_cols, row = c / p.grid_cols;
      const cv::Rect roi(col * k.width / p.grid_cols, row * k.height / p.grid_rows, k.width / p.grid_cols, k.height / p.grid_rows);
      std::vector<cv::Point2f> corners;
      cv::goodFeaturesToTrack(gray(roi), corners, missing, p.feature_quality, p.min_feature_distance_px, mask(roi));
      for (const cv::Point2f& q : corners) {
        Feature f;
        f.px = q + cv::Point2f(static_cast<float>(roi.x), static_cast<float>(roi.y));
        tracks.push_back(f);
      }
    }
  }

  DepthGrid Grid(int64_t utime, bool healthy, const std::string& reason, int tracked, int measured) {
    DepthGrid g;
    g.utime = utime;
    g.cols = p.grid_cols;
    g.rows = p.grid_rows;
    g.healthy = healthy;
    g.reason = reason;
    g.tracked = tracked;
    g.measured = measured;
    g.obstacle_depth_m = p.obstacle_depth_m;
    g.cells.assign(p.grid_cols * p.grid_rows, DepthCell{});
    std::vector<double> sum_z(g.cells.size(), 0.0), sum_p(g.cells.size(), 0.0);
    published.clear();
    for (const Feature& f : tracks) {
      DepthFeature d;
      d.px = f.px;
      d.depth_m = f.initialised ? f.z : 0.0;
      d.sigma_m = f.initialised ? std::sqrt(f.p) : 0.0;
      d.converged = healthy && f.initialised && f.updates >= p.converged_updates && f.z > 0 &&
                    std::sqrt(f.p) / f.z <= p.converged_rel_sigma &&
                    (utime - f.last_measured_utime) * 1e-6 <= p.max_measurement_age_s;
      published.push_back(d);
      if (!d.converged) continue;
      const int c = CellOf(f.px);
      ++g.cells[c].features;
      sum_z[c] += f.z;
      sum_p[c] += f.p;
    }
    for (std::size_t c = 0; c < g.cells.size(); ++c) {
      DepthCell& cell = g.cells[c];
      if (!healthy) {
        cell.reason = reason;
        continue;
      }
      if (cell.features < p.min_cell_features) {
        cell.reason = measured == 0 && !reason.empty() ? reason
                                                        : Format("%.0f converged features (%.0f needed)", cell.features, p.min_cell_features);
        continue;
      }
      const double n = cell.features;
      cell.depth_m = sum_z[c] / n;  // the thesis averages the features' depths in each cell
      cell.sigma_m = std::sqrt(sum_p[c]) / n;
      cell.state = cell.depth_m < p.obstacle_depth_m ? CellState::kObstacle : CellState::kFree;
      cell.confidence = std::clamp(std::min(1.0, n / (2.0 * p.min_cell_features)) *
                                       (1.0 - cell.sigma_m / cell.depth_m / p.converged_rel_sigma), 0.0, 1.0);
    }
    return g;
  }

  DepthGrid Unusable(int64_t utime, const std::string& reason) {
    // The flow restarts from the next good frame; the features' filters are kept.
    prev_gray.release();
    prev_T_NC.reset();
    return Grid(utime, false, reason, 0, 0);
  }
};

MonoDepthEstimator::MonoDepthEstimator(const CameraIntrinsics& camera, const MonoDepthParams& params)
    : impl_(std::make_unique<Impl>()) {
  ValidateIntrinsics(camera);
  params.Validate();
  impl_->k = camera;
  impl_->p = params;
  impl_->K = (cv::Mat_<double>(3, 3) << camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  impl_->dist = cv::Mat(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) impl_->dist.at<double>(i) = camera.distortion[i];
}
MonoDepthEstimator::~MonoDepthEstimator() = default;
MonoDepthEstimator::MonoDepthEstimator(MonoDepthEstimator&&) noexcept = default;
MonoDepthEstimator& MonoDepthEstimator::operator=(MonoDepthEstimator&&) noexcept = default;

const std::vector<DepthFeature>& MonoDepthEstimator::features() const { return impl_->published; }
const MonoDepthParams& MonoDepthEstimator::params() const { return impl_->p; }

DepthGrid MonoDepthEstimator::Update(const cv::Mat& image, int64_t utime, const std::optional<Eigen::Isometry3d>& T_NC,
                                     const std::optional<Eigen::Vector3d>& v_N) {
  Impl& m = *impl_;
  const MonoDepthParams& p = m.p;
  if (image.empty() || image.depth() != CV_8U || (image.channels() != 1 && image.channels() != 3))
    return m.Unusable(utime, "the image is empty or not 8-bit grey or BGR");
  if (image.cols != m.k.width || image.rows != m.k.height)
    return m.Unusable(utime, "the image is " + std::to_string(image.cols) + "x" + std::to_string(image.rows) + ", the calibration " +
                                 std::to_string(m.k.width) + "x" + std::to_string(m.k.height));
  if (m.prev_utime >= 0 && utime <= m.prev_utime) return m.Unusable(utime, "frame time is not after the previous frame's");
  if (!T_NC) {
    m.prev_utime = utime;
    return m.Unusable(utime, "no navigation sample for this frame");
  }
  if (!T_NC->matrix().allFinite() || (v_N && !v_N->allFinite())) {
    m.prev_utime = utime;
    return m.Unusable(utime, "the navigation pose or velocity is not finite");
  }
  cv::Mat gray;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else gray = image;

  int tracked = 0, measured = 0;
  std::string reason;
  if (!m.prev_gray.empty() && m.prev_T_NC && !m.tracks.empty()) {
    // Lucas-Kanade forward, then back: a feature that does not return to where it was is dropped.
    std::vector<cv::Point2f> prev_px, cur_px, back_px;
    for (const auto& f : m.tracks) prev_px.push_back(f.px);
    std::vector<uchar> ok_fwd, ok_back;
    std::vector<float> err;
    const cv::Size win(p.lk_window_px, p.lk_window_px);
    cv::calcOpticalFlowPyrLK(m.prev_gray, gray, prev_px, cur_px, ok_fwd, err, win, p.lk_levels);
    cv::calcOpticalFlowPyrLK(gray, m.prev_gray, cur_px, back_px, ok_back, err, win, p.lk_levels);
    const cv::Rect2f inside(static_cast<float>(p.border_px), static_cast<float>(p.border_px),
                            static_cast<float>(m.k.width - 2 * p.border_px), static_cast<float>(m.k.height - 2 * p.border_px));
    std::vector<Impl::Feature> kept;
    std::vector<cv::Point2f> kept_prev, kept_cur;
    for (std::size_t i = 0; i < m.tracks.size(); ++i) {
      if (!ok_fwd[i] || !ok_back[i] || !inside.contains(cur_px[i]) ||
          cv::norm(back_px[i] - prev_px[i]) > p.max_forward_backward_px)
        continue;
      Impl::Feature f = m.tracks[i];
      f.px = cur_px[i];
      kept.push_back(f);
      kept_prev.push_back(prev_px[i]);
      kept_cur.push_back(cur_px[i]);
    }
    m.tracks = std::move(kept);
    tracked = static_cast<int>(m.tracks.size());

    // The camera's motion between the frames from the navigation poses: angular velocity from
    // the relative rotation, linear velocity resolved in the camera at mid-interval (thesis 3.4.1:
    // w^C = R_B^C w^B, v^C = R_B^C v^B; here straight from the camera poses, which carry R_BC).
    const double dt = (utime - m.prev_utime) * 1e-6;
    const Eigen::Matrix3d R_prev = m.prev_T_NC->linear(), R_cur = T_NC->linear();
    const Eigen::AngleAxisd rel(R_prev.transpose() * R_cur);
    const Eigen::Vector3d w_C = rel.axis() * rel.angle() / dt;
    const Eigen::Matrix3d R_mid = R_prev * Eigen::AngleAxisd(0.5 * rel.angle(), rel.axis()).toRotationMatrix();
    const Eigen::Vector3d v_mid_N = v_N && m.prev_v_N ? Eigen::Vector3d(0.5 * (*v_N + *m.prev_v_N))
                                                      : Eigen::Vector3d((T_NC->translation() - m.prev_T_NC->translation()) / dt);
    const Eigen::Vector3d v_C = R_mid.transpose() * v_mid_N;
    const double f_px = 0.5 * (m.k.fx + m.k.fy);
    // Flow noise in normalised units per second (two positions, each flow_noise_px).
    const double sigma_b = std::sqrt(2.0) * p.flow_noise_px / f_px / dt;
    if (v_C.norm() * dt < 1e-3) reason = Format("no parallax: the camera moved %.1f mm between frames", v_C.norm() * dt * 1e3);

    const std::vector<cv::Point2f> n_prev = m.Normalised(kept_prev), n_cur = m.Normalised(kept_cur);
    for (std::size_t i = 0; i < m.tracks.size(); ++i) {
      Impl::Feature& f = m.tracks[i];
      const double x = 0.5 * (n_prev[i].x + n_cur[i].x), y = 0.5 * (n_prev[i].y + n_cur[i].y);
      const Eigen::Vector2d flow((n_cur[i].x - n_prev[i].x) / dt, (n_cur[i].y - n_prev[i].y) / dt);
      // Eq. 3.26 over the interval: dZ/dt = (w_y x - w_x y) Z - v_z.
      const double rot = w_C.y() * x - w_C.x() * y;
      if (f.initialised) {
        const double F = 1.0 + dt * rot;
        f.z = f.z + dt * (rot * f.z - v_C.z());
        f.p = F * F * f.p + std::pow(p.process_noise * f.z, 2) * dt;
      }
      // Eq. 3.22-3.25: b = flow - B(x, y) w^C = A(x, y) v^C / Z, solved for 1/Z by least squares.
      Eigen::Matrix<double, 2, 3> B;
      B << x * y, -(1 + x * x), y, 1 + y * y, -x * y, -x;
      Eigen::Matrix<double, 2, 3> M;
      M << -1, 0, x, 0, -1, y;
      const Eigen::Vector2d b = flow - B * w_C;
      const Eigen::Vector2d a = M * v_C;
      const double aa = a.squaredNorm();
      if (aa <= 0) continue;
      const double inv_z = a.dot(b) / aa;
      const double sigma_inv_z = sigma_b / std::sqrt(aa);
      // No depth from this frame when the translation moves the feature too little to see, or
      // the inverse depth is not clearly positive (far away, or noise).
      if (std::sqrt(aa) * inv_z * dt * f_px < p.min_parallax_px || inv_z < p.gate_sigma * sigma_inv_z) continue;
      // Eq. 3.24 has two rows for one unknown: the flow across the direction the translation
      // moves the feature must be noise. More is a point that does not exist in the world (a
      // T-junction where an edge crosses an occluded one slides along it) or that moves: no
      // measurement, and a feature that keeps doing it is renewed.
      if ((b - a * inv_z).norm() > p.gate_sigma * sigma_b) {
        if (++f.outliers >= p.max_outliers) f = Impl::Feature{f.px};
        continue;
      }
      // Z at mid-interval, carried to this frame by Eq. 3.26 over the half step.
      double z_meas = 1.0 / inv_z;
      z_meas += 0.5 * dt * (rot * z_meas - v_C.z());
      const double r = std::pow(sigma_inv_z * z_meas * z_meas, 2);  // Eq. 3.27's eps_2, from the flow noise
      if (!f.initialised) {
        f.initialised = true;
        f.z = z_meas;
        f.p = r;
        f.updates = 1;
        f.last_measured_utime = utime;
        ++measured;
        continue;
      }
      const double nu = z_meas - f.z, s = f.p + r;
      if (nu * nu > p.gate_sigma * p.gate_sigma * s) {
        if (++f.outliers >= p.max_outliers) f = Impl::Feature{f.px};  // renewed: starts again
        continue;
      }
      const double gain = f.p / s;
      f.z += gain * nu;
      f.p *= 1.0 - gain;
      f.outliers = 0;
      ++f.updates;
      f.last_measured_utime = utime;
      ++measured;
    }
  }
  m.Replenish(gray);
  m.prev_gray = gray.clone();
  m.prev_utime = utime;
  m.prev_T_NC = T_NC;
  m.prev_v_N = v_N;
  return m.Grid(utime, true, reason, tracked, measured);
}

}  // namespace uav::vision
