#include "uav/vision/active_stereo.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include <Eigen/SVD>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

namespace uav::vision {
namespace {

[[noreturn]] void Bad(const std::string& what) { throw std::invalid_argument("active stereo: " + what); }

std::string Format(const char* fmt, double a, double b = 0.0, double c = 0.0) {
  char buf[200];
  std::snprintf(buf, sizeof buf, fmt, a, b, c);
  return buf;
}

// Median of an 8-bit image from its histogram.
int Median(const cv::Mat& gray) {
  int hist[256] = {0};
  for (int r = 0; r < gray.rows; ++r) {
    const uint8_t* row = gray.ptr<uint8_t>(r);
    for (int c = 0; c < gray.cols; ++c) ++hist[row[c]];
  }
  const int half = static_cast<int>(gray.total() / 2);
  int seen = 0;
  for (int v = 0; v < 256; ++v)
    if ((seen += hist[v]) > half) return v;
  return 255;
}

}  // namespace

// The height: the median depth below the body origin of the points on the ground clusters (a
// stray wrong match does not pull it), its standard error from their median absolute deviation.
static void MeasureGround(ActiveStereoResult* r) {
  std::vector<double> down;
  for (const LaserPoint& pt : r->points)
    if (pt.cluster >= 0 && r->clusters[pt.cluster].ground) down.push_back(pt.down_m);
  if (down.empty()) {
    r->healthy = false;
    return;
  }
  std::nth_element(down.begin(), down.begin() + down.size() / 2, down.end());
  r->height_m = down[down.size() / 2];
  for (double& d : down) d = std::abs(d - r->height_m);
  std::nth_element(down.begin(), down.begin() + down.size() / 2, down.end());
  r->height_sigma_m = 1.4826 * down[down.size() / 2] / std::sqrt(static_cast<double>(down.size()));
  r->healthy = true;
}

GroundTracker::GroundTracker(double max_step_m, double relock_s) : max_step_m_(max_step_m), relock_s_(relock_s) {
  if (!(max_step_m > 0) || !(relock_s >= 0)) throw std::invalid_argument("ground tracker: max_step_m must be positive, relock_s not negative");
}

void GroundTracker::Apply(ActiveStereoResult* r, double z_N, int64_t utime) {
  if (!r->healthy || !std::isfinite(z_N)) return;
  const double level = z_N + r->height_m;  // the ground cluster's down position in N
  if (!floor_N_ || std::abs(level - *floor_N_) <= max_step_m_) {
    floor_N_ = level;
    candidate_N_.reset();
    return;
  }
  // The farthest cluster is not the floor seen so far: one nearer may still be it (a few
  // dots beside a table), else the floor is hidden under a surface (a table wider than the dot
  // pattern, a ledge) and there is no height this pair, not a spike.
  bool found = false;
  for (DotCluster& c : r->clusters) {
    c.ground = c.points >= 3 && std::abs(z_N + c.down_m - *floor_N_) <= max_step_m_;
    found |= c.ground;
  }
  if (found) {
    MeasureGround(r);
    floor_N_ = z_N + r->height_m;
    candidate_N_.reset();
    return;
  }
  // A new level that stays under the vehicle for relock_s becomes the ground (a platform, a
  // floor at another level).
  if (!candidate_N_ || std::abs(level - *candidate_N_) > max_step_m_) candidate_N_ = level, candidate_since_ = utime;
  if ((utime - candidate_since_) * 1e-6 >= relock_s_) {
    floor_N_ = level;
    candidate_N_.reset();
    for (DotCluster& c : r->clusters) c.ground = c.points > 0 && std::abs(z_N + c.down_m - level) <= max_step_m_;
    MeasureGround(r);
    return;
  }
  char why[160];
  std::snprintf(why, sizeof why, "the floor is hidden: the dots land %.2f m %s the floor seen last", std::abs(level - *floor_N_),
                level < *floor_N_ ? "above" : "below");
  r->healthy = false;
  r->reason = why;
  r->height_m = r->height_sigma_m = 0.0;
  for (DotCluster& c : r->clusters) c.ground = false;
}

void ActiveStereoParams::Validate() const {
  auto need = [](bool ok, const char* what) {
    if (!ok) Bad(what);
  };
  need(std::isfinite(threshold_dn) && threshold_dn > 0 && threshold_dn < 255, "threshold_dn must be in (0, 255)");
  need(min_dot_area_px > 0 && max_dot_area_px > min_dot_area_px, "dot areas must satisfy 0 < min < max");
  need(max_bright_fraction > 0 && max_bright_fraction < 1, "max_bright_fraction must be in (0, 1)");
  need(min_disparity_px > 0 && max_disparity_px > min_disparity_px, "the disparity window must satisfy 0 < min < max");
  need(row_tolerance_px >= 0 && ambiguity_margin_px >= 0, "row_tolerance_px and ambiguity_margin_px must not be negative");
  need(max_clusters >= 1 && max_clusters <= 16, "max_clusters must be 1..16");
  need(cluster_spread_m > 0, "cluster_spread_m must be positive");
  need(min_points >= 3 && min_ground_points >= 3, "min_points and min_ground_points must be at least 3");
}

Eigen::Vector3d TriangulateLinear(const Eigen::Matrix<double, 3, 4>& P, const Eigen::Matrix<double, 3, 4>& Pp,
                                  const Eigen::Vector2d& x, const Eigen::Vector2d& xp) {
  // Eq. 4.9: rows u p3 - p1, v p3 - p2 of each camera; Eq. 4.11: the same of the fourth column.
  Eigen::Matrix<double, 4, 3> A;
  Eigen::Vector4d b;
  const Eigen::Matrix<double, 3, 4>* cams[2] = {&P, &Pp};
  const Eigen::Vector2d* obs[2] = {&x, &xp};
  for (int k = 0; k < 2; ++k) {
    const auto& M = *cams[k];
    for (int i = 0; i < 2; ++i) {
      A.row(2 * k + i) = (*obs[k])(i) * M.block<1, 3>(2, 0) - M.block<1, 3>(i, 0);
      b(2 * k + i) = (*obs[k])(i) * M(2, 3) - M(i, 3);
    }
  }
  // Eq. 4.8, A X + b = 0, in least squares by SVD.
  return A.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(-b);
}

struct ActiveStereo::Impl {
  ActiveStereoParams p;
  StereoRectifier rectifier;
  Eigen::Matrix<double, 3, 4> P_left, P_right;  // rectified projection matrices
  explicit Impl(const StereoRig& rig, const ActiveStereoParams& params) : p(params), rectifier(rig) {
    const RectifiedGeometry& g = rectifier.geometry();
    P_left << g.f_px, 0, g.cx, 0, 0, g.f_px, g.cy, 0, 0, 0, 1, 0;
    P_right = P_left;
    P_right(0, 3) = -g.f_px * g.baseline_m;
  }
};

ActiveStereo::ActiveStereo(const StereoRig& rig, const ActiveStereoParams& params) {
  params.Validate();
  impl_ = std::make_unique<Impl>(rig, params);
}
ActiveStereo::~ActiveStereo() = default;
ActiveStereo::ActiveStereo(ActiveStereo&&) noexcept = default;
const ActiveStereoParams& ActiveStereo::params() const { return impl_->p; }
const RectifiedGeometry& ActiveStereo::geometry() const { return impl_->rectifier.geometry(); }

std::vector<cv::Point2f> ActiveStereo::FindDots(const cv::Mat& image, std::string* problem) const {
  const ActiveStereoParams& p = impl_->p;
  cv::Mat gray;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  else gray = image;
  // Thesis 4.3.1: the dots are much brighter than the surroundings; a threshold over the
  // image's median keeps them whatever the room's light.
  const int median = Median(gray);
  const double threshold = median + p.threshold_dn;
  std::vector<cv::Point2f> dots;
  if (threshold >= 255) {
    *problem = Format("too bright to see the dots (median %.0f DN)", median);
    return dots;
  }
  cv::Mat binary;
  cv::threshold(gray, binary, threshold, 255, cv::THRESH_BINARY);
  const double bright = static_cast<double>(cv::countNonZero(binary)) / static_cast<double>(binary.total());
  if (bright > p.max_bright_fraction) {
    *problem = Format("too bright to see the dots (%.1f %% of the image above the dot threshold)", 100 * bright);
    return dots;
  }
  std::vector<std::vector<cv::Point>> contours;
  cv::findContours(binary, contours, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_NONE);
  for (const auto& contour : contours) {
    // A circle fitted to the contour; its area filters noise and reflections (4.3.1).
    cv::Point2f centre;
    float radius = 0;
    cv::minEnclosingCircle(contour, centre, radius);
    const double area = M_PI * radius * radius;
    if (area < p.min_dot_area_px || area > p.max_dot_area_px) continue;
    // The centre to a fraction of a pixel: the brightness-weighted centroid inside the circle
    // (the fitted circle's own centre is only as fine as the contour's pixels).
    const cv::Rect box = cv::boundingRect(contour) & cv::Rect(0, 0, gray.cols, gray.rows);
    double sw = 0, sx = 0, sy = 0;
    for (int y = box.y; y < box.y + box.height; ++y)
      for (int x = box.x; x < box.x + box.width; ++x) {
        const double w = gray.at<uint8_t>(y, x) - threshold;
        if (w <= 0) continue;
        sw += w, sx += w * x, sy += w * y;
      }
    if (sw > 0) dots.emplace_back(static_cast<float>(sx / sw), static_cast<float>(sy / sw));
  }
  if (dots.empty()) *problem = "no laser dots seen (too far, blank, or the emitter off)";
  return dots;
}

ActiveStereoResult ActiveStereo::Process(const cv::Mat& left, const cv::Mat& right, const Eigen::Isometry3d& T_BL,
                                         const Eigen::Matrix3d& R_NB) const {
  const Impl& m = *impl_;
  const ActiveStereoParams& p = m.p;
  ActiveStereoResult out;
  try {
    m.rectifier.CheckPair(left, right);
  } catch (const std::invalid_argument& e) {
    out.reason = e.what();
    return out;
  }
  if (!T_BL.matrix().allFinite() || !R_NB.allFinite()) {
    out.reason = "the camera mount or the attitude is not finite";
    return out;
  }
  std::string left_problem, right_problem;
  const std::vector<cv::Point2f> left_px = FindDots(left, &left_problem), right_px = FindDots(right, &right_problem);
  out.left_dots = static_cast<int>(left_px.size());
  out.right_dots = static_cast<int>(right_px.size());
  if (left_px.empty() || right_px.empty()) {
    out.reason = left_px.empty() ? "left image: " + left_problem : "right image: " + right_problem;
    return out;
  }
  using Side = StereoRectifier::Side;
  const std::vector<cv::Point2f> l = m.rectifier.RectifyPoints(left_px, Side::kLeft);
  const std::vector<cv::Point2f> r = m.rectifier.RectifyPoints(right_px, Side::kRight);

  // Thesis 4.3.2: each left dot's match lies left of it on (nearly) the same row, within the
  // disparity window; a dot with two candidates on rows too alike to choose is rejected. The
  // search runs both ways and a match stands only when each dot is the other's choice (a right
  // dot whose own match was lost is not handed to a neighbour's left dot).
  auto choose = [&](const cv::Point2f& q, const std::vector<cv::Point2f>& others, double sign, bool* ambiguous) {
    double best = 1e9, second = 1e9;
    int best_j = -1;
    for (std::size_t j = 0; j < others.size(); ++j) {
      const double d = sign * (q.x - others[j].x), dy = std::abs(q.y - others[j].y);
      if (d < p.min_disparity_px || d > p.max_disparity_px || dy > p.row_tolerance_px) continue;
      if (dy < best) second = best, best = dy, best_j = static_cast<int>(j);
      else second = std::min(second, dy);
    }
    *ambiguous = best_j >= 0 && second <= best + p.ambiguity_margin_px;
    return *ambiguous ? -1 : best_j;
  };
  std::vector<int> match(l.size(), -1);
  for (std::size_t i = 0; i < l.size(); ++i) {
    bool ambiguous = false, back_ambiguous = false;
    const int j = choose(l[i], r, 1.0, &ambiguous);
    out.ambiguous += ambiguous;
    if (j >= 0 && choose(r[j], l, -1.0, &back_ambiguous) == static_cast<int>(i)) match[i] = j;
  }
  const Eigen::Matrix3d R_L_rect = m.rectifier.geometry().R_L_rect;
  for (std::size_t i = 0; i < l.size(); ++i) {
    if (match[i] < 0) continue;
    const cv::Point2f& a = l[i];
    const cv::Point2f& b = r[match[i]];
    LaserPoint pt;
    pt.left_px = left_px[i];
    pt.disparity_px = a.x - b.x;
    const Eigen::Vector3d X_rect = TriangulateLinear(m.P_left, m.P_right, {a.x, a.y}, {b.x, b.y});
    pt.p_C = R_L_rect * X_rect;
    pt.down_m = (R_NB * (T_BL * pt.p_C)).z();
    out.points.push_back(pt);
  }
  const int n = static_cast<int>(out.points.size());
  if (n < p.min_points) {
    out.reason = Format("%.0f dots matched of %.0f seen (%.0f needed)", n, out.left_dots, p.min_points);
    return out;
  }

  // Thesis 4.3.4: K-means on the 3-D points (gravity-aligned, about the body origin); k grows
  // until every cluster is flat to within cluster_spread_m, so a table and the floor beside it,
  // or a ledge and the floor below, come apart.
  cv::Mat samples(n, 3, CV_32F);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d q = R_NB * (T_BL * out.points[i].p_C);
    for (int k = 0; k < 3; ++k) samples.at<float>(i, k) = static_cast<float>(q(k));
  }
  std::vector<int> labels;
  int k = 1;
  for (; k <= p.max_clusters; ++k) {
    labels.assign(n, 0);
    if (k > 1) {
      cv::theRNG().state = 0x5eed;  // repeatable
      cv::Mat centres;
      cv::kmeans(samples, k, labels, cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 30, 1e-4), 3,
                 cv::KMEANS_PP_CENTERS, centres);
    }
    std::vector<double> s(k, 0), s2(k, 0);
    std::vector<int> c(k, 0);
    for (int i = 0; i < n; ++i) {
      const double z = out.points[i].down_m;
      s[labels[i]] += z, s2[labels[i]] += z * z, ++c[labels[i]];
    }
    bool flat = true;
    for (int j = 0; j < k; ++j)
      if (c[j] > 1 && std::sqrt(std::max(0.0, s2[j] / c[j] - (s[j] / c[j]) * (s[j] / c[j]))) > p.cluster_spread_m) flat = false;
    if (flat || k == p.max_clusters) break;
  }
  out.clusters.assign(k, DotCluster{});
  for (int i = 0; i < n; ++i) {
    DotCluster& c = out.clusters[labels[i]];
    out.points[i].cluster = labels[i];
    c.centre_B += T_BL * out.points[i].p_C;
    c.down_m += out.points[i].down_m;
    ++c.points;
  }
  for (DotCluster& c : out.clusters)
    if (c.points) c.centre_B /= c.points, c.down_m /= c.points;
  for (int i = 0; i < n; ++i) {
    DotCluster& c = out.clusters[labels[i]];
    c.spread_m += std::pow(out.points[i].down_m - c.down_m, 2);
  }
  for (DotCluster& c : out.clusters)
    if (c.points) c.spread_m = std::sqrt(c.spread_m / c.points);

  // The ground: the farthest cluster below with enough points, with any other flat cluster at
  // the same level (a floor wider than one cluster comes out in pieces). Tables, walls and
  // ledges are nearer and do not pull the height (thesis 4.4: no spike over a window's edge).
  int ground = -1;
  for (int j = 0; j < k; ++j)
    if (out.clusters[j].points >= p.min_ground_points && (ground < 0 || out.clusters[j].down_m > out.clusters[ground].down_m))
      ground = j;
  if (ground < 0) {
    out.reason = Format("no cluster of %.0f points to take as the ground (%.0f points in %.0f clusters)", p.min_ground_points, n, k);
    return out;
  }
  const double level = out.clusters[ground].down_m;
  for (DotCluster& c : out.clusters) c.ground = c.points > 0 && std::abs(c.down_m - level) <= 2 * p.cluster_spread_m;
  MeasureGround(&out);
  out.healthy = true;
  return out;
}

}  // namespace uav::vision
