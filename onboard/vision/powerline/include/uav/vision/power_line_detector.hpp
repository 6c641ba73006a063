#pragma once
// Power lines in one image (thesis 3.6): a thickness filter keeps only structures thinner than a
// wire can be, Sobel gradients of what is left (Eq. 3.28-3.30) with an inverse threshold give an
// edge map, a line segment detector (EDLines, or LSD) finds straight pieces in it, short pieces are
// removed, pieces that continue one another are grouped into wires, and each wire is fitted
// with a least-squares quadratic (Eq. 3.31-3.40) in its own frame, so wires at any angle work
// (a downward or tilted camera sees them so); the thesis's forward-camera mode, near-horizontal
// wires only, is a setting. The thickness filter runs on two pyramid levels, so a wire near the
// camera, wider than the filter passes at full resolution, is found on the coarser one. A wire
// hangs in front of its background, so a thin strip along a boundary (the horizon, a roof's or a
// road's margin), with different surfaces either side, is dropped. A plain class: images in,
// curves out.
#include <string>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

namespace uav::vision {

struct PowerLineParams {
  enum class Mode { kAny, kHorizontal };
  Mode mode = Mode::kAny;
  double max_wire_width_px = 4.0;     // thickness filter: thinner structures pass ...
  int pyramid_levels = 2;             // ... at full resolution, twice as wide at each coarser level
  double edge_threshold = 7.0;        // [grey levels] weakest thin-structure edge kept (inverse threshold)
  // The straight pieces of the edge map: EDLines, or OpenCV's LSD (3.5 times slower on foliage;
  // the vehicle's default until the avoidance tables are measured with EDLines: pwl_segments).
  enum class Segments { kEdLines, kLsd };
  Segments segments = Segments::kEdLines;
  double lsd_density = 0.4;           // LSD: share of aligned pixels in a segment's rectangle (OpenCV: 0.7)
  double min_segment_fraction = 0.03;  // of the image diagonal: shorter pieces are dropped
  double horizontal_max_angle_deg = 30.0;  // horizontal mode: steeper pieces are dropped
  double group_angle_deg = 5.0;       // pieces of one wire differ in direction by less ...
  double group_offset_px = 2.0;       // ... lie within this of each other's line ...
  double group_gap_fraction = 0.25;   // ... and leave gaps under this share of the diagonal
  double min_wire_fraction = 0.3;     // a wire spans at least this share of the diagonal ...
  double min_support = 0.5;           // ... with pieces along at least this share of its span
  double max_fit_rms_px = 2.0;        // [px] spread of the wire's flanks about their mean offset from the quadratic
  double max_side_ratio = 1.0;        // background difference across the wire, at most this times its contrast
  // Second search, for faint wires over texture whose ridge breaks into pieces too short for the
  // first: the thin-structure response at half resolution, averaged along straight lines in
  // `line_orientations` directions, less the mean of the parallel lines `line_flank_px` either
  // side; the same segments, grouping, fit and tests run on the strongest direction's response.
  int line_orientations = 24;         // 0: no second search
  // The learned check (wire_verifier.hpp): curves the verifier gives a lower probability of being
  // a wire are dropped. 0: no check.
  double min_wire_probability = 0.7;
  double line_length_px = 22.0;       // [px] length of the averaging line
  double line_flank_px = 4.0;         // [px] distance of the subtracted parallel lines

