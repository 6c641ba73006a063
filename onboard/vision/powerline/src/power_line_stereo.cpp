#include "uav/vision/power_line_stereo.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>

#include <opencv2/imgproc.hpp>

namespace uav::vision {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kDisparityStepPx = 0.5;  // [px] search grid; the peak is refined below it

// Bilinear sample of a CV_32F image; false outside.
bool Sample(const cv::Mat& image, double x, double y, double* value) {
  if (x < 0 || y < 0 || x > image.cols - 1.001 || y > image.rows - 1.001) return false;
  const int x0 = static_cast<int>(x), y0 = static_cast<int>(y);
  const double fx = x - x0, fy = y - y0;
  const float* r0 = image.ptr<float>(y0);
  const float* r1 = image.ptr<float>(y0 + 1);
  *value = (1 - fy) * ((1 - fx) * r0[x0] + fx * r0[x0 + 1]) + fy * ((1 - fx) * r1[x0] + fx * r1[x0 + 1]);
  return true;
}

// The matching window of one piece: points along it and across it (the wire and its neighbours:
// wires strung together form a pattern across the window that only the right shift reproduces).
std::vector<Eigen::Vector2d> Window(const std::vector<Eigen::Vector2d>& along, double half_width_px) {
  const Eigen::Vector2d t = (along.back() - along.front()).normalized();
  const Eigen::Vector2d n(-t.y(), t.x());
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < along.size(); i += 2)
    for (double j = -half_width_px; j <= half_width_px; j += 1.0) out.push_back(along[i] + j * n);
  return out;
}

// Zero-mean normalised cross-correlation of the left window with the right image shifted by d;
// NaN when part of the window falls outside either image.
double Ncc(const std::vector<double>& left, const cv::Mat& right, const std::vector<Eigen::Vector2d>& pts, double d) {
  double sl = 0, sr = 0, sll = 0, srr = 0, slr = 0, r = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!Sample(right, pts[i].x() - d, pts[i].y(), &r)) return std::nan("");
    sl += left[i], sr += r, sll += left[i] * left[i], srr += r * r, slr += left[i] * r;
  }
  const double n = static_cast<double>(pts.size());
  const double var_l = sll - sl * sl / n, var_r = srr - sr * sr / n;
  if (var_l <= 1e-9 || var_r <= 1e-9) return 0.0;
  return (slr - sl * sr / n) / std::sqrt(var_l * var_r);
}

struct PieceMatch {
  double u = 0.0;  // curve parameter of the piece's centre
  double d = 0.0;  // [px] disparity
  std::vector<Eigen::Vector2d> along;  // the piece's points in the rectified left image
};

// Distance from the origin to the segment ab.
double SegmentDistance(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double t = ab.squaredNorm() > 0 ? std::clamp(-a.dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
  return (a + t * ab).norm();
}

}  // namespace

void WireRangingParams::Validate() const {
  auto check = [](bool ok, const char* name) {
    if (!ok) throw std::invalid_argument(std::string("wire ranging parameter ") + name + " out of range");
  };
  check(std::isfinite(min_range_m) && min_range_m > 0.1, "min_range_m (> 0.1 m)");
  check(std::isfinite(max_range_m) && max_range_m > min_range_m && max_range_m < 1000, "max_range_m (min_range_m..1000 m)");
  check(pieces >= 2 && pieces <= 100, "pieces (2..100)");
  check(min_baseline_angle_deg > 0 && min_baseline_angle_deg < 90, "min_baseline_angle_deg (0..90)");
  check(window_half_width_px >= 2 && window_half_width_px <= 50, "window_half_width_px (2..50)");
  check(min_correlation > 0 && min_correlation < 1, "min_correlation (0..1)");
  check(max_ambiguity > 0 && max_ambiguity <= 1, "max_ambiguity (0..1)");
  check(disparity_sigma_px > 0 && disparity_sigma_px < 10, "disparity_sigma_px (0..10)");
  check(max_fit_residual_px > 0 && max_fit_residual_px < 10, "max_fit_residual_px (0..10)");
  check(max_slope_deg > 0 && max_slope_deg <= 90, "max_slope_deg (0..90)");
  check(vertical_image_deg > 0 && vertical_image_deg < 45, "vertical_image_deg (0..45)");
  check(vertical_share > 0 && vertical_share <= 1, "vertical_share (0..1)");
}

struct PowerLineStereo::Impl {
  Impl(const StereoRig& rig, const PowerLineParams& detection, const WireRangingParams& ranging)
      : rectifier(rig), detector(detection), params(ranging), left(rig.left) {
    params.Validate();
  }
  StereoRectifier rectifier;
  PowerLineDetector detector;
  WireRangingParams params;
  CameraIntrinsics left;

