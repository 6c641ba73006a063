#include "uav/vision/global_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <ceres/ceres.h>
#include <Eigen/Geometry>
#include "homography.hpp"

namespace uav::vision {

namespace {

void Require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("global alignment: " + what);
}

constexpr int kMoveSize = 6;  // [t_x, t_y, theta, s, g_x, g_y]

// x' = c + (t + exp(s) R(theta) d) / (1 + g . d), d = x - c: a similarity about the frame's
// centre and the perspective of a small camera tilt (g = tilt / height above ground).
template <class T>
void Move(const T* m, const Eigen::Vector2d& x, const Eigen::Vector2d& c, T* out) {
  const T scale = ceres::exp(m[3]);
  const T cs = scale * ceres::cos(m[2]), sn = scale * ceres::sin(m[2]);
  const double dx = x.x() - c.x(), dy = x.y() - c.y();
  const T w = T(1.0) + m[4] * dx + m[5] * dy;
  out[0] = c.x() + (m[0] + cs * dx - sn * dy) / w;
  out[1] = c.y() + (m[1] + sn * dx + cs * dy) / w;
}

// Two frames' placements of one matched ground point agree (in map pixels).
struct MatchCost {
  Eigen::Vector2d x_a, x_b, c_a, c_b;  // base-placed map pixels and the frames' centres
  template <class T>
  bool operator()(const T* m_a, const T* m_b, T* r) const {
    T pa[2], pb[2];
    Move(m_a, x_a, c_a, pa);
    Move(m_b, x_b, c_b, pb);
    r[0] = pa[0] - pb[0];
    r[1] = pa[1] - pb[1];
    return true;
  }
};

// The navigation prior: the move is small, to the navigation solution's own uncertainty.
struct PriorCost {
  double inv_position, inv_yaw, inv_scale, inv_g;  // 1 / sigma in map px, rad, log scale, 1/map px
  template <class T>
  bool operator()(const T* m, T* r) const {
    r[0] = m[0] * inv_position;
    r[1] = m[1] * inv_position;
    r[2] = m[2] * inv_yaw;
    r[3] = m[3] * inv_scale;
    r[4] = m[4] * inv_g;
    r[5] = m[5] * inv_g;
    return true;
  }
};

// Without a navigation prior the tilt is still held to the attitude's uncertainty (a frame that
// only its neighbours tie would otherwise be free to lean).
struct TiltCost {
  double inv_g;
  template <class T>
  bool operator()(const T* m, T* r) const {
    r[0] = m[4] * inv_g;
    r[1] = m[5] * inv_g;
    return true;
  }
};

// The navigation error of consecutive frames is nearly the same (GPS wanders slowly).
struct DriftCost {
  double inv_drift;  // 1 / sigma in map px
  template <class T>
  bool operator()(const T* m_a, const T* m_b, T* r) const {
    r[0] = (m_a[0] - m_b[0]) * inv_drift;
    r[1] = (m_a[1] - m_b[1]) * inv_drift;
    return true;
  }
};

Eigen::Matrix3d MoveMatrix(const double* m, const Eigen::Vector2d& c) {
  const double scale = std::exp(m[3]);
  Eigen::Matrix2d sR;
  sR << scale * std::cos(m[2]), -scale * std::sin(m[2]), scale * std::sin(m[2]), scale * std::cos(m[2]);
  // Move(x) = c + (t + sR d) / (1 + g.d), d = x - c, as a matrix: T(c) [sR t; g^T 1] T(-c).
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M.topLeftCorner<2, 2>() = sR;
  M.topRightCorner<2, 1>() = Eigen::Vector2d(m[0], m[1]);
  M.bottomLeftCorner<1, 2>() = Eigen::Vector2d(m[4], m[5]).transpose();
  Eigen::Matrix3d to_centre = Eigen::Matrix3d::Identity(), from_centre = Eigen::Matrix3d::Identity();
  to_centre.topRightCorner<2, 1>() = -c;
  from_centre.topRightCorner<2, 1>() = c;
  return from_centre * M * to_centre;
}

// The similarity about c that carries the base placement closest to the start placement.
void StartMove(const AlignmentFrame& f, const Eigen::Vector2d& c, double* m) {
  Eigen::Matrix<double, 2, 9> from, to;
  for (int i = 0; i < 9; ++i) {
    const Eigen::Vector2d p = f.centre_px + 100.0 * Eigen::Vector2d(i % 3 - 1, i / 3 - 1);
    from.col(i) = Apply(f.H_base, p);
    to.col(i) = Apply(f.H_start, p);
  }
  const Eigen::Matrix3d S = Eigen::umeyama(from, to, true);
  const Eigen::Matrix2d sR = S.topLeftCorner<2, 2>();
  const double scale = std::sqrt(std::abs(sR.determinant()));
  m[2] = std::atan2(sR(1, 0), sR(0, 0));
  m[3] = std::log(std::max(scale, 1e-6));
  const Eigen::Vector2d t = sR * c + S.topRightCorner<2, 1>() - c;
  m[0] = t.x();
  m[1] = t.y();
  m[4] = m[5] = 0.0;
  if (!std::isfinite(m[0] + m[1] + m[2] + m[3])) m[0] = m[1] = m[2] = m[3] = 0.0;
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  const size_t i = std::min(v.size() - 1, static_cast<size_t>(q * (v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + static_cast<long>(i), v.end());
  return v[i];
}

}  // namespace

void ValidateAlignmentParams(const AlignmentParams& p) {
  auto in = [](double v, double lo, double hi) { return std::isfinite(v) && v > lo && v <= hi; };
  Require(in(p.nav_position_sigma_m, 0, 1000), "nav_position_sigma_m must be in (0, 1000] m");
  Require(in(p.nav_drift_sigma_m, 0, 100), "nav_drift_sigma_m must be in (0, 100] m");
  Require(in(p.nav_yaw_sigma_rad, 0, 1), "nav_yaw_sigma_rad must be in (0, 1] rad");
  Require(in(p.nav_scale_sigma, 0, 1), "nav_scale_sigma must be in (0, 1]");
  Require(in(p.nav_tilt_sigma_rad, 0, 0.5), "nav_tilt_sigma_rad must be in (0, 0.5] rad");
  Require(in(p.match_loss_px, 0, 100), "match_loss_px must be in (0, 100] px");
  Require(in(p.outlier_px, 0, 1000), "outlier_px must be in (0, 1000] px");
  Require(p.max_iterations >= 1 && p.max_iterations <= 1000, "max_iterations must be 1..1000");
}

AlignmentSolution AlignFrames(const std::vector<AlignmentFrame>& frames, const std::vector<FrameMatches>& matches,
                              double gsd_m, const AlignmentParams& params) {
  ValidateAlignmentParams(params);
  Require(std::isfinite(gsd_m) && gsd_m > 0, "gsd_m must be positive");
  const int n = static_cast<int>(frames.size());
  for (const AlignmentFrame& f : frames) {
    Require(f.H_base.allFinite() && f.H_start.allFinite() && f.centre_px.allFinite(), "a frame's placement is not finite");
    Require(std::isfinite(f.focal_px) && f.focal_px > 0, "a frame's focal_px must be positive");
  }
  for (const FrameMatches& fm : matches) {
    Require(fm.a >= 0 && fm.a < n && fm.b >= 0 && fm.b < n && fm.a != fm.b,
            "matches between frames " + std::to_string(fm.a) + " and " + std::to_string(fm.b) + " of " + std::to_string(n));
    Require(fm.p_a.size() == fm.p_b.size(), "matches of frames " + std::to_string(fm.a) + " and " + std::to_string(fm.b) +
                                                 " have " + std::to_string(fm.p_a.size()) + " and " +
                                                 std::to_string(fm.p_b.size()) + " points");
  }
  AlignmentSolution out;
  if (n == 0) {
    out.message = "no frames";
    return out;
  }
  std::vector<Eigen::Vector2d> centre(n);
  std::vector<std::array<double, kMoveSize>> move(n);
  std::vector<double> inv_g(n);  // 1 / sigma of g: the height above ground in map px over the tilt's sigma
  for (int k = 0; k < n; ++k) {
    centre[k] = Apply(frames[k].H_base, frames[k].centre_px);
    StartMove(frames[k], centre[k], move[k].data());
    // Map px per image px at the centre, times the focal length in image px: the height in map px.
    const Eigen::Vector2d& p = frames[k].centre_px;
    const Eigen::Vector2d u = Apply(frames[k].H_base, p + Eigen::Vector2d(1, 0)) - centre[k];
    const Eigen::Vector2d v = Apply(frames[k].H_base, p + Eigen::Vector2d(0, 1)) - centre[k];
    const double map_per_image = std::sqrt(std::abs(u.x() * v.y() - u.y() * v.x()));
    inv_g[k] = std::max(frames[k].focal_px * map_per_image, 1.0) / params.nav_tilt_sigma_rad;
  }
  // The matches in base-placed map pixels, once.
  struct Match {
    int a, b;
    Eigen::Vector2d x_a, x_b;
  };
  std::vector<Match> all;
  out.pair_used.assign(matches.size(), true);
  for (size_t pair = 0; pair < matches.size(); ++pair) {
    const FrameMatches& fm = matches[pair];
    if (frames[fm.a].nav_prior && frames[fm.b].nav_prior && !fm.p_a.empty()) {
      std::vector<double> start_px;
      for (size_t i = 0; i < fm.p_a.size(); ++i)
        start_px.push_back((Apply(frames[fm.a].H_start, fm.p_a[i]) - Apply(frames[fm.b].H_start, fm.p_b[i])).norm());
      const double sigma_m = std::min(std::sqrt(2.0) * params.nav_position_sigma_m,
                                      params.nav_drift_sigma_m * std::sqrt(std::abs(fm.b - fm.a)));
      if (!(Quantile(start_px, 0.5) <= 3.0 * sigma_m / gsd_m + params.outlier_px)) {
        ++out.pairs_rejected;
        out.pair_used[pair] = false;
        continue;
      }
    }
    for (size_t i = 0; i < fm.p_a.size(); ++i) {
      const Match m{fm.a, fm.b, Apply(frames[fm.a].H_base, fm.p_a[i]), Apply(frames[fm.b].H_base, fm.p_b[i])};
      if (m.x_a.allFinite() && m.x_b.allFinite()) all.push_back(m);
    }
  }
  const double inv_position = gsd_m / params.nav_position_sigma_m, inv_drift = gsd_m / params.nav_drift_sigma_m;
  auto solve = [&](const std::vector<Match>& use) {
    ceres::Problem::Options problem_options;
    problem_options.loss_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    ceres::HuberLoss loss(params.match_loss_px);
    ceres::Problem problem(problem_options);
    for (int k = 0; k < n; ++k) problem.AddParameterBlock(move[k].data(), kMoveSize);
    for (const Match& m : use)
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<MatchCost, 2, kMoveSize, kMoveSize>(
                                   new MatchCost{m.x_a, m.x_b, centre[m.a], centre[m.b]}),
                               &loss, move[m.a].data(), move[m.b].data());
    bool any_prior = false;
    int previous_nav = -1;
    for (int k = 0; k < n; ++k) {
      if (!frames[k].nav_prior) {
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<TiltCost, 2, kMoveSize>(new TiltCost{inv_g[k]}), nullptr,
                                 move[k].data());
        continue;
      }
      any_prior = true;
      problem.AddResidualBlock(new ceres::AutoDiffCostFunction<PriorCost, 6, kMoveSize>(new PriorCost{
                                   inv_position, 1.0 / params.nav_yaw_sigma_rad, 1.0 / params.nav_scale_sigma, inv_g[k]}),
                               nullptr, move[k].data());
      if (previous_nav >= 0)
        problem.AddResidualBlock(new ceres::AutoDiffCostFunction<DriftCost, 2, kMoveSize, kMoveSize>(new DriftCost{inv_drift}),
                                 nullptr, move[previous_nav].data(), move[k].data());
      previous_nav = k;
    }
    if (!any_prior) problem.SetParameterBlockConstant(move[0].data());  // the first frame holds the gauge
    ceres::Solver::Options options;
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.max_num_iterations = params.max_iterations;
    options.num_threads = 2;
    options.logging_type = ceres::SILENT;
    ceres::Solver::Summary summary;
    ceres::Solve(options, &problem, &summary);
    out.iterations += static_cast<int>(summary.iterations.size());
    out.message = summary.BriefReport();
    return summary.IsSolutionUsable();
  };
  if (!solve(all)) return out;
  // Once more without the matches that still disagree: points off the ground plane (roofs,
  // crowns) and moving things, which a homography's RANSAC can let through.
  std::vector<Match> kept;
  for (const Match& m : all) {
    double pa[2], pb[2];
    Move(move[m.a].data(), m.x_a, centre[m.a], pa);
    Move(move[m.b].data(), m.x_b, centre[m.b], pb);
    if (std::hypot(pa[0] - pb[0], pa[1] - pb[1]) <= params.outlier_px) kept.push_back(m);
  }
  out.matches_used = static_cast<int>(kept.size());
  out.matches_dropped = static_cast<int>(all.size() - kept.size());
  if (out.matches_dropped > 0 && !solve(kept)) return out;
  out.H_map_img.resize(n);
  for (int k = 0; k < n; ++k) out.H_map_img[k] = MoveMatrix(move[k].data(), centre[k]) * frames[k].H_base;
  out.ok = true;
  return out;
}

ResidualStats MatchResiduals(const std::vector<Eigen::Matrix3d>& H_map_img, const std::vector<FrameMatches>& matches,
                             bool cross_only) {
  std::vector<double> d;
  for (const FrameMatches& fm : matches) {
    if (cross_only && !fm.cross) continue;
    if (fm.a >= static_cast<int>(H_map_img.size()) || fm.b >= static_cast<int>(H_map_img.size())) continue;
    for (size_t i = 0; i < fm.p_a.size(); ++i)
      d.push_back((Apply(H_map_img[fm.a], fm.p_a[i]) - Apply(H_map_img[fm.b], fm.p_b[i])).norm());
  }
  ResidualStats s;
  s.matches = static_cast<int>(d.size());
  s.median_px = Quantile(d, 0.5);
  s.p95_px = Quantile(d, 0.95);
  return s;
}

}  // namespace uav::vision
