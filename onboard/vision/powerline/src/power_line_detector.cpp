#include "uav/vision/power_line_detector.hpp"

#include "wire_verifier.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <Eigen/Dense>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/ximgproc/edge_drawing.hpp>

namespace uav::vision {
namespace {

constexpr double kDeg = M_PI / 180.0;

struct Segment {
  Eigen::Vector2d p, q;  // end points [px]
  Eigen::Vector2d d;     // unit direction, x >= 0 (undirected lines)
  double length;
};

int Find(std::vector<int>& parent, int i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// Distance of point x from the infinite line through s.
double LineDistance(const Segment& s, const Eigen::Vector2d& x) {
  const Eigen::Vector2d n(-s.d.y(), s.d.x());
  return std::abs(n.dot(x - s.p));
}

// Whether a and b continue one another: nearly parallel, each near the other's line, and the gap
// between them along the line short. Allowing the offset to grow with the distance between the
// pieces lets a sagging wire's pieces join.
bool SameWire(const Segment& a, const Segment& b, const PowerLineParams& P, double diag) {
  const double cos_angle = std::abs(a.d.dot(b.d));
  if (cos_angle < std::cos(P.group_angle_deg * kDeg)) return false;
  const Eigen::Vector2d ma = 0.5 * (a.p + a.q), mb = 0.5 * (b.p + b.q);
  const double along = std::abs(a.d.dot(mb - ma));
  const double gap = along - 0.5 * (a.length + b.length);
  if (gap > P.group_gap_fraction * diag) return false;
  const double tolerance = P.group_offset_px + 0.02 * std::max(0.0, gap);
  return LineDistance(a, b.p) < tolerance && LineDistance(a, b.q) < tolerance && LineDistance(b, a.p) < tolerance &&
         LineDistance(b, a.q) < tolerance;
}

// Fits one group in its own frame; false when it is not a wire.
bool FitWire(const std::vector<const Segment*>& group, const PowerLineParams& P, double diag, WireCurve* w) {
  // Points every 2 px along each piece, weighted by length through their count.
  std::vector<Eigen::Vector2d> pts;
  for (const Segment* s : group) {
    const int n = std::max(2, static_cast<int>(s->length / 2.0));
    for (int i = 0; i <= n; ++i) pts.push_back(s->p + (s->q - s->p) * (static_cast<double>(i) / n));
  }
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  for (const auto& p : pts) c += p;
  c /= static_cast<double>(pts.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& p : pts) cov += (p - c) * (p - c).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(cov);
  Eigen::Vector2d axis = eig.eigenvectors().col(1);
  if (axis.x() < 0 || (axis.x() == 0 && axis.y() < 0)) axis = -axis;
  const Eigen::Vector2d perp(-axis.y(), axis.x());
  std::vector<Eigen::Vector2d> uv;
  uv.reserve(pts.size());
  for (const auto& p : pts) uv.emplace_back(axis.dot(p - c), perp.dot(p - c));
  double u_min = 1e300, u_max = -1e300;
  for (const auto& x : uv) u_min = std::min(u_min, x.x()), u_max = std::max(u_max, x.x());
  if (u_max - u_min < P.min_wire_fraction * diag) return false;
  const Eigen::Vector3d b = FitQuadratic(uv);
  // A wire is seen as its two flanks, one either side of the fitted centre line: their mean
  // distance from it is half the wire's width, and their spread about that distance is the fit's
  // residual. So a wire 10 px wide near the camera fits as well as one of 2 px far away.
  std::vector<double> offset;
  offset.reserve(uv.size());
  double sum = 0;
  for (const auto& x : uv) {
    offset.push_back(std::abs(b(0) + b(1) * x.x() + b(2) * x.x() * x.x() - x.y()));
    sum += offset.back();
  }
  const double half_width = sum / static_cast<double>(offset.size());
  double sq = 0;
  for (double d : offset) sq += (d - half_width) * (d - half_width);
  const double rms = std::sqrt(sq / static_cast<double>(offset.size()));
  if (rms > P.max_fit_rms_px) return false;
  // Support: the share of the span covered by the pieces' projections.
  std::vector<std::pair<double, double>> spans;
  for (const Segment* s : group) {
    const double a = axis.dot(s->p - c), e = axis.dot(s->q - c);
    spans.emplace_back(std::min(a, e), std::max(a, e));
  }
  std::sort(spans.begin(), spans.end());
  double covered = 0, reach = -1e300;
  for (const auto& [a, e] : spans) {
    if (e <= reach) continue;
    covered += e - std::max(a, reach);
    reach = e;
  }
  const double support = covered / (u_max - u_min);
  if (support < P.min_support) return false;
  w->origin_px = c;
  w->axis = axis;
  w->b = b;
  w->u_min = u_min;
  w->u_max = u_max;
  w->rms_px = rms;
  w->support = support;
  w->segments = static_cast<int>(group.size());
  w->width_px = 2 * half_width;
  return true;
}

// A wire hangs in front of whatever lies behind it, so the background is alike on its two sides,
// while a thin strip along a boundary (the horizon's far band, a roof's or a road's dark margin)
// has different surfaces either side. Along the curve, the grey level just beyond each flank (L,
// R) and on the curve (C): over texture L - R changes sign from place to place and its median is
// near zero, across a boundary it keeps its sign. The wire is kept when that median is smaller
// than `max_ratio` times the median contrast C - (L + R) / 2 of the wire against its background.
bool BackgroundAlikeOnBothSides(const cv::Mat& gray, const WireCurve& w, double widest_px, double max_ratio) {
  // [px] Past the widest wire the detector passes: a wide wire found by one flank only has its
  // curve on that flank, and the wire's own grey must not count as a side.
  const double beyond = std::max(0.5 * w.width_px, widest_px) + 2.0;
  std::vector<double> side_difference, contrast;
  for (const detail::StripsBeside& s : detail::ReadStripsBeside(gray, w, beyond)) {
    side_difference.push_back(s.left - s.right);
    contrast.push_back(s.contrast);
  }
  if (side_difference.size() < 5) return true;  // too little of it inside the image to tell
  return std::abs(detail::Median(side_difference)) < max_ratio * std::abs(detail::Median(contrast));
}


// Bilinear grey at p, NaN outside the image.
float GreyAt(const cv::Mat& gray, const Eigen::Vector2d& p) {
  if (!(p.x() >= 0 && p.y() >= 0 && p.x() <= gray.cols - 2 && p.y() <= gray.rows - 2))
    return std::numeric_limits<float>::quiet_NaN();
  const int x = static_cast<int>(p.x()), y = static_cast<int>(p.y());
  const float fx = static_cast<float>(p.x() - x), fy = static_cast<float>(p.y() - y);
  const uint8_t* r0 = gray.ptr<uint8_t>(y) + x;
  const uint8_t* r1 = gray.ptr<uint8_t>(y + 1) + x;
  return (1 - fy) * ((1 - fx) * r0[0] + fx * r0[1]) + fy * ((1 - fx) * r1[0] + fx * r1[1]);
}

// The curve's points 2 px apart, each with its normal.
std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> AlongTheCurve(const WireCurve& w) {
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> at;
  for (const Eigen::Vector2d& p : w.Sample(2.0))
    at.emplace_back(p, w.NormalAt(w.axis.dot(p - w.origin_px)));
  return at;
}

// The grey across a curve: per offset t in [-reach, reach] (1 px apart) along the normal, the
// grey at each of the points whose whole profile lies inside the image. An offset's column is
// read when first asked for: the cable's edges are found a few offsets out, and most of the
// background's are never needed.
class Across {
 public:
  Across(const cv::Mat& gray, const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>>& at, int reach)
      : gray_(gray), reach_(reach), columns_(2 * reach + 1) {
    for (const auto& [p, n] : at) {
      const Eigen::Vector2d first = p - reach * n, last = p + reach * n;
      // A straight profile inside at both ends is inside all along.
      if (std::min({first.x(), first.y(), last.x(), last.y()}) >= 0 && std::max(first.x(), last.x()) <= gray.cols - 2 &&
          std::max(first.y(), last.y()) <= gray.rows - 2)
        at_.emplace_back(p, n);
    }
  }
  int points() const { return static_cast<int>(at_.size()); }
  const std::vector<float>& Column(int k) const {
    std::vector<float>& column = columns_[k];
    if (column.empty())
      for (const auto& [p, n] : at_) column.push_back(GreyAt(gray_, p + (k - reach_) * n));
    return column;
  }

 private:
  const cv::Mat& gray_;
  int reach_;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> at_;
  mutable std::vector<std::vector<float>> columns_;
};

// Over offsets [from, to] of `across`: the median grey, and the median absolute deviation of
// each sample from its own offset's median (how steady the grey is along the curve).
struct Band {
  float level = 0, spread = 0;
};
Band BandOf(const Across& across, int from, int to) {
  std::vector<float> all, deviation;
  for (int k = from; k <= to; ++k) {
    const std::vector<float>& grey = across.Column(k);
    all.insert(all.end(), grey.begin(), grey.end());
    const float m = detail::Median(grey);
    for (const float g : grey) deviation.push_back(std::abs(g - m));
  }
  return {detail::Median(std::move(all)), detail::Median(std::move(deviation))};
}

// A cable near the camera is wider than the thickness filter passes, and is found by a highlight
// or a stripe along it: its curve then lies inside the cable, drawn as a thin line. Its true
// edges are where the background begins. Across the curve, the grey at a fixed offset is steady
// along a cable's length (the same surface all along it) while over a textured background it
// varies from sample to sample: per offset, the median absolute deviation of the grey over the
// samples (MAD) is low on the cable and high beyond its edges. An edge is the first offset out
// from the curve where the MAD passes halfway between the cable's (on the curve) and the
// background's (at the far ends) and stays past it. Over a smooth background (sky, pavement) the
// two do not differ and the curve is left as it was; so is a wire no wider than its flanks showed.
WireCurve ToTheCableEdges(const cv::Mat& gray, const WireCurve& w, double diag) {
  const int reach = static_cast<int>(std::ceil(0.04 * diag));  // [px] wider than a cable is seen
  const Across across(gray, AlongTheCurve(w), reach);
  if (across.points() < 10) return w;
  // Each offset's spread, worked out when first asked for: a thin wire's edges are found a few
  // offsets out, and the offsets beyond them are not needed.
  std::vector<float> mad(2 * reach + 1, -1.0f);
  const auto spread_at = [&](int k) {
    if (mad[k] < 0) mad[k] = BandOf(across, k, k).spread;
    return mad[k];
  };
  const auto median_of_five = [&](int first) {
    std::vector<float> five;
    for (int k = first; k < first + 5; ++k) five.push_back(spread_at(k));
    return detail::Median(std::move(five));
  };
  const float cable = median_of_five(reach - 2);
  const auto edge = [&](int step) {
    const float background = median_of_five(step < 0 ? 0 : 2 * reach - 4);
    if (background < 2.0f * cable) return std::numeric_limits<double>::quiet_NaN();  // no less steady than the cable
    const float threshold = 0.5f * (cable + background);
    for (int t = 1; t < reach - 1; ++t)
      if (spread_at(reach + step * t) > threshold && spread_at(reach + step * (t + 1)) > threshold) return step * (t - 0.5);
    return std::numeric_limits<double>::quiet_NaN();
  };
  const double left = edge(-1);
  if (!std::isfinite(left)) return w;
  const double right = edge(+1), width = right - left;
  if (!std::isfinite(width) || width <= w.width_px + 3.0) return w;
  WireCurve cable_edges = w;
  cable_edges.b(0) += 0.5 * (left + right);
  cable_edges.width_px = width;
  return cable_edges;
}

// A wide cable found over part of its length (pieces of it, over a background that hid its
// thin edges, gave nothing to group) goes on along its curve. From each end, 20 px at a time, the
// stretch ahead is the cable's when it is the same cable: its grey within the cable's own
// spread of the found part's, steady along it, and set apart from what lies 2 to 5 px beyond
// its edges (a background twice as unsteady, or a contrast of three times the cable's spread and
// 5 grey levels). The steadiest of the curve's extrapolation and 1-2 px either side is taken, and
// the quadratic is fitted again through the found part and the stretches taken.
WireCurve AlongTheCable(const cv::Mat& gray, const WireCurve& w) {
  const int half = std::max(1, static_cast<int>(std::floor(0.5 * w.width_px)) - 1);  // the cable's inside
  const int reach = half + 6;
  const std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> found = AlongTheCurve(w);
  const Across found_across(gray, found, reach);
  if (found_across.points() < 10) return w;
  const Band cable = BandOf(found_across, reach - half, reach + half);
  // Whether the stretch in `across`, centred on its column `centre`, is the cable's.
  const auto is_cable = [&](const Across& across, int centre, double* steadiness) {
    if (across.points() < 8) return false;
    const Band inside = BandOf(across, centre - half, centre + half);
    const Band left = BandOf(across, centre - reach, centre - reach + 3);
    const Band right = BandOf(across, centre + reach - 3, centre + reach);
    *steadiness = inside.spread;
    const float tolerance = std::max(3.0f * cable.spread, 10.0f);
    if (std::abs(inside.level - cable.level) > tolerance) return false;
    const auto apart = [&](const Band& side) {
      return side.spread >= 2.0f * inside.spread || std::abs(side.level - inside.level) >= 3.0f * cable.spread + 5.0f;
    };
    return apart(left) && apart(right);
  };
  const Eigen::Vector2d perp(-w.axis.y(), w.axis.x());
  std::vector<Eigen::Vector2d> uv;
  for (const Eigen::Vector2d& p : w.Sample(2.0)) uv.emplace_back(w.axis.dot(p - w.origin_px), perp.dot(p - w.origin_px));
  double u_min = w.u_min, u_max = w.u_max;
  constexpr double kStretchPx = 20.0;
  for (const int direction : {-1, +1}) {
    double u = direction < 0 ? w.u_min : w.u_max, shift = 0.0;
    for (;;) {
      // The stretch read 2 px wider either side, so each lateral shift is a shift of columns.
      constexpr int kShift = 2;
      std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> ahead;
      for (double a = 1.0; a <= kStretchPx; a += 1.0) {
        const Eigen::Vector2d n = w.NormalAt(u + direction * a);
        ahead.emplace_back(w.PointAt(u + direction * a) + shift * n, n);
      }
      const Across stretch(gray, ahead, reach + kShift);
      double best = std::numeric_limits<double>::infinity(), best_shift = 0.0;
      // The steadiest, nearest the extrapolation first: inside a cable wider than the window all
      // are alike, and the curve must not wander across it.
      for (const int ds : {0, -1, 1, -2, 2}) {
        double steadiness = 0.0;
        if (is_cable(stretch, reach + kShift + ds, &steadiness) && steadiness < best - 0.5) best = steadiness, best_shift = shift + ds;
      }
      if (!std::isfinite(best)) break;
      shift = best_shift;
      for (double a = 2.0; a <= kStretchPx; a += 2.0) {
        const Eigen::Vector2d q = w.PointAt(u + direction * a) + shift * w.NormalAt(u + direction * a);
        uv.emplace_back(w.axis.dot(q - w.origin_px), perp.dot(q - w.origin_px));
      }
      u += direction * kStretchPx;
      (direction < 0 ? u_min : u_max) = u;
    }
  }
  if (u_min == w.u_min && u_max == w.u_max) return w;
  WireCurve longer = w;
  longer.b = FitQuadratic(uv);
  longer.u_min = u_min;
  longer.u_max = u_max;
  return longer;
}

void CheckImage(const cv::Mat& bgr) {
  if (bgr.empty()) throw std::invalid_argument("empty image");
  if (bgr.type() != CV_8UC3)
    throw std::invalid_argument("image has " + std::to_string(bgr.channels()) + " channel(s) of depth " +
                                std::to_string(bgr.depth()) + "; a BGR colour image (8-bit, 3 channels) is needed");
  if (bgr.cols < 32 || bgr.rows < 32)
    throw std::invalid_argument("image of " + std::to_string(bgr.cols) + "x" + std::to_string(bgr.rows) +
                                " px is smaller than 32x32");
}

}  // namespace

void PowerLineParams::Validate() const {
  auto check = [](bool ok, const char* name) {
    if (!ok) throw std::invalid_argument(std::string("power-line parameter ") + name + " out of range");
  };
  check(max_wire_width_px >= 1 && max_wire_width_px <= 30, "max_wire_width_px (1..30)");
  check(edge_threshold >= 0 && edge_threshold <= 255, "edge_threshold (0..255)");
  check(min_segment_fraction > 0 && min_segment_fraction < 1, "min_segment_fraction (0..1)");
  check(horizontal_max_angle_deg > 0 && horizontal_max_angle_deg <= 90, "horizontal_max_angle_deg (0..90)");
  check(group_angle_deg > 0 && group_angle_deg < 45, "group_angle_deg (0..45)");
  check(group_offset_px > 0 && group_offset_px < 50, "group_offset_px (0..50)");
  check(group_gap_fraction >= 0 && group_gap_fraction < 1, "group_gap_fraction (0..1)");
  check(min_wire_fraction > 0 && min_wire_fraction <= 1, "min_wire_fraction (0..1)");
  check(min_support > 0 && min_support <= 1, "min_support (0..1)");
  check(max_fit_rms_px > 0 && max_fit_rms_px < 50, "max_fit_rms_px (0..50)");
  check(pyramid_levels >= 1 && pyramid_levels <= 4, "pyramid_levels (1..4)");
  check(lsd_density > 0 && lsd_density <= 1, "lsd_density (0..1)");
  check(segments == Segments::kEdLines || segments == Segments::kLsd, "segments (EDLines or LSD)");
  check(max_side_ratio > 0 && max_side_ratio < 100, "max_side_ratio (0..100)");
  check(line_orientations >= 0 && line_orientations <= 180, "line_orientations (0..180)");
  check(line_length_px >= 4 && line_length_px <= 200, "line_length_px (4..200)");
  check(line_flank_px >= 2 && line_flank_px <= 50, "line_flank_px (2..50)");
  check(min_wire_probability >= 0 && min_wire_probability <= 1, "min_wire_probability (0..1)");
}

Eigen::Vector2d WireCurve::PointAt(double u) const {
  const Eigen::Vector2d perp(-axis.y(), axis.x());
  return origin_px + u * axis + (b(0) + b(1) * u + b(2) * u * u) * perp;
}

Eigen::Vector2d WireCurve::NormalAt(double u) const {
  const Eigen::Vector2d perp(-axis.y(), axis.x());
  return (perp - (b(1) + 2 * b(2) * u) * axis).normalized();
}

std::vector<Eigen::Vector2d> WireCurve::Sample(double step_px) const {
  std::vector<Eigen::Vector2d> out;
  const int n = std::max(1, static_cast<int>(std::ceil((u_max - u_min) / std::max(step_px, 0.1))));
  for (int i = 0; i <= n; ++i) out.push_back(PointAt(u_min + (u_max - u_min) * i / n));
  return out;
}

Eigen::Vector3d FitQuadratic(const std::vector<Eigen::Vector2d>& uv) {
  // The rows of X are (1, u, u^2) (Eq. 3.38-3.39); b minimises |X b - v|^2 (Eq. 3.40).
  Eigen::MatrixXd X(uv.size(), 3);
  Eigen::VectorXd v(uv.size());
  for (std::size_t i = 0; i < uv.size(); ++i) {
    X(i, 0) = 1.0;
    X(i, 1) = uv[i].x();
    X(i, 2) = uv[i].x() * uv[i].x();
    v(i) = uv[i].y();
  }
  return X.colPivHouseholderQr().solve(v);
}

PowerLineDetector::PowerLineDetector(const PowerLineParams& params) : params_(params) { params_.Validate(); }

namespace {

// Straight pieces of the thin structures in a thickness-filtered image (8-bit or float; steps 2-4 of
// Detect); `gain` scales the structures' grey levels before the edge threshold.
std::vector<cv::Vec4f> ThinStructureSegments(const cv::Mat& thin, const PowerLineParams& P, double gain = 1.0) {
  // Sobel gradients of the thin structures (Eq. 3.28-3.30): both directions for wires at any
  // angle, d/dy alone for the thesis's near-horizontal wires.
  cv::Mat scaled = thin;
  if (thin.type() != CV_8U || gain != 1.0) thin.convertTo(scaled, CV_8U, gain);  // else no copy
  cv::Mat gx, gy, mag;
  cv::Sobel(scaled, gy, CV_32F, 0, 1, 3);
  if (P.mode == PowerLineParams::Mode::kHorizontal) {
    mag = cv::abs(gy);
  } else {
    cv::Sobel(scaled, gx, CV_32F, 1, 0, 3);
    cv::magnitude(gx, gy, mag);
  }
  // Inverse threshold: thin structures whose edges are strong enough (the Sobel kernel's gain of
  // 4 taken out, so the threshold is in grey levels) stay, the rest goes; inverted, the wires
  // are dark lines on white, and the segment detector finds each as the pair of its flanks, a
  // pixel either side.
  cv::Mat strong;
  mag.convertTo(strong, CV_32F, 0.25);
  cv::dilate(strong > P.edge_threshold, strong, cv::Mat());  // the ridge lies between its edges
  cv::Mat kept = cv::Mat::zeros(scaled.size(), CV_8U);
  scaled.copyTo(kept, strong);
  cv::Mat edge_input;
  kept.convertTo(edge_input, CV_8U, -2.0, 255.0);
  std::vector<cv::Vec4f> raw;
  if (P.segments == PowerLineParams::Segments::kLsd) {
    // LSD with OpenCV's defaults except the share of aligned pixels a region needs: a faint wire
    // over foliage has gaps in its ridge that the default (0.7) splits into pieces too short to keep.
    cv::createLineSegmentDetector(cv::LSD_REFINE_STD, 0.8, 0.6, 2.0, 22.5, 0.0, P.lsd_density)->detect(edge_input, raw);
    return raw;
  }
  // EDLines (Akinlar and Topal, 2011; OpenCV's EdgeDrawing): edge chains walked from anchors
  // along the gradient's ridge, cut into least-squares lines, each validated by its NFA as LSD's
  // are. A fifth of LSD's time on foliage, where LSD's region growing visits every textured
  // pixel. Chains and lines shorter than the shortest piece kept (min_segment_fraction of this
  // image's diagonal) are not followed at all: most of the foliage's edges end there.
  const cv::Ptr<cv::ximgproc::EdgeDrawing> edlines = cv::ximgproc::createEdgeDrawing();
  const int shortest_px = std::max(
      5, static_cast<int>(std::lround(P.min_segment_fraction * std::hypot(edge_input.cols, edge_input.rows))));
  edlines->params.MinPathLength = shortest_px;
  edlines->params.MinLineLength = shortest_px;
  edlines->detectEdges(edge_input);
  edlines->detectLines(raw);
  return raw;
}

// Steps 5-7 of Detect: the pieces (image pixels) grouped into wires, fitted and tested.
std::vector<WireCurve> WiresOfPieces(const std::vector<cv::Vec4f>& raw, const cv::Mat& gray, const PowerLineParams& P) {
  const double diag = std::hypot(gray.cols, gray.rows);
  std::vector<Segment> segs;
  const double min_len = P.min_segment_fraction * diag;
  const double max_slope = std::tan(P.horizontal_max_angle_deg * kDeg);
  for (const auto& r : raw) {
    Segment s{{r[0], r[1]}, {r[2], r[3]}, {}, 0.0};
    s.length = (s.q - s.p).norm();
    if (s.length < min_len) continue;  // removal of short segments
    s.d = (s.q - s.p) / s.length;
    if (s.d.x() < 0 || (s.d.x() == 0 && s.d.y() < 0)) s.d = -s.d;
    if (P.mode == PowerLineParams::Mode::kHorizontal && std::abs(s.d.y()) > max_slope * std::abs(s.d.x())) continue;
    segs.push_back(s);
  }
  // Grouping: pieces that continue one another belong to one wire (union-find).
  std::vector<int> parent(segs.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (std::size_t i = 0; i < segs.size(); ++i)
    for (std::size_t j = i + 1; j < segs.size(); ++j)
      if (SameWire(segs[i], segs[j], P, diag)) parent[Find(parent, static_cast<int>(i))] = Find(parent, static_cast<int>(j));
  std::vector<std::vector<const Segment*>> groups(segs.size());
  for (std::size_t i = 0; i < segs.size(); ++i) groups[Find(parent, static_cast<int>(i))].push_back(&segs[i]);
  // Second pass, on the curves: a group whose pieces all lie on another group's fitted curve
  // (within the grouping offset, extrapolated across the gap) is the same wire: a sagging wire's
  // far pieces, or its other flank. Groups too short to be wires alone join this way too.
  std::vector<std::pair<int, WireCurve>> fitted;
  PowerLineParams loose = P;
  loose.min_wire_fraction = P.min_segment_fraction;
  loose.min_support = 0.01;
  for (std::size_t g = 0; g < groups.size(); ++g) {
    WireCurve w;
    if (!groups[g].empty() && FitWire(groups[g], loose, diag, &w)) fitted.emplace_back(static_cast<int>(g), w);
  }
  auto on_curve = [&](const std::vector<const Segment*>& pieces, const WireCurve& w) {
    const Eigen::Vector2d perp(-w.axis.y(), w.axis.x());
    const double reach = P.group_gap_fraction * diag;
    for (const Segment* s : pieces)
      for (const Eigen::Vector2d& x : {s->p, s->q, Eigen::Vector2d(0.5 * (s->p + s->q))}) {
        const double u = w.axis.dot(x - w.origin_px), v = perp.dot(x - w.origin_px);
        if (u < w.u_min - reach || u > w.u_max + reach) return false;
        if (std::abs(w.b(0) + w.b(1) * u + w.b(2) * u * u - v) > P.group_offset_px) return false;
      }
    return true;
  };
  std::vector<int> merged(groups.size());
  std::iota(merged.begin(), merged.end(), 0);
  // Longest curves first, so that pieces join the best-supported curve.
  std::sort(fitted.begin(), fitted.end(), [](const auto& a, const auto& b) {
    return a.second.u_max - a.second.u_min > b.second.u_max - b.second.u_min;
  });
  for (std::size_t i = 0; i < fitted.size(); ++i)
    for (std::size_t j = i + 1; j < fitted.size(); ++j)
      if (on_curve(groups[fitted[j].first], fitted[i].second) || on_curve(groups[fitted[i].first], fitted[j].second))
        merged[Find(merged, fitted[j].first)] = Find(merged, fitted[i].first);
  std::vector<std::vector<const Segment*>> wires_pieces(groups.size());
  for (std::size_t g = 0; g < groups.size(); ++g)
    for (const Segment* s : groups[g]) wires_pieces[Find(merged, static_cast<int>(g))].push_back(s);
  std::vector<WireCurve> wires;
  for (const auto& g : wires_pieces) {
    WireCurve w;
    if (!g.empty() && FitWire(g, P, diag, &w) &&
        BackgroundAlikeOnBothSides(gray, w, P.max_wire_width_px * (1 << (P.pyramid_levels - 1)), P.max_side_ratio))
      wires.push_back(w);
  }
  return wires;
}

// A curve of the second search, found at half resolution, may lie on one flank of its wire's
// response, a pixel or two off: each of its samples moves to the strongest thin-structure response
// within 2 of those pixels across it, and the quadratic is fitted again to those points in the
// curve's frame. The wire is taken as thin (its centre line): a wide one is the first search's.
WireCurve OnTheRidge(const cv::Mat& thin, const WireCurve& w) {
  const Eigen::Vector2d perp(-w.axis.y(), w.axis.x());
  std::vector<Eigen::Vector2d> uv;
  for (const Eigen::Vector2d& p : w.Sample(2.0)) {
    const Eigen::Vector2d n = w.NormalAt(w.axis.dot(p - w.origin_px));
    double best = -1, best_t = 0;
    for (double t = -4.0; t <= 4.0; t += 0.5) {
      const int u = cvRound(p.x() + t * n.x()), v = cvRound(p.y() + t * n.y());
      if (u < 0 || v < 0 || u >= thin.cols || v >= thin.rows) continue;
      const double g = thin.at<uint8_t>(v, u);
      if (g > best || (g == best && std::abs(t) < std::abs(best_t))) best = g, best_t = t;
    }
    if (best < 0) continue;
    const Eigen::Vector2d q = p + best_t * n;
    uv.emplace_back(w.axis.dot(q - w.origin_px), perp.dot(q - w.origin_px));
  }
  if (uv.size() < 5) return w;
  WireCurve refined = w;
  refined.b = FitQuadratic(uv);
  refined.width_px = 0.0;
  return refined;
}

}  // namespace

std::vector<WireCurve> PowerLineDetector::Detect(const cv::Mat& bgr) const {
  CheckImage(bgr);
  const PowerLineParams& P = params_;
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  // Step 1, the thickness filter, passes structures up to max_wire_width_px; a wire near the
  // camera is wider. Each coarser pyramid level doubles the width that passes, and its pieces,
  // scaled back, join the finer levels' in the grouping.
  const cv::Mat thin = ThinStructureResponse(gray, P.max_wire_width_px);
  // The full-resolution pieces, and the coarser levels' with the second search's, are found at
  // once on two threads (OpenCV's pool; the same result on one): each is half of the work.
  std::vector<cv::Vec4f> raw, coarser, faint;
  const auto coarser_and_faint_pieces = [&] {
    cv::Mat level = gray;
    for (int l = 1; l < P.pyramid_levels; ++l) {
      cv::pyrDown(level, level);
      const float scale = static_cast<float>(1 << l);
      for (const cv::Vec4f& r : ThinStructureSegments(ThinStructureResponse(level, P.max_wire_width_px), P))
        coarser.push_back(r * scale);
    }
    if (P.line_orientations == 0) return;
    // The second search, for the wires whose ridge the texture around them broke into pieces
    // too short to keep. At half resolution (max-pooled, so a wire a pixel wide keeps its
    // strength), four times cheaper; averaged along a line of n pixels, texture's spread falls by
    // about sqrt(n) (3.3 over 11), so edges half as strong pass the same threshold: the response
    // is doubled before it.
    cv::Mat pooled, half;
    cv::dilate(thin, pooled, cv::Mat::ones(2, 2, CV_8U), cv::Point(0, 0));
    cv::resize(pooled, half, cv::Size(thin.cols / 2, thin.rows / 2), 0, 0, cv::INTER_NEAREST);
    const int length = 2 * static_cast<int>(P.line_length_px / 4.0) + 1;  // half resolution, odd
    const int flank = std::max(1, static_cast<int>(std::lround(P.line_flank_px / 2.0)));
    faint = ThinStructureSegments(OrientedLineResponse(half, P.line_orientations, length, flank), P, 2.0);
    for (cv::Vec4f& r : faint) r = 2.0f * r + cv::Vec4f::all(0.5f);  // half-resolution pixel centres
  };
  cv::parallel_for_(cv::Range(0, 2), [&](const cv::Range& tasks) {
    for (int task = tasks.start; task < tasks.end; ++task) {
      if (task == 0) raw = ThinStructureSegments(thin, P);
      else coarser_and_faint_pieces();
    }
  });
  raw.insert(raw.end(), coarser.begin(), coarser.end());
  std::vector<WireCurve> wires = WiresOfPieces(raw, gray, P);
  if (!faint.empty())
    for (const WireCurve& w : WiresOfPieces(faint, gray, P)) wires.push_back(OnTheRidge(thin, w));
  // One curve per wire, longest first: a curve lying along a longer one (its other flank, the same
  // wire found again on the coarser pyramid level or by the second search) is that wire.
  std::sort(wires.begin(), wires.end(),
            [](const WireCurve& a, const WireCurve& b) { return a.u_max - a.u_min > b.u_max - b.u_min; });
  std::vector<WireCurve> kept;
  for (const WireCurve& w : wires) {
    const auto along_kept = [&](const WireCurve& longer) {
      const Eigen::Vector2d perp(-longer.axis.y(), longer.axis.x());
      const double reach = 0.5 * std::max(longer.width_px, w.width_px) + P.group_offset_px;
      const std::vector<Eigen::Vector2d> samples = w.Sample(4.0);
      int near = 0;
      for (const Eigen::Vector2d& x : samples) {
        const double u = longer.axis.dot(x - longer.origin_px), v = perp.dot(x - longer.origin_px);
        near += u >= longer.u_min && u <= longer.u_max &&
                std::abs(longer.b(0) + longer.b(1) * u + longer.b(2) * u * u - v) <= reach;
      }
      return near >= 0.8 * static_cast<double>(samples.size());
    };
    if (std::none_of(kept.begin(), kept.end(), along_kept)) kept.push_back(w);
  }
  // A cable near the camera, found by a highlight or over part of its length, is taken to its
  // edges and along its length.
  for (WireCurve& w : kept) w = AlongTheCable(gray, ToTheCableEdges(gray, w, std::hypot(gray.cols, gray.rows)));
  if (P.min_wire_probability <= 0.0) return kept;
  // The learned check: paving joints, kerbs, window mullions and brush strokes pass every test
  // above; the verifier, trained on what the tests let through on real photos, drops most of them.
  const detail::WireVerifier& verifier = detail::WireVerifier::Embedded();
  std::vector<WireCurve> verified;
  for (WireCurve& w : kept) {
    w.probability = verifier.Probability(detail::MeasureWire(gray, thin, w));
    if (w.probability >= P.min_wire_probability) verified.push_back(w);
  }
  return verified;
}

cv::Mat OrientedLineResponse(const cv::Mat& thin, int orientations, int length_px, int flank_px) {
  if (thin.empty() || thin.type() != CV_8U) throw std::invalid_argument("OrientedLineResponse needs an 8-bit grey image");
  if (orientations < 1 || length_px < 1 || flank_px < 1)
    throw std::invalid_argument("OrientedLineResponse needs orientations, length and flank of 1 or more");
  // Sums along a line as sums of the image shifted to each of the line's pixels (the nearest
  // pixel to each step along the direction), in 16 bits on an image padded by mirroring, so the
  // border makes no line. A Gaussian of 0.5 px first, about the smoothing a bilinear sample at a
  // random sub-pixel place gives, so that a wire a pixel wide between two of a line's pixels
  // still adds up. Shifts, not turns of the image: six times faster than turning it.
  const int half = length_px / 2, reach = flank_px + 1, margin = half + reach + 1;
  cv::Mat padded8, padded;
  cv::copyMakeBorder(thin, padded8, margin, margin, margin, margin, cv::BORDER_REFLECT_101);
  cv::GaussianBlur(padded8, padded8, cv::Size(3, 3), 0.5);
  padded8.convertTo(padded, CV_16S);
  // The sums cover the image and `reach` around it, where the flanks are read.
  const cv::Size region(thin.cols + 2 * reach, thin.rows + 2 * reach);
  const cv::Rect image(reach, reach, thin.cols, thin.rows);
  cv::Mat best(thin.size(), CV_16S, cv::Scalar(0)), sums(region, CV_16S), flanks, response;
  for (int k = 0; k < orientations; ++k) {
    const double a = M_PI * k / orientations, dx = std::cos(a), dy = std::sin(a);
    sums.setTo(0);
    for (int t = -half; t <= half; ++t) {
      const int ox = static_cast<int>(std::lround(t * dx)), oy = static_cast<int>(std::lround(t * dy));
      sums += padded(cv::Rect(margin - reach + ox, margin - reach + oy, region.width, region.height));
    }
    // The flanks: the same sums `flank_px` either side, across the direction.
    const cv::Point across(static_cast<int>(std::lround(-flank_px * dy)), static_cast<int>(std::lround(flank_px * dx)));
    cv::add(sums(image + across), sums(image - across), flanks);
    cv::addWeighted(sums(image), 2.0, flanks, -1.0, 0.0, response);  // 2 x (line - flanks' mean)
    best = cv::max(best, response);
  }
  cv::Mat out;
  best.convertTo(out, CV_32F, 1.0 / (2.0 * (2 * half + 1)));
  return out;
}

cv::Mat ThinStructureResponse(const cv::Mat& grey, double max_wire_width_px) {
  // The black-hat keeps dark structures, the top-hat bright ones, narrower than the kernel; a
  // step edge (a roof, a road, a wall) has neither and drops out here.
  const int k = 2 * static_cast<int>(std::ceil(max_wire_width_px)) + 1;
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(k, k));
  cv::Mat dark, bright, thin;
  cv::morphologyEx(grey, dark, cv::MORPH_BLACKHAT, kernel);
  cv::morphologyEx(grey, bright, cv::MORPH_TOPHAT, kernel);
  cv::max(dark, bright, thin);
  return thin;
}

std::vector<cv::Vec4f> LsdSegments(const cv::Mat& bgr) {
  CheckImage(bgr);
  cv::Mat gray;
  cv::cvtColor(bgr, gray, cv::COLOR_BGR2GRAY);
  std::vector<cv::Vec4f> segs;
  cv::createLineSegmentDetector(cv::LSD_REFINE_STD)->detect(gray, segs);
  return segs;
}

cv::Mat DrawWireMask(const cv::Size& size, const std::vector<WireCurve>& wires, int width_px) {
  cv::Mat mask = cv::Mat::zeros(size, CV_8U);
  for (const auto& w : wires) {
    // A wire wider than two strokes is drawn as its two flanks, which is where its boundary
    // lies; a thinner one as its centre line.
    std::vector<double> offsets{0.0};
    if (w.width_px > 2.0 * width_px) offsets = {-0.5 * w.width_px, 0.5 * w.width_px};
    for (double offset : offsets) {
      std::vector<cv::Point> pts;
      for (const auto& p : w.Sample(2.0)) {
        const Eigen::Vector2d q = p + offset * w.NormalAt(w.axis.dot(p - w.origin_px));
        pts.emplace_back(cvRound(q.x()), cvRound(q.y()));
      }
      cv::polylines(mask, pts, false, cv::Scalar(255), width_px, cv::LINE_8);
    }
  }
  return mask;
}

cv::Mat DrawSegmentMask(const cv::Size& size, const std::vector<cv::Vec4f>& segments, int width_px) {
  cv::Mat mask = cv::Mat::zeros(size, CV_8U);
  for (const auto& s : segments)
    cv::line(mask, cv::Point(cvRound(s[0]), cvRound(s[1])), cv::Point(cvRound(s[2]), cvRound(s[3])), cv::Scalar(255),
             width_px, cv::LINE_8);
  return mask;
}

void MaskTally::Add(const cv::Mat& detected_mask, const cv::Mat& truth_mask, double tol_px) {
  // Distance of every pixel to the nearest set pixel of each mask.
  auto distance_to = [](const cv::Mat& mask) {
    cv::Mat inverted = mask == 0, dist;
    cv::distanceTransform(inverted, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
    return dist;
  };
  const cv::Mat to_truth = distance_to(truth_mask), to_detected = distance_to(detected_mask);
  detected += cv::countNonZero(detected_mask);
  truth += cv::countNonZero(truth_mask);
  detected_correct += cv::countNonZero((to_truth <= tol_px) & (detected_mask > 0));
  truth_found += cv::countNonZero((to_detected <= tol_px) & (truth_mask > 0));
}

MaskScore MaskTally::Score() const {
  MaskScore s;
  if (detected > 0) s.precision = detected_correct / detected;
  if (truth > 0) s.recall = truth_found / truth;
  if (s.precision + s.recall > 0) s.f1 = 2 * s.precision * s.recall / (s.precision + s.recall);
  return s;
}

MaskScore ScoreMasks(const cv::Mat& detected, const cv::Mat& truth, double tol_px) {
  MaskTally tally;
  tally.Add(detected, truth, tol_px);
  return tally.Score();
}

namespace detail {

bool ValueAt(const cv::Mat& image, const Eigen::Vector2d& p, double* value) {
  const int u = cvRound(p.x()), v = cvRound(p.y());
  if (u < 0 || v < 0 || u >= image.cols || v >= image.rows) return false;
  *value = image.at<uint8_t>(v, u);
  return true;
}

std::vector<StripsBeside> ReadStripsBeside(const cv::Mat& gray, const WireCurve& w, double beyond) {
  std::vector<StripsBeside> out;
  for (const Eigen::Vector2d& p : w.Sample(3.0)) {
    StripsBeside s;
    s.p = p;
    s.n = w.NormalAt(w.axis.dot(p - w.origin_px));
    // Each side's level is the median over a strip 8 px wide beyond the flank, so a second wire
    // strung beside this one, a pixel or two of the strip, does not count as a different surface.
    for (double t = beyond; t <= beyond + 8.0; t += 1.0) {
      double g;
      if (ValueAt(gray, p - t * s.n, &g)) s.left_strip.push_back(g);
      if (ValueAt(gray, p + t * s.n, &g)) s.right_strip.push_back(g);
    }
    if (s.left_strip.size() < 5 || s.right_strip.size() < 5) continue;
    s.left = Median(s.left_strip);
    s.right = Median(s.right_strip);
    const double background = 0.5 * (s.left + s.right);
    // The wire itself: the grey level between the flanks that stands out most from the background.
    double c = background;
    for (double t = -0.5 * w.width_px - 1.0; t <= 0.5 * w.width_px + 1.0; t += 0.5) {
      double g;
      if (ValueAt(gray, p + t * s.n, &g) && std::abs(g - background) > std::abs(c - background)) c = g;
    }
    s.contrast = c - background;
    out.push_back(std::move(s));
  }
  return out;
}

}  // namespace detail

}  // namespace uav::vision