  // The disparity of one piece of the curve, or false when it cannot be told.
  bool MatchPiece(const std::vector<Eigen::Vector2d>& along, const cv::Mat& response_left,
                  const cv::Mat& response_right, double* d_out) const {
    const WireRangingParams& P = params;
    const Eigen::Vector2d t = (along.back() - along.front()).normalized();
    const double sin_angle = std::abs(t.y());  // rectified rows are the epipolar lines
    if (sin_angle < std::sin(P.min_baseline_angle_deg * kDeg)) return false;
    const RectifiedGeometry& g = rectifier.geometry();
    const double d_lo = g.f_px * g.baseline_m / P.max_range_m, d_hi = g.f_px * g.baseline_m / P.min_range_m;
    const std::vector<Eigen::Vector2d> pts = Window(along, P.window_half_width_px);
    std::vector<double> left(pts.size());
    for (std::size_t i = 0; i < pts.size(); ++i)
      if (!Sample(response_left, pts[i].x(), pts[i].y(), &left[i])) return false;
    const int n = static_cast<int>((d_hi - d_lo) / kDisparityStepPx) + 1;
    std::vector<double> score(n);
    int best = -1;
    for (int i = 0; i < n; ++i) {
      score[i] = Ncc(left, response_right, pts, d_lo + i * kDisparityStepPx);
      if (std::isfinite(score[i]) && (best < 0 || score[i] > score[best])) best = i;
    }
    if (best < 0 || score[best] < P.min_correlation) return false;
    // A second peak clear of the first (two pixels across the wire, which takes 1 / sin_angle of
    // disparity per pixel) and nearly as strong makes the piece ambiguous: the window lined up
    // with a neighbouring wire of a bundle, one wire spacing off.
    const double peak_halfwidth = 2.0 / sin_angle;
    for (int i = 0; i < n; ++i) {
      const bool local_max = (i == 0 || !(score[i - 1] > score[i])) && (i == n - 1 || !(score[i + 1] > score[i]));
      if (local_max && std::abs(i - best) * kDisparityStepPx > peak_halfwidth && score[i] > P.max_ambiguity * score[best])
        return false;
    }
    double d = d_lo + best * kDisparityStepPx;
    if (best > 0 && best < n - 1 && std::isfinite(score[best - 1]) && std::isfinite(score[best + 1])) {
      const double a = score[best - 1], b = score[best], c = score[best + 1];
      const double den = a - 2 * b + c;
      if (den < 0) d += 0.5 * (a - c) / den * kDisparityStepPx;
    }
    *d_out = d;
    return d > 0;
  }

  // Whether a detected wire is a vertical structure (a pole, a trunk): along most of its length
  // its image runs toward the vanishing point of the vertical, the direction in which a vertical
  // line through that pixel is imaged whatever its depth; or, ranged, its polyline rises more than
  // max_slope_deg from level end to end. The image test alone decides for a trunk whose ranging
  // went wrong (a trunk against crowns and sky matched partly to what is behind it). Its cost: a
  // wire seen exactly end-on, in a vertical plane through the camera, is taken for a pole.
  bool Vertical(const Wire3D& w, const Eigen::Vector3d& down_L) const {
    const WireRangingParams& P = params;
    if (w.p_L.size() >= 2) {
      const Eigen::Vector3d along = w.p_L.back() - w.p_L.front();
      const double length = along.norm();
      if (length > 0 && std::abs(along.dot(down_L)) > length * std::sin(P.max_slope_deg * M_PI / 180.0)) return true;
    }
    const RectifiedGeometry& g = rectifier.geometry();
    const Eigen::Vector3d down = g.R_L_rect.transpose() * down_L;  // in the rectified frame
    const WireCurve& c = w.curve;
    int samples = 0, vertical = 0;
    for (const Eigen::Vector2d& x : c.Sample(8.0)) {
      const Eigen::Vector3d ray((x.x() - g.cx) / g.f_px, (x.y() - g.cy) / g.f_px, 1.0);
      // d/dt of the projection of (ray + t down), up to scale.
      const Eigen::Vector2d vertical_px(down.x() * ray.z() - ray.x() * down.z(), down.y() * ray.z() - ray.y() * down.z());
      if (vertical_px.norm() < 1e-3) continue;  // at the vertical's vanishing point: no direction
      const Eigen::Vector2d normal = c.NormalAt(c.axis.dot(x - c.origin_px));
      ++samples;
      // Along the vertical: at most vertical_image_deg off the tangent, so its sine on the normal.
      vertical += std::abs(normal.dot(vertical_px.normalized())) < std::sin(P.vertical_image_deg * M_PI / 180.0);
    }
    return samples > 0 && vertical >= P.vertical_share * samples;
  }

