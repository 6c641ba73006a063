#include "uav/vision/stereo_vo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <Eigen/SVD>
#include <opencv2/calib3d.hpp>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace uav::vision {
namespace {

// Whether a tracked pixel q lies in an image of `size`.
bool Inside(const cv::Point2f& q, const cv::Size& size) {
  return q.x >= 0 && q.y >= 0 && q.x <= size.width - 1 && q.y <= size.height - 1;
}

std::string Format(const char* fmt, double a, double b = 0, double c = 0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// Euler angles of the thesis (Eq. 5.30-5.31, z-y-x) and back: the LM's rotation parameters (5.5).
Eigen::Matrix3d RotationFromEuler(double phi, double theta, double psi) {
  return (Eigen::AngleAxisd(psi, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(phi, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}
Eigen::Vector3d EulerFromRotation(const Eigen::Matrix3d& r) {
  return {std::atan2(r(2, 1), r(2, 2)), std::atan2(-r(2, 0), std::hypot(r(2, 1), r(2, 2))), std::atan2(r(1, 0), r(0, 0))};
}

// One correspondence from the keyframe to the current frame.
struct Match {
  int keyframe_index;
  Eigen::Vector3d p_K;           // triangulated in the keyframe (with the disparity offset as now estimated)
  cv::Point2f px_K;              // its measurement there: left pixel (the row averaged over both images) ...
  float disparity_K = 0;         // ... and the disparity as matched [px], before the offset
  cv::Point2f px_C;              // tracked into the current left image
  std::optional<Eigen::Vector3d> p_C;  // triangulated in the current frame
  std::optional<float> u_R;            // the current right image's column on the same row
};

// The spread of disparities (10th to 90th percentile) a keyframe's points need to measure the
// rig's disparity offset (see StereoVo::Impl::OffsetFromFrame).
constexpr double kOffsetDepthSpan = 3.0;

// A rectified pair's pixel, row and matched disparity to a point in the left camera (thesis 3.2,
// Eq. 3.11), the disparity corrected by `offset` px (see StereoVo::Impl::disparity_offset).
Eigen::Vector3d Triangulated(const RectifiedGeometry& g, double u, double v, double disparity, double offset) {
  const double z = g.f_px * g.baseline_m / (disparity + offset);
  return {(u - g.cx) * z / g.f_px, (v - g.cy) * z / g.f_px, z};
}

// Thesis 5.5: LM over the three Euler angles and the translation, the Jacobian by forward
// differences. A subclass gives the residuals of a pose T_CK.
Eigen::Isometry3d PoseOf(const cv::Mat& x) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = RotationFromEuler(x.at<double>(0), x.at<double>(1), x.at<double>(2));
  T.translation() = Eigen::Vector3d(x.at<double>(3), x.at<double>(4), x.at<double>(5));
  return T;
}
cv::Mat ParamsOf(const Eigen::Isometry3d& T) {
  const Eigen::Vector3d e = EulerFromRotation(T.linear());
  return (cv::Mat_<double>(6, 1) << e.x(), e.y(), e.z(), T.translation().x(), T.translation().y(), T.translation().z());
}

// A rotation prior (gyro-aided odometry): the IMU's rotation of the current frame from the
// keyframe, and `weight`, the inverse of the lower Cholesky factor of its covariance (residual
// units per radian). It adds three residuals, weight times the rotation vector of
// R_CK R_CK(prior)^T (a small rotation in the current camera's frame).
struct RotationPrior {
  Eigen::Matrix3d R_CK;
  Eigen::Matrix3d weight;
};
Eigen::Vector3d FromPrior(const Eigen::Matrix3d& R_CK, const RotationPrior& prior) {
  const Eigen::AngleAxisd d(R_CK * prior.R_CK.transpose());
  return d.angle() * d.axis();
}

class PoseResiduals : public cv::LMSolver::Callback {
 public:
  PoseResiduals(double angle_step, std::optional<RotationPrior> prior) : angle_step_(angle_step), prior_(prior) {}
  bool compute(cv::InputArray param, cv::OutputArray err, cv::OutputArray J) const override {
    const cv::Mat x = param.getMat();
    const std::vector<double> e0 = AllErrors(PoseOf(x));
    cv::Mat(e0).copyTo(err);
    if (J.needed()) {
      J.create(static_cast<int>(e0.size()), 6, CV_64F);
      cv::Mat Jm = J.getMat();
      for (int j = 0; j < 6; ++j) {
        cv::Mat xh = x.clone();
        const double h = j < 3 ? angle_step_ : 1e-6;
        xh.at<double>(j) += h;
        const std::vector<double> e1 = AllErrors(PoseOf(xh));
        for (size_t i = 0; i < e0.size(); ++i) Jm.at<double>(static_cast<int>(i), j) = (e1[i] - e0[i]) / h;
      }
    }
    return true;
  }
 protected:
  virtual std::vector<double> Errors(const Eigen::Isometry3d& T_CK) const = 0;

 private:
  std::vector<double> AllErrors(const Eigen::Isometry3d& T_CK) const {
    std::vector<double> e = Errors(T_CK);
    if (prior_) {
      const Eigen::Vector3d r = prior_->weight * FromPrior(T_CK.linear(), *prior_);
      e.insert(e.end(), {r.x(), r.y(), r.z()});
    }
    return e;
  }
  double angle_step_;
  std::optional<RotationPrior> prior_;
};

// Runs LM (20 iterations) from T0; T0 again when it ends in non-finite numbers.
Eigen::Isometry3d RefineLm(const cv::Ptr<PoseResiduals>& residuals, const Eigen::Isometry3d& T0) {
  cv::Mat x = ParamsOf(T0);
  cv::LMSolver::create(residuals, 20)->run(x);
  return cv::checkRange(x) ? PoseOf(x) : T0;
}

// Eq. 5.21 for the rigid method: the 3-D residuals, each weighted by its depth's sigma.
class RigidResiduals : public PoseResiduals {
 public:
  RigidResiduals(const std::vector<Eigen::Vector3d>& P, const std::vector<Eigen::Vector3d>& Q,
                 const std::vector<double>& inv_sigma, std::optional<RotationPrior> prior)
      : PoseResiduals(1e-6, prior), P_(P), Q_(Q), inv_sigma_(inv_sigma) {}

 private:
  std::vector<double> Errors(const Eigen::Isometry3d& T) const override {
    std::vector<double> e;
    e.reserve(3 * P_.size());
    for (size_t i = 0; i < P_.size(); ++i) {
      const Eigen::Vector3d r = (T * P_[i] - Q_[i]) * inv_sigma_[i];
      e.insert(e.end(), {r.x(), r.y(), r.z()});
    }
    return e;
  }
  const std::vector<Eigen::Vector3d>& P_;
  const std::vector<Eigen::Vector3d>& Q_;
  const std::vector<double>& inv_sigma_;
};

// Eq. 5.21 for PnP, in both cameras of the pair: the keyframe's points reprojected into the
// current left image (u, v) and, where the current pair matched them, into the right one (u; the
// row is the same after rectification). The right camera's column pins the depth along the motion
// that a single image leaves free to trade against a rotation.
// One point's stereo reprojection errors (Eq. 5.21 in both cameras): c is the point in the
// current left camera; the right column sits the disparity offset to the right of the true one
// (true disparity = measured + offset).
void AppendStereoErrors(const Eigen::Vector3d& c, const Match& m, double f, double cx, double cy, double b, double offset,
                        std::vector<double>& e) {
  const double z = std::max(c.z(), 1e-3);
  e.push_back(f * c.x() / z + cx - m.px_C.x);
  e.push_back(f * c.y() / z + cy - m.px_C.y);
  if (m.u_R) e.push_back(f * (c.x() - b) / z + cx + offset - *m.u_R);
}

class StereoReprojection : public PoseResiduals {
 public:
  StereoReprojection(const std::vector<Match>& m, const std::vector<int>& in, double f, double cx, double cy, double b,
                     double disparity_offset, std::optional<RotationPrior> prior)
      : PoseResiduals(1e-7, prior), m_(m), in_(in), f_(f), cx_(cx), cy_(cy), b_(b), offset_(disparity_offset) {}

 private:
  std::vector<double> Errors(const Eigen::Isometry3d& T) const override {
    std::vector<double> e;
    e.reserve(3 * in_.size());
    for (int i : in_) AppendStereoErrors(T * m_[i].p_K, m_[i], f_, cx_, cy_, b_, offset_, e);
    return e;
  }
  const std::vector<Match>& m_;
  const std::vector<int>& in_;
  double f_, cx_, cy_, b_, offset_;
};

}  // namespace

const char* Name(VoMethod m) {
  switch (m) {
    case VoMethod::kPnp: return "pnp";
    case VoMethod::kEpnp: return "epnp";
    case VoMethod::kRigid: return "rigid";
  }
  return "?";
}

std::optional<VoMethod> ParseVoMethod(std::string_view name) {
  for (VoMethod m : {VoMethod::kPnp, VoMethod::kEpnp, VoMethod::kRigid})
    if (name == Name(m)) return m;
  return std::nullopt;
}

void VoParams::Validate() const {
  auto require = [](bool ok, const char* what) {
    if (!ok) throw std::invalid_argument(std::string("visual odometry parameter ") + what);
  };
  require(max_features >= 20 && max_features <= 5000, "max_features must be 20..5000");
  require(min_distance_px >= 1 && min_distance_px <= 100, "min_distance_px must be 1..100");
  require(border_px >= 0 && border_px <= 200, "border_px must be 0..200");
  require(corner_quality > 0 && corner_quality < 1, "corner_quality must be in (0, 1)");
  require(feature_grid >= 1 && feature_grid <= 16, "feature_grid must be 1..16");
  require(lk_window_px >= 5 && lk_window_px <= 61 && lk_levels >= 0 && lk_levels <= 6, "LK window 5..61 px, levels 0..6");
  require(lk_fb_tol_px > 0 && epipolar_tol_px > 0, "tolerances must be positive");
  require(disparity_sigma_px > 0 && max_depth_error > 0 && max_depth_error < 1, "depth error model out of range");
  require(min_depth_m > 0, "min_depth_m must be positive");
  require(disparity_offset_prior_sigma_px >= 0 && disparity_offset_prior_sigma_px <= 5 && disparity_offset_min_sigma_px > 0 &&
              disparity_offset_min_sigma_px <= std::max(disparity_offset_prior_sigma_px, 0.01) &&
              disparity_offset_measurement_sigma_px > 0 && disparity_offset_measurement_sigma_px <= 5,
          "disparity_offset_prior_sigma_px must be 0..5, disparity_offset_min_sigma_px in (0, prior] and "
          "disparity_offset_measurement_sigma_px in (0, 5]");
  require(ransac_p > 0 && ransac_p < 1 && ransac_initial_outliers >= 0 && ransac_initial_outliers < 1,
          "RANSAC probabilities must be in (0, 1)");
  require(ransac_max_iterations >= 1 && ransac_max_iterations <= 100000, "ransac_max_iterations must be 1..100000");
  require(consensus > 0 && consensus <= 1, "consensus must be in (0, 1]");
  require(reprojection_tol_px > 0 && rigid_tol_sigma > 0, "inlier tolerances must be positive");
  require(min_inliers >= 6 && keyframe_min_inliers >= min_inliers, "min_inliers >= 6 and keyframe_min_inliers >= it");
  require(keyframe_min_fraction > 0 && keyframe_min_fraction < 1, "keyframe_min_fraction must be in (0, 1)");
  require(max_sync_skew_s >= 0 && max_gap_s > 0 && min_contrast_dn >= 0, "timing and contrast limits");
  require(imu_rotation_sigma_rad > 0 && imu_rotation_sigma_rad <= 1 && imu_rotation_gate_rad > 0 && imu_rotation_gate_rad <= M_PI &&
              track_sigma_px > 0 && track_sigma_px <= 10,
          "imu_rotation_sigma_rad must be in (0, 1], imu_rotation_gate_rad in (0, pi] and track_sigma_px in (0, 10]");
}

int RansacIterations(double p, double outliers, int s) {
  const double inlier_sample = std::pow(1.0 - std::clamp(outliers, 0.0, 1.0), s);
  if (inlier_sample >= 1.0) return 1;
  if (inlier_sample <= 0.0) return std::numeric_limits<int>::max();
  const double n = std::ceil(std::log(1.0 - p) / std::log(1.0 - inlier_sample));  // Eq. 5.20
  return n > 1e9 ? std::numeric_limits<int>::max() : std::max(1, static_cast<int>(n));
}

bool RigidMotion(const Eigen::Matrix3Xd& P, const Eigen::Matrix3Xd& Q, const Eigen::VectorXd& w,
                 Eigen::Isometry3d* T_QP) {
  const double wsum = w.sum();
  if (P.cols() < 3 || P.cols() != Q.cols() || w.size() != P.cols() || !(wsum > 0)) return false;
  // Eq. 5.2-5.4: weighted centroids and centred points; Eq. 5.5-5.6: S = X W Y^T = U Sigma V^T.
  const Eigen::Vector3d p_bar = P * w / wsum, q_bar = Q * w / wsum;
  const Eigen::Matrix3Xd X = P.colwise() - p_bar, Y = Q.colwise() - q_bar;
  const Eigen::Matrix3d S = X * w.asDiagonal() * Y.transpose();
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(S, Eigen::ComputeFullU | Eigen::ComputeFullV);
  // Three points on a line leave two singular values at zero: the rotation about it is free.
  if (!(svd.singularValues()(1) > 1e-9 * std::max(1.0, svd.singularValues()(0)))) return false;
  // Eq. 5.7: R = V diag(1, 1, det(V U^T)) U^T (a reflection is not a rotation); Eq. 5.8: t.
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1 : 1;
  T_QP->setIdentity();
  T_QP->linear() = svd.matrixV() * D * svd.matrixU().transpose();
  T_QP->translation() = q_bar - T_QP->linear() * p_bar;
  return true;
}

struct StereoVo::Impl {
  RectifiedGeometry g;
  VoParams p;
  cv::Mat K;
  double max_depth_m = 0;
  std::mt19937 rng{12345};

  enum PointState : char { kGone = 0, kTracked = 1, kPredicted = 2 };
  struct Keyframe {
    cv::Mat left;                      // the keyframe's own left image
    cv::Mat last_left;                 // the previous frame's left image, where tracking starts
    std::vector<cv::Point2f> px;       // left pixels of the points with depth
    std::vector<Eigen::Vector3d> p_K;  // their positions in the keyframe [m]
    std::vector<cv::Point2f> px_row;   // each point's column and row (averaged over both images) ...
    std::vector<float> disparity;      // ... and disparity as matched [px], before the offset
    double p_K_offset = 0;             // the disparity offset p_K was computed with
    // The offset the latest frame's motion from this keyframe asks for, and its variance [px^2];
    // counted once, when the keyframe is replaced (the frames of one keyframe share its
    // disparities, so their errors are not independent).
    std::optional<std::pair<double, double>> offset_measurement;
    std::vector<cv::Point2f> last_px;  // where each was last seen or predicted (the next LK's guess)
    std::vector<char> alive;           // kTracked, kPredicted or kGone
    Eigen::Isometry3d T_WK = Eigen::Isometry3d::Identity();
    Eigen::Isometry3d T_CK = Eigen::Isometry3d::Identity();  // the last frame's motion from it
  };
  std::optional<Keyframe> keyframe;
  Eigen::Isometry3d T_WC = Eigen::Isometry3d::Identity();
  std::optional<Eigen::Matrix3d> R_XW;  // W in the IMU's frame X, from the first pair that had one
  // The rig's disparity offset [px] (true disparity = matched + offset) and its information
  // [1/px^2]: a rectified pair whose principal points sit a tenth of a pixel apart (a
  // calibration's residual, as KITTI's has) makes every depth wrong by a share that grows with
  // the depth, and the motion's length with it. Estimated from the motion itself (see
  // OffsetFromFrame), so no calibration target is needed in the field.
  double disparity_offset = 0;
  double offset_information = 0;
  int segment = 0;
  int64_t last_utime = -1;

  double DepthSigma(double z) const { return z * z * p.disparity_sigma_px / (g.f_px * g.baseline_m); }

  cv::Mat Grey(const cv::Mat& m) const {
    if (m.channels() == 1) return m;
    cv::Mat g1;
    cv::cvtColor(m, g1, cv::COLOR_BGR2GRAY);
    return g1;
  }

  // Stereo correspondence (thesis 5.2): LK from left to right with a back check, kept on the
  // rectified row within the epipolar tolerance and in the working range, then triangulated
  // (Eq. 3.11, the linear triangulation of 4.3.3 for a rectified pair). `disparity_guess` (one per
  // point, or empty: none) starts the search where the point is expected: close to the ground
  // disparities outgrow what the pyramid finds from zero.
  std::vector<std::optional<Eigen::Vector3d>> Triangulate(const cv::Mat& left, const cv::Mat& right,
                                                          const std::vector<cv::Point2f>& px_l, int* row_misses,
                                                          std::vector<float>* u_r = nullptr,
                                                          const std::vector<float>& disparity_guess = {}) const {
    std::vector<std::optional<Eigen::Vector3d>> out(px_l.size());
    if (u_r) u_r->assign(px_l.size(), 0.0f);
    if (px_l.empty()) return out;
    std::vector<cv::Point2f> px_r = px_l, back;
    for (size_t i = 0; i < disparity_guess.size(); ++i) px_r[i].x -= disparity_guess[i];
    std::vector<uchar> st1, st2;
    std::vector<float> err;
    const cv::Size win(p.lk_window_px, p.lk_window_px);
    // One more pyramid level than frame-to-frame: disparities reach a fifth of the width.
    // Iterated to a thousandth of a pixel: at the edge of the working range a tenth of a pixel of
    // disparity is 1 % of the depth.
    const cv::TermCriteria term(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 0.001);
    cv::calcOpticalFlowPyrLK(left, right, px_l, px_r, st1, err, win, p.lk_levels + 1, term,
                             disparity_guess.empty() ? 0 : cv::OPTFLOW_USE_INITIAL_FLOW);
    back = px_l;
    cv::calcOpticalFlowPyrLK(right, left, px_r, back, st2, err, win, p.lk_levels + 1, term, cv::OPTFLOW_USE_INITIAL_FLOW);
    for (size_t i = 0; i < px_l.size(); ++i) {
      if (!st1[i] || !st2[i] || cv::norm(back[i] - px_l[i]) > p.lk_fb_tol_px) continue;
      if (std::abs(px_r[i].y - px_l[i].y) > p.epipolar_tol_px) {
        ++*row_misses;
        continue;
      }
      const double d = px_l[i].x - px_r[i].x + disparity_offset;
      if (!(d > 0)) continue;
      const double z = g.f_px * g.baseline_m / d;
      if (z < p.min_depth_m || z > max_depth_m) continue;
      out[i] = Triangulated(g, px_l[i].x, 0.5 * (px_l[i].y + px_r[i].y), px_l[i].x - px_r[i].x, disparity_offset);
      if (u_r) (*u_r)[i] = px_r[i].x;
    }
    return out;
  }

  // Shi-Tomasi corners (thesis 5.2) in a grid of cells, each with its own quality threshold: one
  // strong corner (a roof edge, a person) otherwise sets a threshold that the ground's texture
  // everywhere else falls under, and a keyframe at 15 m kept 30 of 400 points. The border is
  // masked and the points stay min_distance_px apart across the cells too.
  std::vector<cv::Point2f> DetectCorners(const cv::Mat& left) const {
    const int b = p.border_px, n = p.feature_grid;
    const cv::Rect inner(b, b, left.cols - 2 * b, left.rows - 2 * b);
    std::vector<cv::Point2f> out;
    if (inner.width < 2 * n || inner.height < 2 * n) return out;
    const int per_cell = std::max(1, p.max_features / (n * n));
    cv::Mat taken = cv::Mat::zeros(left.size(), CV_8U);
    for (int cy = 0; cy < n; ++cy)
      for (int cx = 0; cx < n; ++cx) {
        const cv::Rect cell(inner.x + cx * inner.width / n, inner.y + cy * inner.height / n,
                            (cx + 1) * inner.width / n - cx * inner.width / n, (cy + 1) * inner.height / n - cy * inner.height / n);
        std::vector<cv::Point2f> corners;
        cv::goodFeaturesToTrack(left(cell), corners, per_cell, p.corner_quality, p.min_distance_px);
        for (cv::Point2f c : corners) {
          c += cv::Point2f(static_cast<float>(cell.x), static_cast<float>(cell.y));
          const cv::Point ci(cvRound(c.x), cvRound(c.y));
          if (taken.at<uchar>(ci)) continue;  // too close to a point of the next cell
          cv::circle(taken, ci, static_cast<int>(p.min_distance_px), 255, cv::FILLED);
          out.push_back(c);
        }
      }
    return out;
  }

  // Detects and triangulates a new keyframe; the reason when it has too few points.
  std::string MakeKeyframe(const cv::Mat& left, const cv::Mat& right, const Eigen::Isometry3d& T_WK) {
    const std::vector<cv::Point2f> corners = DetectCorners(left);
    int row_misses = 0;
    std::vector<float> u_r;
    const auto points = Triangulate(left, right, corners, &row_misses, &u_r);
    Keyframe k;
    k.left = left.clone();
    k.last_left = k.left;
    k.T_WK = T_WK;
    for (size_t i = 0; i < corners.size(); ++i) {
      if (!points[i]) continue;
      k.px.push_back(corners[i]), k.p_K.push_back(*points[i]);
      k.px_row.emplace_back(corners[i].x, static_cast<float>(points[i]->y() * g.f_px / points[i]->z() + g.cy));
      k.disparity.push_back(corners[i].x - u_r[i]);
    }
    k.p_K_offset = disparity_offset;
    k.last_px = k.px;
    k.alive.assign(k.px.size(), kTracked);
    if (static_cast<int>(k.px.size()) < p.min_inliers) {
      if (row_misses > static_cast<int>(corners.size()) / 2)
        return Format("%.0f of %.0f stereo matches leave the epipolar line: a mismatched pair or a calibration that does "
                      "not fit", row_misses, static_cast<double>(corners.size()));
      return Format("only %.0f of %.0f features have a depth in the working range (%.1f m)", static_cast<double>(k.px.size()),
                    static_cast<double>(corners.size()), max_depth_m);
    }
    keyframe = std::move(k);
    return "";
  }

  Eigen::Vector2d Project(const Eigen::Isometry3d& T_CK, const Eigen::Vector3d& p_K) const {
    const Eigen::Vector3d c = T_CK * p_K;
    return {g.f_px * c.x() / c.z() + g.cx, g.f_px * c.y() / c.z() + g.cy};
  }
  bool PnpInlier(const Eigen::Isometry3d& T_CK, const Match& m) const {
    const Eigen::Vector3d c = T_CK * m.p_K;
    if (!(c.z() > 0)) return false;
    return (Project(T_CK, m.p_K) - Eigen::Vector2d(m.px_C.x, m.px_C.y)).norm() < p.reprojection_tol_px;
  }
  double RigidSigma(const Match& m) const {
    return std::hypot(DepthSigma(m.p_K.z()), DepthSigma(m.p_C->z())) + 0.005;
  }
  bool RigidInlier(const Eigen::Isometry3d& T_CK, const Match& m) const {
    return (T_CK * m.p_K - *m.p_C).norm() < p.rigid_tol_sigma * RigidSigma(m);
  }
  bool Inlier(const Eigen::Isometry3d& T_CK, const Match& m) const {
    return p.method == VoMethod::kRigid ? RigidInlier(T_CK, m) : PnpInlier(T_CK, m);
  }

  static Eigen::Isometry3d FromRvecTvec(const cv::Mat& rvec, const cv::Mat& tvec) {
    cv::Mat R;
    cv::Rodrigues(rvec, R);
    Eigen::Matrix3d Re;
    cv::cv2eigen(R, Re);
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Re;
    T.translation() = Eigen::Vector3d(tvec.at<double>(0), tvec.at<double>(1), tvec.at<double>(2));
    return T;
  }
  static void ToRvecTvec(const Eigen::Isometry3d& T, cv::Mat* rvec, cv::Mat* tvec) {
    cv::Mat R;
    cv::eigen2cv(Eigen::Matrix3d(T.linear()), R);
    cv::Rodrigues(R, *rvec);
    *tvec = (cv::Mat_<double>(3, 1) << T.translation().x(), T.translation().y(), T.translation().z());
  }

  // The keyframe points and their pixels now, as OpenCV's PnP takes them.
  static void PnpInputs(const std::vector<Match>& m, const std::vector<int>& idx, std::vector<cv::Point3d>* obj,
                        std::vector<cv::Point2d>* img) {
    for (int i : idx) obj->emplace_back(m[i].p_K.x(), m[i].p_K.y(), m[i].p_K.z()), img->emplace_back(m[i].px_C.x, m[i].px_C.y);
  }

  // The minimal solvers inside RANSAC: 3 points for the rigid method, 4 for P3P (the fourth
  // picks among its solutions) and for EPnP.
  int SampleSize() const { return p.method == VoMethod::kRigid ? 3 : 4; }
  bool SolveSample(const std::vector<Match>& m, const std::vector<int>& idx, Eigen::Isometry3d* T_CK) const {
    if (p.method == VoMethod::kRigid) {
      Eigen::Matrix3Xd P(3, idx.size()), Q(3, idx.size());
      for (size_t i = 0; i < idx.size(); ++i) P.col(i) = m[idx[i]].p_K, Q.col(i) = *m[idx[i]].p_C;
      return RigidMotion(P, Q, Eigen::VectorXd::Ones(idx.size()), T_CK);
    }
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    PnpInputs(m, idx, &obj, &img);
    cv::Mat rvec, tvec;
    bool ok = false;
    try {
      ok = cv::solvePnP(obj, img, K, cv::noArray(), rvec, tvec, false,
                        p.method == VoMethod::kPnp ? cv::SOLVEPNP_AP3P : cv::SOLVEPNP_EPNP);
    } catch (const cv::Exception&) {
      return false;  // a degenerate sample
    }
    if (!ok || !cv::checkRange(rvec) || !cv::checkRange(tvec)) return false;
    *T_CK = FromRvecTvec(rvec, tvec);
    return true;
  }

  // Re-estimates on the consensus set (RANSAC step 4/6) and refines it by LM (Eq. 5.21).
  Eigen::Isometry3d Refine(const std::vector<Match>& m, const std::vector<int>& in, const Eigen::Isometry3d& T0,
                           const std::optional<RotationPrior>& imu) const {
    // The rigid residuals are in sigmas already; the reprojections in pixels of track_sigma_px.
    const auto prior = [&](double unit) {
      return imu ? std::optional<RotationPrior>(RotationPrior{imu->R_CK, unit * imu->weight}) : std::nullopt;
    };
    if (p.method == VoMethod::kRigid) {
      std::vector<Eigen::Vector3d> P, Q;
      std::vector<double> inv_sigma;
      Eigen::Matrix3Xd Pm(3, in.size()), Qm(3, in.size());
      Eigen::VectorXd w(in.size());
      for (size_t i = 0; i < in.size(); ++i) {
        const Match& x = m[in[i]];
        P.push_back(x.p_K), Q.push_back(*x.p_C);
        const double s = RigidSigma(x);
        inv_sigma.push_back(1.0 / s);
        Pm.col(i) = x.p_K, Qm.col(i) = *x.p_C, w(i) = 1.0 / (s * s);  // Eq. 5.1's weights
      }
      Eigen::Isometry3d T = T0;
      if (!RigidMotion(Pm, Qm, w, &T)) T = T0;
      return RefineLm(cv::makePtr<RigidResiduals>(P, Q, inv_sigma, prior(1.0)), T);
    }
    std::vector<cv::Point3d> obj;
    std::vector<cv::Point2d> img;
    PnpInputs(m, in, &obj, &img);
    cv::Mat rvec, tvec;
    ToRvecTvec(T0, &rvec, &tvec);
    try {
      if (p.method == VoMethod::kEpnp) {
        cv::Mat r2, t2;
        if (cv::solvePnP(obj, img, K, cv::noArray(), r2, t2, false, cv::SOLVEPNP_EPNP) && cv::checkRange(r2) &&
            cv::checkRange(t2))
          rvec = r2, tvec = t2;
      }
      cv::solvePnPRefineLM(obj, img, K, cv::noArray(), rvec, tvec);  // Eq. 5.21 in the left image
    } catch (const cv::Exception&) {
      return T0;
    }
    if (!cv::checkRange(rvec) || !cv::checkRange(tvec)) return T0;
    // Then Eq. 5.21 in both images of the current pair.
    return RefineLm(cv::makePtr<StereoReprojection>(m, in, g.f_px, g.cx, g.cy, g.baseline_m, disparity_offset,
                                                    prior(p.track_sigma_px)),
                    FromRvecTvec(rvec, tvec));
  }

  // RANSAC (thesis 5.4) then refinement; the consensus indices in `inliers`.
  std::optional<Eigen::Isometry3d> Estimate(const std::vector<Match>& m, const std::optional<RotationPrior>& imu,
                                            std::vector<int>* inliers, int* iterations) {
    const int n = static_cast<int>(m.size()), s = SampleSize();
    if (n < std::max(s, p.min_inliers)) return std::nullopt;
    int needed = std::min(p.ransac_max_iterations, RansacIterations(p.ransac_p, p.ransac_initial_outliers, s));
    std::vector<int> best, idx(s), cur;
    Eigen::Isometry3d best_T = Eigen::Isometry3d::Identity();
    std::uniform_int_distribution<int> pick(0, n - 1);
    int it = 0;
    for (; it < needed; ++it) {
      for (int j = 0; j < s; ++j) {
        int k;
        do k = pick(rng); while (std::find(idx.begin(), idx.begin() + j, k) != idx.begin() + j);
        idx[j] = k;
      }
      Eigen::Isometry3d T;
      if (!SolveSample(m, idx, &T)) continue;
      // With the IMU's rotation, a sample whose rotation is far from it is not a hypothesis
      // (a few points near one depth can fit a motion that tilts the camera by tens of degrees).
      if (imu && FromPrior(T.linear(), *imu).norm() > p.imu_rotation_gate_rad) continue;
      cur.clear();
      for (int i = 0; i < n; ++i)
        if (Inlier(T, m[i])) cur.push_back(i);
      if (cur.size() > best.size()) {
        best.swap(cur), best_T = T;
        // Eq. 5.20 with the outlier share this consensus implies.
        needed = std::min(p.ransac_max_iterations, RansacIterations(p.ransac_p, 1.0 - double(best.size()) / n, s));
      }
      if (best.size() >= p.consensus * n) {  // step 4: a large enough consensus ends the search
        ++it;
        break;
      }
    }
    *iterations = it;
    if (static_cast<int>(best.size()) < p.min_inliers) return std::nullopt;
    Eigen::Isometry3d T = Refine(m, best, best_T, imu);
    // The refined motion decides the final consensus; one more refinement on it.
    for (int pass = 0; pass < 2; ++pass) {
      inliers->clear();
      for (int i = 0; i < n; ++i)
        if (Inlier(T, m[i])) inliers->push_back(i);
      if (static_cast<int>(inliers->size()) < p.min_inliers) return std::nullopt;
      if (pass == 0) T = Refine(m, *inliers, T, imu);
    }
    return T;
  }

  // The disparity offset that the motion from the keyframe asks for (thesis 5.5's stereo
  // reprojections with the offset as a seventh unknown beside the pose): one Gauss-Newton step
  // from the refined pose, and the offset's variance from the step's normal equations, scaled by
  // the residuals' spread. A constant offset changes near and far depths by different shares,
  // which no motion can mimic, so it is observable wherever the points span a range of depths
  // and the camera has moved; at a hover or over flat ground at one depth the variance is large
  // and the estimate does not move.
  std::optional<std::pair<double, double>> OffsetFromFrame(const std::vector<Match>& m, const std::vector<int>& in,
                                                           const Eigen::Isometry3d& T_CK,
                                                           const std::optional<RotationPrior>& imu) const {
    const auto residuals = [&](const Eigen::Matrix<double, 7, 1>& x) {
      cv::Mat pose(6, 1, CV_64F);
      for (int j = 0; j < 6; ++j) pose.at<double>(j) = x(j);
      const Eigen::Isometry3d T = PoseOf(pose);
      std::vector<double> e;
      e.reserve(3 * in.size() + 3);
      // The keyframe's points re-triangulated with the offset being solved for.
      for (int i : in)
        AppendStereoErrors(T * Triangulated(g, m[i].px_K.x, m[i].px_K.y, m[i].disparity_K, x(6)), m[i], g.f_px, g.cx, g.cy,
                           g.baseline_m, x(6), e);
      if (imu) {
        const Eigen::Vector3d r = p.track_sigma_px * imu->weight * FromPrior(T.linear(), *imu);
        e.insert(e.end(), {r.x(), r.y(), r.z()});
      }
      return Eigen::Map<const Eigen::VectorXd>(e.data(), static_cast<Eigen::Index>(e.size())).eval();
    };
    // An offset is told from the motion's length only by how differently it changes near and far
    // depths: points whose disparities span less than a factor of kOffsetDepthSpan (10th to 90th
    // percentile) do not measure it, whatever the normal equations say (a downward camera over
    // plain ground would otherwise pass its tilt and scale errors off as an offset).
    std::vector<double> d;
    for (int i : in) d.push_back(m[i].disparity_K + disparity_offset);
    if (d.size() < 20) return std::nullopt;
    std::sort(d.begin(), d.end());
    if (!(d[d.size() * 9 / 10] >= kOffsetDepthSpan * d[d.size() / 10])) return std::nullopt;
    Eigen::Matrix<double, 7, 1> x;
    const cv::Mat pose = ParamsOf(T_CK);
    for (int j = 0; j < 6; ++j) x(j) = pose.at<double>(j);
    x(6) = disparity_offset;
    const Eigen::VectorXd r0 = residuals(x);
    const Eigen::Index n = r0.size();
    if (n < 20) return std::nullopt;
    Eigen::MatrixXd J(n, 7);
    for (int j = 0; j < 7; ++j) {
      Eigen::Matrix<double, 7, 1> xh = x;
      const double h = j < 3 ? 1e-7 : j < 6 ? 1e-6 : 1e-4;
      xh(j) += h;
      J.col(j) = (residuals(xh) - r0) / h;
    }
    const Eigen::Matrix<double, 7, 7> H = J.transpose() * J;
    const Eigen::LDLT<Eigen::Matrix<double, 7, 7>> ldlt(H);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) return std::nullopt;
    const Eigen::Matrix<double, 7, 1> step = ldlt.solve(-J.transpose() * r0);
    const Eigen::Matrix<double, 7, 1> e6 = Eigen::Matrix<double, 7, 1>::Unit(6);
    const double sigma2 = r0.squaredNorm() / std::max<double>(1.0, static_cast<double>(n) - 7);
    const double variance = sigma2 * ldlt.solve(e6)(6);
    if (!std::isfinite(step(6)) || !(variance > 0) || !std::isfinite(variance)) return std::nullopt;
    return std::pair{disparity_offset + step(6), variance};
  }

  // Folds one keyframe's measurement of the offset into the estimate (inverse-variance
  // weighting); a measurement more than 3 sigma from the estimate is a bad motion, not the rig.
  // The information is capped at disparity_offset_min_sigma_px, so the estimate keeps following a
  // rig whose calibration shifts (heat, a knock).
  void FuseOffset(const std::optional<std::pair<double, double>>& measured) {
    if (!measured || !(offset_information > 0)) return;
    const auto [value, variance] = *measured;
    // A measurement that leaves the offset loose (a downward camera over plain ground, where a
    // depth offset and the motion's length trade almost freely) is where the pose's own errors
    // would pass for an offset: it is not counted.
    if (variance > p.disparity_offset_measurement_sigma_px * p.disparity_offset_measurement_sigma_px) return;
    if (std::abs(value - disparity_offset) > 3 * std::sqrt(variance + 1 / offset_information)) return;
    const double info = 1 / variance;
    disparity_offset = (offset_information * disparity_offset + info * value) / (offset_information + info);
    offset_information = std::min(offset_information + info, 1 / (p.disparity_offset_min_sigma_px * p.disparity_offset_min_sigma_px));
  }

  VoResult Unhealthy(std::string reason) const {
    VoResult r;
    r.healthy = false;
    r.reason = std::move(reason);
    r.T_WC = T_WC;
    r.segment = segment;
    return r;
  }

  std::string CheckPair(const RectifiedPair& pair, cv::Mat* left, cv::Mat* right) const {
    for (const auto& [img, side] : {std::pair{&pair.left, "left"}, std::pair{&pair.right, "right"}}) {
      if (img->empty()) return std::string(side) + " image is empty";
      if (img->depth() != CV_8U || (img->channels() != 1 && img->channels() != 3))
        return std::string(side) + " image must be 8-bit grey or BGR";
      if (img->cols != g.width || img->rows != g.height)
        return std::string(side) + Format(" image is %.0fx%.0f but the calibration is for %.0fx", img->cols, img->rows, g.width) +
               std::to_string(g.height);
    }
    const double skew = std::abs(pair.right_utime - pair.left_utime) * 1e-6;
    if (skew > p.max_sync_skew_s)
      return Format("unsynchronised pair: the right image was exposed %.1f ms from the left (limit %.1f ms)", skew * 1e3,
                    p.max_sync_skew_s * 1e3);
    if (pair.R_XC && !(pair.R_XC->allFinite() && (*pair.R_XC * pair.R_XC->transpose() - Eigen::Matrix3d::Identity()).norm() < 1e-3 &&
                       pair.R_XC->determinant() > 0))
      return "the IMU attitude given with the pair is not a rotation";
    const Eigen::Matrix3d& c = pair.R_XC_covariance;
    if (pair.R_XC && !(c.allFinite() && (c - c.transpose()).norm() <= 1e-9 * (1 + c.norm()) &&
                       Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(c).eigenvalues().minCoeff() >= -1e-12))
      return "the IMU attitude covariance given with the pair is not a covariance (finite, symmetric, not negative)";
    *left = Grey(pair.left);
    *right = Grey(pair.right);
    for (const auto& [img, side] : {std::pair{left, "left"}, std::pair{right, "right"}}) {
      cv::Scalar mean, sd;
      cv::meanStdDev(*img, mean, sd);
      if (sd[0] < p.min_contrast_dn)
        return std::string(side) + Format(" image is blank or dark (mean %.1f DN, spread %.2f DN)", mean[0], sd[0]);
    }
    return "";
  }

  VoResult Process(const RectifiedPair& pair) {
    cv::Mat left, right;
    if (std::string bad = CheckPair(pair, &left, &right); !bad.empty()) return Unhealthy(bad);
    const int64_t utime = pair.left_utime;
    if (last_utime >= 0 && utime <= last_utime) return Unhealthy("frame time does not increase: " + std::to_string(utime));
    const bool gap = last_utime >= 0 && (utime - last_utime) * 1e-6 > p.max_gap_s;
    const double gap_s = (utime - last_utime) * 1e-6;
    last_utime = utime;
    if (pair.R_XC && !R_XW) R_XW = *pair.R_XC * T_WC.linear().transpose();
    if (gap && keyframe) {
      keyframe.reset();
      ++segment;
      if (std::string why = MakeKeyframe(left, right, T_WC); !why.empty()) return Unhealthy(why);
      VoResult r = Unhealthy(Format("a gap of %.2f s between frames: the track restarts here", gap_s));
      r.segment = segment;
      return r;
    }
    if (!keyframe) {
      // A new segment begins at this frame, from the last pose known (the motion since is lost).
      if (std::string why = MakeKeyframe(left, right, T_WC); !why.empty()) return Unhealthy(why);
      VoResult r;
      r.healthy = true;
      r.T_WC = T_WC;
      r.segment = segment;
      r.new_keyframe = true;
      r.keyframe_points = r.tracked = r.inliers = static_cast<int>(keyframe->px.size());
      return r;
    }
    Keyframe& k = *keyframe;
    if (k.p_K_offset != disparity_offset) {  // the offset has been learnt further: the points move
      for (size_t i = 0; i < k.p_K.size(); ++i)
        k.p_K[i] = Triangulated(g, k.px_row[i].x, k.px_row[i].y, k.disparity[i], disparity_offset);
      k.p_K_offset = disparity_offset;
    }
    // Frame to frame (thesis 5.2: "KLT is further applied to each subsequent left image frame"):
    // each keyframe point from where it was in the previous frame, with a backward check. From
    // frame to frame the view changes little (exposure, cloud shadows, perspective), which a
    // keyframe-to-frame LK would have to bridge at once; the pose is still computed against the
    // keyframe's 3-D points, so a hovering camera does not integrate anything.
    std::vector<int> ids, lost_ids;
    std::vector<cv::Point2f> from, lost_from, lost_to;
    for (size_t i = 0; i < k.px.size(); ++i) {
      if (k.alive[i] == kTracked) ids.push_back(static_cast<int>(i)), from.push_back(k.last_px[i]);
      if (k.alive[i] == kPredicted)
        lost_ids.push_back(static_cast<int>(i)), lost_from.push_back(k.px[i]), lost_to.push_back(k.last_px[i]);
    }
    std::vector<cv::Point2f> to = from, back = from;
    std::vector<uchar> st1, st2;
    std::vector<float> err;
    const cv::Size win(p.lk_window_px, p.lk_window_px);
    const auto term = cv::TermCriteria(cv::TermCriteria::COUNT + cv::TermCriteria::EPS, 50, 0.001);
    if (!from.empty()) {
      cv::calcOpticalFlowPyrLK(k.last_left, left, from, to, st1, err, win, p.lk_levels, term);
      cv::calcOpticalFlowPyrLK(left, k.last_left, to, back, st2, err, win, p.lk_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
    }
    // Frame-to-frame positions accumulate LK's small errors as a random walk, which a hovering
    // camera would read as drift. Each track is therefore pulled back onto the keyframe's own
    // patch (one LK pass at full resolution from where frame-to-frame put it); where the view has
    // changed too much for that (it moves the point further than the forward-backward tolerance)
    // the frame-to-frame position stands.
    std::vector<cv::Point2f> anchored = to, anchor_from;
    std::vector<uchar> st3;
    for (int id : ids) anchor_from.push_back(k.px[id]);
    if (!from.empty())
      cv::calcOpticalFlowPyrLK(k.left, left, anchor_from, anchored, st3, err, win, 0, term, cv::OPTFLOW_USE_INITIAL_FLOW);
    std::vector<Match> matches;
    std::vector<cv::Point2f> tracked_px;
    for (size_t j = 0; j < ids.size(); ++j) {
      if (!st1[j] || !st2[j] || cv::norm(back[j] - from[j]) > p.lk_fb_tol_px) continue;
      if (st3[j] && cv::norm(anchored[j] - to[j]) < p.lk_fb_tol_px) to[j] = anchored[j];
      if (!Inside(to[j], left.size())) continue;
      matches.push_back({ids[j], k.p_K[ids[j]], k.px_row[ids[j]], k.disparity[ids[j]], to[j], std::nullopt, std::nullopt});
      tracked_px.push_back(to[j]);
    }
    // Points lost earlier are looked for again straight from the keyframe's image, starting where
    // the last motion put them, with the same back check: a cloud shadow or one failed check
    // does not wear the keyframe down (a hovering camera keeps its keyframe).
    if (!lost_ids.empty()) {
      std::vector<cv::Point2f> lost_back = lost_from;
      cv::calcOpticalFlowPyrLK(k.left, left, lost_from, lost_to, st1, err, win, p.lk_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
      cv::calcOpticalFlowPyrLK(left, k.left, lost_to, lost_back, st2, err, win, p.lk_levels, term, cv::OPTFLOW_USE_INITIAL_FLOW);
      for (size_t j = 0; j < lost_ids.size(); ++j) {
        const cv::Point2f& q = lost_to[j];
        if (!st1[j] || !st2[j] || cv::norm(lost_back[j] - lost_from[j]) > p.lk_fb_tol_px) continue;
        if (!Inside(q, left.size())) continue;
        matches.push_back({lost_ids[j], k.p_K[lost_ids[j]], k.px_row[lost_ids[j]], k.disparity[lost_ids[j]], q, std::nullopt,
                           std::nullopt});
        tracked_px.push_back(q);
      }
    }
    const int tracked = static_cast<int>(matches.size());
    {
      // The tracked points in this pair too: the 3D-3D method needs them in 3-D, PnP's
      // refinement in the right image.
      // Each point's disparity as the last motion predicts it; the points it puts inside the
      // working range are the ones expected in the right image.
      std::vector<float> disparity_guess;
      int expected = 0;
      for (const Match& m : matches) {
        const double z = (k.T_CK * m.p_K).z();
        const bool in_range = z >= p.min_depth_m && z <= max_depth_m;
        expected += in_range;
        disparity_guess.push_back(in_range ? static_cast<float>(g.f_px * g.baseline_m / z) : 0.0f);
      }
      int row_misses = 0;
      std::vector<float> u_r;
      const auto now = Triangulate(left, right, tracked_px, &row_misses, &u_r, disparity_guess);
      // The keyframe's points had a stereo match when it was made, and most keep one while they
      // stay in view and in range: a right image that does not belong to the left (or a
      // calibration that does not fit) loses most of them. The pair is refused; the track goes on
      // with the next one.
      const auto found = std::count_if(now.begin(), now.end(), [](const auto& q) { return q.has_value(); });
      if (expected >= p.min_inliers && found < expected / 2)
        return Unhealthy(Format("only %.0f of %.0f tracked points expected in range are found in the right image on "
                                "their rows (%.0f off the epipolar line): a mismatched pair or a calibration that does not fit",
                                static_cast<double>(found), static_cast<double>(expected), static_cast<double>(row_misses)));
      std::vector<Match> kept;
      for (size_t j = 0; j < matches.size(); ++j) {
        if (now[j]) matches[j].p_C = now[j], matches[j].u_R = u_r[j];
        if (now[j] || p.method != VoMethod::kRigid) kept.push_back(matches[j]);
      }
      matches.swap(kept);
    }
    std::vector<int> inliers;
    int iterations = 0;
    // The IMU's attitude as a prior on this frame's rotation from the keyframe: R_CK = R_WC^T R_WK
    // with R_WC from the IMU and R_WK as the chain has it. Tied to W, not to the keyframe, so
    // that the small rotation errors of successive keyframes (plenty while climbing, when the
    // view changes scale) do not add up.
    std::optional<RotationPrior> imu;
    if (pair.R_XC && R_XW) {
      const Eigen::Matrix3d cov =
          pair.R_XC_covariance + Eigen::Matrix3d::Identity() * p.imu_rotation_sigma_rad * p.imu_rotation_sigma_rad;
      const Eigen::LLT<Eigen::Matrix3d> llt(cov);
      imu = RotationPrior{(R_XW->transpose() * *pair.R_XC).transpose() * k.T_WK.linear(),
                          llt.matrixL().solve(Eigen::Matrix3d::Identity())};
    }
    const auto T_CK = Estimate(matches, imu, &inliers, &iterations);
    if (!T_CK) {
      // Lost: the next frame starts a new segment from its own keyframe.
      VoResult r = Unhealthy(Format("RANSAC found no motion that %.0f of %.0f tracked points agree on", p.min_inliers,
                                    static_cast<double>(matches.size())) +
                             Format(" (%.0f of the keyframe's %.0f points tracked)", tracked, static_cast<double>(k.px.size())));
      r.tracked = tracked;
      r.keyframe_points = static_cast<int>(k.px.size());
      r.ransac_iterations = iterations;
      keyframe.reset();
      ++segment;
      return r;
    }
    if (p.method != VoMethod::kRigid && offset_information > 0)
      if (auto o = OffsetFromFrame(matches, inliers, *T_CK, imu)) k.offset_measurement = o;
    // The pose chain (Eq. 5.22-5.28): T_WC = T_WK T_KC, with T_KC = C^-1 of this frame's motion.
    const Eigen::Isometry3d T_KC = T_CK->inverse();
    T_WC = k.T_WK * T_KC;
    double sq = 0;
    for (int i : inliers) {
      const Match& m = matches[i];
      sq += (Project(*T_CK, m.p_K) - Eigen::Vector2d(m.px_C.x, m.px_C.y)).squaredNorm();
    }
    // The consensus is followed into the next frame from where it was seen; every other keyframe
    // point still in view is looked for again from where this motion puts it.
    k.last_left = left;
    k.T_CK = *T_CK;
    for (size_t i = 0; i < k.px.size(); ++i) {
      const Eigen::Vector2d q = Project(*T_CK, k.p_K[i]);
      k.last_px[i] = cv::Point2f(static_cast<float>(q.x()), static_cast<float>(q.y()));
      const bool in_view = q.x() >= p.border_px && q.y() >= p.border_px && q.x() < left.cols - p.border_px &&
                           q.y() < left.rows - p.border_px;
      k.alive[i] = in_view ? kPredicted : kGone;
    }
    for (int i : inliers)
      k.alive[matches[i].keyframe_index] = kTracked, k.last_px[matches[i].keyframe_index] = matches[i].px_C;

    VoResult r;
    r.healthy = true;
    r.T_WC = T_WC;
    r.T_KC = T_KC;
    r.segment = segment;
    r.keyframe_points = static_cast<int>(k.px.size());
    r.tracked = tracked;
    r.inliers = static_cast<int>(inliers.size());
    r.ransac_iterations = iterations;
    r.rms_px = std::sqrt(sq / std::max<size_t>(1, inliers.size()));
    // A keyframe that never had keyframe_min_inliers points (plain ground) is kept until it
    // loses keyframe_min_fraction of them: replacing it every frame would chain every frame's
    // error, which is drift.
    const bool thinning = r.keyframe_points > p.keyframe_min_inliers && r.inliers < p.keyframe_min_inliers;
    if (thinning || r.inliers < p.keyframe_min_fraction * r.keyframe_points) {
      // A new keyframe here; if this frame cannot make one, the old keyframe is kept.
      FuseOffset(k.offset_measurement);
      Keyframe old = std::move(k);
      if (MakeKeyframe(left, right, T_WC).empty()) r.new_keyframe = true;
      else keyframe = std::move(old);
    }
    return r;
  }
};

StereoVo::StereoVo(const RectifiedGeometry& geometry, const VoParams& params) : impl_(std::make_unique<Impl>()) {
  params.Validate();
  if (!(geometry.f_px > 0) || !(geometry.baseline_m > 0) || geometry.width < 16 || geometry.height < 16)
    throw std::invalid_argument("visual odometry: the rectified geometry needs a positive focal length, baseline and size");
  impl_->g = geometry;
  impl_->p = params;
  impl_->K = (cv::Mat_<double>(3, 3) << geometry.f_px, 0, geometry.cx, 0, geometry.f_px, geometry.cy, 0, 0, 1);
  impl_->max_depth_m = params.max_depth_error * geometry.f_px * geometry.baseline_m / params.disparity_sigma_px;
  if (params.disparity_offset_prior_sigma_px > 0)
    impl_->offset_information = 1 / (params.disparity_offset_prior_sigma_px * params.disparity_offset_prior_sigma_px);
}
StereoVo::~StereoVo() = default;
StereoVo::StereoVo(StereoVo&&) noexcept = default;
VoResult StereoVo::Process(const RectifiedPair& pair) {
  VoResult r = impl_->Process(pair);
  r.disparity_offset_px = impl_->disparity_offset;
  r.disparity_offset_sigma_px = impl_->offset_information > 0 ? 1 / std::sqrt(impl_->offset_information) : 0.0;
  return r;
}
const RectifiedGeometry& StereoVo::geometry() const { return impl_->g; }
const VoParams& StereoVo::params() const { return impl_->p; }

}  // namespace uav::vision