  // Throws std::invalid_argument naming the field when a value is out of its range.
  void Validate() const;
};

// One detected wire: v = b0 + b1 u + b2 u^2 (Eq. 3.31) in the wire's own frame, whose origin is
// `origin_px` and whose u axis is `axis` (unit, image pixels); u runs over [u_min, u_max].
struct WireCurve {
  Eigen::Vector2d origin_px = Eigen::Vector2d::Zero();
  Eigen::Vector2d axis = Eigen::Vector2d::UnitX();
  Eigen::Vector3d b = Eigen::Vector3d::Zero();  // b0, b1, b2
  double u_min = 0.0, u_max = 0.0;
  double rms_px = 0.0;        // residual of the fit over its supporting pieces
  double support = 0.0;       // share of [u_min, u_max] covered by pieces
  int segments = 0;           // straight pieces grouped into it
  double width_px = 0.0;      // between its flanks (0 when only one flank was found)
  double probability = 1.0;   // the learned verifier's that it is a wire (1 when it did not run)
  Eigen::Vector2d PointAt(double u) const;  // image pixel at u
  Eigen::Vector2d NormalAt(double u) const;  // unit normal of the curve at u (the tangent turned +90 degrees)
  std::vector<Eigen::Vector2d> Sample(double step_px) const;  // from u_min to u_max
  Eigen::Vector2d first() const { return PointAt(u_min); }
  Eigen::Vector2d last() const { return PointAt(u_max); }
};

// Least squares quadratic through points (Eq. 3.38-3.40, solved by QR rather than by the normal
// equations' inverse, which squares the condition number). Needs at least three distinct u.
Eigen::Vector3d FitQuadratic(const std::vector<Eigen::Vector2d>& uv);

class PowerLineDetector {
 public:
  explicit PowerLineDetector(const PowerLineParams& params = {});
  // Wires in a BGR image (CV_8UC3). Throws std::invalid_argument naming what is wrong with an
  // empty image, another type, or one under 32 x 32 pixels.
  std::vector<WireCurve> Detect(const cv::Mat& bgr) const;
  const PowerLineParams& params() const { return params_; }

 private:
  PowerLineParams params_;
};

// The thickness filter alone (CV_8U, same size as the 8-bit grey image): per pixel the larger
// of the black-hat (dark structures) and top-hat (bright ones) with a disc a little wider than
// max_wire_width_px, so thin lines stay bright and step edges (roofs, roads, walls) drop out.
cv::Mat ThinStructureResponse(const cv::Mat& grey, double max_wire_width_px);

// The second search's map (CV_32F, grey levels, the size of the 8-bit `thin`): per pixel the largest over
// `orientations` directions of the mean of `thin` along a line of `length_px` through it, less
// the mean of the two parallel lines `flank_px` either side (negative: 0). Texture averages out
// along a line, a straight wire does not, and a wire beside the pixel is in a flank, not on the line.
cv::Mat OrientedLineResponse(const cv::Mat& thin, int orientations, int length_px, int flank_px);

// The LSD-only baseline of the accuracy tables: every segment LSD finds in the grey image.
std::vector<cv::Vec4f> LsdSegments(const cv::Mat& bgr);

// A mask of the image's size: 255 on the curves (or segments) drawn `width_px` wide, 0 elsewhere.
// A wire wider than two strokes is drawn as its two flanks (its boundary), others as one curve.
cv::Mat DrawWireMask(const cv::Size& size, const std::vector<WireCurve>& wires, int width_px = 2);
cv::Mat DrawSegmentMask(const cv::Size& size, const std::vector<cv::Vec4f>& segments, int width_px = 2);

// Per-pixel precision and recall of `detected` against `truth` (both 8-bit masks) with a
// tolerance: a detected pixel is right within tol_px of a true one, a true pixel found within
// tol_px of a detected one (the BSDS-style boundary matching of power-line benchmarks).
struct MaskScore {
  double precision = 0.0, recall = 0.0, f1 = 0.0;
};
MaskScore ScoreMasks(const cv::Mat& detected, const cv::Mat& truth, double tol_px);

// The same counts summed over a set of images, so the set is scored as one (precision =
// correct detected pixels over all detected pixels), not as a mean of per-image scores.
struct MaskTally {
  double detected = 0, detected_correct = 0, truth = 0, truth_found = 0;  // pixel counts
  void Add(const cv::Mat& detected_mask, const cv::Mat& truth_mask, double tol_px);
  MaskScore Score() const;
};

}  // namespace uav::vision