  // Whether the background beside one ranged piece lies at the piece's own depth on both sides:
  // a mark on a surface (a streak on the ground, a roof's margin), not a wire hanging in front of
  // what is behind it. Each side's strip, just beyond the wire, is matched in the grey images near
  // the wire's disparity. An untextured side (sky, a plain road) cannot tell and counts as
  // behind, and so does a side whose strip holds the next wire of a bundle at nearly this depth
  // while the other side is sky; requiring one side only would reject such bundles.
  bool PieceOnASurface(const std::vector<Eigen::Vector2d>& along, double width_px, double d_wire, const cv::Mat& grey_left,
                       const cv::Mat& grey_right) const {
    constexpr double kSearchPx = 1.5, kStepPx = 0.25, kSameDepthPx = 0.5, kMinCorrelation = 0.7, kMinVariance = 4.0;
    const Eigen::Vector2d t = (along.back() - along.front()).normalized();
    const Eigen::Vector2d n(-t.y(), t.x());
    for (double side : {-1.0, 1.0}) {
      std::vector<Eigen::Vector2d> pts;
      for (std::size_t i = 0; i < along.size(); i += 3)
        for (double j = 0.5 * width_px + 3.0; j <= 0.5 * width_px + 11.0; j += 1.0) pts.push_back(along[i] + side * j * n);
      std::vector<double> left(pts.size());
      double sum = 0, sum_sq = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        if (!Sample(grey_left, pts[i].x(), pts[i].y(), &left[i])) return false;
        sum += left[i], sum_sq += left[i] * left[i];
      }
      const double count = static_cast<double>(pts.size());
      if (sum_sq / count - (sum / count) * (sum / count) < kMinVariance) return false;  // cannot tell
      double best_d = 0, best = -1;
      for (double d = std::max(0.0, d_wire - kSearchPx); d <= d_wire + kSearchPx; d += kStepPx) {
        const double c = Ncc(left, grey_right, pts, d);
        if (std::isfinite(c) && c > best) best = c, best_d = d;
      }
      if (best < kMinCorrelation || std::abs(best_d - d_wire) > kSameDepthPx) return false;
    }
    return true;
  }

  // One curve ranged; nullopt when it is a mark on a surface, not a wire.
  std::optional<Wire3D> Range(const WireCurve& curve, const cv::Mat& response_left, const cv::Mat& response_right,
                              const cv::Mat& grey_left, const cv::Mat& grey_right) const {
    const WireRangingParams& P = params;
    const RectifiedGeometry& g = rectifier.geometry();
    Wire3D w;
    w.curve = curve;
    w.pieces = P.pieces;
    for (const Eigen::Vector2d& x : curve.Sample(8.0)) {
      const Eigen::Vector3d ray = g.R_L_rect * Eigen::Vector3d((x.x() - g.cx) / g.f_px, (x.y() - g.cy) / g.f_px, 1.0);
      if (ray.z() > 1e-6) w.image_px.push_back(Project(left, ray));
    }
    const double span = curve.u_max - curve.u_min, piece_len = span / P.pieces;
    std::vector<PieceMatch> matches;
    for (int k = 0; k < P.pieces; ++k) {
      const double u0 = curve.u_min + k * piece_len;
      std::vector<Eigen::Vector2d> pts;
      const int n = std::max(2, static_cast<int>(piece_len));
      for (int i = 0; i <= n; ++i) pts.push_back(curve.PointAt(u0 + piece_len * i / n));
      double d = 0;
      if (MatchPiece(pts, response_left, response_right, &d)) matches.push_back({u0 + 0.5 * piece_len, d, pts});
    }
    if (matches.size() < 2) return w;
    // Robust line d(u) = a + b u: the pair of pieces that most others agree with, then least
    // squares over those that agree.
    std::vector<int> inliers;
    double best_sum = 1e300;
    for (std::size_t i = 0; i < matches.size(); ++i)
      for (std::size_t j = i + 1; j < matches.size(); ++j) {
        const double b = (matches[j].d - matches[i].d) / (matches[j].u - matches[i].u);
        const double a = matches[i].d - b * matches[i].u;
        std::vector<int> in;
        double sum = 0;
        for (std::size_t k = 0; k < matches.size(); ++k) {
          const double r = std::abs(a + b * matches[k].u - matches[k].d);
          if (r < P.max_fit_residual_px) in.push_back(static_cast<int>(k)), sum += r;
        }
        if (in.size() > inliers.size() || (in.size() == inliers.size() && sum < best_sum)) inliers = in, best_sum = sum;
      }
    if (inliers.size() < 2) return w;
    Eigen::MatrixXd A(inliers.size(), 2);
    Eigen::VectorXd y(inliers.size());
    for (std::size_t k = 0; k < inliers.size(); ++k) {
      A(k, 0) = 1.0;
      A(k, 1) = matches[inliers[k]].u;
      y(k) = matches[inliers[k]].d;
    }
    const Eigen::Vector2d ab = A.colPivHouseholderQr().solve(y);
    const double rms = std::sqrt((A * ab - y).squaredNorm() / static_cast<double>(inliers.size()));
    const double sigma_d = std::max(P.disparity_sigma_px, rms);
    w.ranged_pieces = static_cast<int>(inliers.size());
    int on_surface = 0;
    for (int k : inliers)
      on_surface += PieceOnASurface(matches[k].along, curve.width_px, ab(0) + ab(1) * matches[k].u, grey_left, grey_right);
    if (2 * on_surface > static_cast<int>(inliers.size())) return std::nullopt;
    // The polyline covers the ranged pieces only: no extrapolation past the evidence.
    const double u_first = matches[inliers.front()].u - 0.5 * piece_len;
    const double u_last = matches[inliers.back()].u + 0.5 * piece_len;
    const int steps = std::max(1, static_cast<int>(std::lround((u_last - u_first) / piece_len)));
    for (int i = 0; i <= steps; ++i) {
      const double u = u_first + (u_last - u_first) * i / steps;
      const double d = ab(0) + ab(1) * u;
      if (!(d > 0)) continue;
      const Eigen::Vector2d x = curve.PointAt(u);
      const Eigen::Vector3d p = g.Triangulate(x.x(), x.y(), d);
      w.p_L.push_back(p);
      w.sigma_m.push_back(g.ErrorModel(sigma_d, 0.0).DepthSigma(g.f_px * g.baseline_m / d));
    }
    if (w.p_L.empty()) return w;
    w.range_m = w.p_L[0].norm();
    w.range_sigma_m = w.sigma_m[0];
    for (std::size_t i = 0; i < w.p_L.size(); ++i) {
      const double r = i + 1 < w.p_L.size() ? SegmentDistance(w.p_L[i], w.p_L[i + 1]) : w.p_L[i].norm();
      if (r < w.range_m) w.range_m = r, w.range_sigma_m = w.sigma_m[i];
    }
    return w;
  }
};

PowerLineStereo::PowerLineStereo(const StereoRig& rig, const PowerLineParams& detection, const WireRangingParams& ranging)
    : impl_(std::make_unique<Impl>(rig, detection, ranging)) {}
PowerLineStereo::~PowerLineStereo() = default;
PowerLineStereo::PowerLineStereo(PowerLineStereo&&) noexcept = default;

const RectifiedGeometry& PowerLineStereo::geometry() const { return impl_->rectifier.geometry(); }

std::vector<Wire3D> PowerLineStereo::Process(const cv::Mat& left, const cv::Mat& right, const Eigen::Vector3d& down_L) const {
  if (left.type() != CV_8UC3 || right.type() != CV_8UC3)
    throw std::invalid_argument("power lines in 3-D: both images must be 8-bit BGR");
  cv::Mat left_rect, right_rect;
  impl_->rectifier.Rectify(left, right, &left_rect, &right_rect);
  return ProcessRectified(left_rect, right_rect, down_L);
}

std::vector<Wire3D> PowerLineStereo::ProcessRectified(const cv::Mat& left_rect, const cv::Mat& right_rect,
                                                       const Eigen::Vector3d& down_L) const {
  const Impl& m = *impl_;
  m.rectifier.CheckPair(left_rect, right_rect);
  if (left_rect.type() != CV_8UC3 || right_rect.type() != CV_8UC3)
    throw std::invalid_argument("power lines in 3-D: both images must be 8-bit BGR");
  const cv::Mat rect[2] = {left_rect, right_rect};
  cv::Mat response[2], grey[2];
  for (int i = 0; i < 2; ++i) {
    cv::Mat grey8;
    cv::cvtColor(rect[i], grey8, cv::COLOR_BGR2GRAY);
    grey8.convertTo(grey[i], CV_32F);
    ThinStructureResponse(grey8, m.detector.params().max_wire_width_px).convertTo(response[i], CV_32F);
  }
  std::vector<Wire3D> wires;
  for (const WireCurve& c : m.detector.Detect(rect[0])) {
    std::optional<Wire3D> w = m.Range(c, response[0], response[1], grey[0], grey[1]);
    if (!w) continue;
    w->vertical = down_L.squaredNorm() > 0 && m.Vertical(*w, down_L.normalized());
    wires.push_back(std::move(*w));
  }
  return wires;
}

}  // namespace uav::vision
