#include "seamless_render.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <opencv2/core/eigen.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/stitching/detail/blenders.hpp>
#include <opencv2/stitching/detail/exposure_compensate.hpp>

#include "homography.hpp"
namespace uav::vision {

namespace {

// The frame's outline in map pixels.
std::vector<cv::Point2f> Outline(const Eigen::Matrix3d& H, const cv::Size& size) {
  std::vector<cv::Point2f> out;
  for (const Eigen::Vector2d& q : ImageCorners(size)) {
    const Eigen::Vector2d m = Apply(H, q);
    out.emplace_back(static_cast<float>(m.x()), static_cast<float>(m.y()));
  }
  return out;
}

// The frame warped into the map-pixel rectangle `roi`, from an image decoded at 1/reduce, and its
// footprint mask there (eroded by a pixel: the edge pixels mix with the outside).
void Warp(const cv::Mat& image, const Eigen::Matrix3d& H_map_img, int reduce, const cv::Rect& roi, double map_scale,
          int border, cv::Mat* warped, cv::Mat* mask) {
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();  // map pixel -> roi pixel (at map_scale)
  S(0, 0) = S(1, 1) = map_scale;
  S(0, 2) = -roi.x;
  S(1, 2) = -roi.y;
  cv::Mat H;
  cv::eigen2cv(Eigen::Matrix3d(S * H_map_img * Enlarge(reduce)), H);
  cv::warpPerspective(image, *warped, H, roi.size(), cv::INTER_LINEAR, border);
  if (mask) {
    cv::warpPerspective(cv::Mat(image.size(), CV_8U, cv::Scalar(255)), *mask, H, roi.size(), cv::INTER_NEAREST,
                        cv::BORDER_CONSTANT);
    cv::erode(*mask, *mask, cv::Mat(), cv::Point(-1, -1), 1, cv::BORDER_CONSTANT, cv::Scalar(0));
  }
}

// Which frames the final map is drawn from. Frames whose centres lie within kSeamSpacing of a
// footprint of each other see the ground alike: a point is then at most half that further from
// the centre of the view it gets than from the nearest one, under 2 degrees of view angle. A video
// or a densely taken survey overlaps by 90 % and more; with every frame's centre in the seams,
// most frames own a sliver across their whole footprint and are blended over all of it (a third
// of a survey's render; all of a turning or zooming video's, where each frame owns a ring or a
// wedge around the one before). So:
//  - in capture order, a frame is drawn when its centre is that far from every frame drawn so
//    far, or when kSeamNewGround of its footprint is ground none of them covers;
//  - then, while some frame has more than kSeamLeftover of its footprint uncovered, the one with
//    the most is drawn too;
//  - what is left, slivers under kSeamLeftover of a footprint at the map's outer edge, is not in
//    the map (`SeamlessRenderOf.*`: 0.03 % of a line's ground with a sideways wobble, 1.9 % of a video
//    turning 1.5 degrees a frame).
// Coverage is counted on a grid of kCoverageReduce map pixels (at 8, slivers of a sideways wobble
// fell between its cells: 0.9 % of a line's ground was lost).
std::vector<uint8_t> FramesToDraw(const std::vector<std::vector<cv::Point2f>>& outline,
                                  const std::vector<cv::Point2d>& centre, const cv::Rect& content) {
  constexpr double kSeamSpacing = 0.125;   // of the footprint's shorter side
  constexpr double kSeamNewGround = 0.2;   // of the footprint
  constexpr double kSeamLeftover = 0.005;  // of the footprint
  constexpr int kCoverageReduce = 4;
  const int n = static_cast<int>(outline.size());
  std::vector<uint8_t> drawn(n, 0);
  std::vector<int> picked;
  cv::Mat covered(content.height / kCoverageReduce + 2, content.width / kCoverageReduce + 2, CV_8U, cv::Scalar(0));
  std::vector<cv::Mat> footprint(n);  // on the grid, within `around`
  std::vector<cv::Rect> around(n);
  std::vector<double> cells(n);
  const auto uncovered = [&](int k) { return static_cast<double>(cv::countNonZero(footprint[k] & ~covered(around[k]))); };
  const auto draw = [&](int k) {
    drawn[k] = 1;
    picked.push_back(k);
    covered(around[k]) |= footprint[k];
  };
  for (int k = 0; k < n; ++k) {
    const std::vector<cv::Point2f>& q = outline[k];
    std::vector<cv::Point> corner;
    for (const cv::Point2f& p : q)
      corner.emplace_back(cvRound((p.x - content.x) / kCoverageReduce), cvRound((p.y - content.y) / kCoverageReduce));
    around[k] = (cv::boundingRect(corner) + cv::Size(1, 1)) & cv::Rect(cv::Point(0, 0), covered.size());
    footprint[k] = cv::Mat::zeros(around[k].size(), CV_8U);
    for (cv::Point& c : corner) c -= around[k].tl();
    cv::fillConvexPoly(footprint[k], corner, cv::Scalar(255));
    cells[k] = std::max(1, cv::countNonZero(footprint[k]));
    const double spacing = kSeamSpacing * std::min(cv::norm(q[1] - q[0]), cv::norm(q[3] - q[0]));
    bool near = false;
    for (const int j : picked) near = near || cv::norm(centre[j] - centre[k]) < spacing;
    if (!near || uncovered(k) > kSeamNewGround * cells[k]) draw(k);
  }
  std::vector<double> fresh(n, 0.0);  // uncovered cells of each frame not drawn
  for (int k = 0; k < n; ++k)
    if (!drawn[k]) fresh[k] = uncovered(k);
  for (;;) {
    int best = -1;
    double most = 0.0;
    for (int k = 0; k < n; ++k)
      if (!drawn[k] && fresh[k] > kSeamLeftover * cells[k] && fresh[k] > most) {
        best = k;
        most = fresh[k];
      }
    if (best < 0) break;
    draw(best);
    for (int k = 0; k < n; ++k)  // only the frames it overlaps lose uncovered ground
      if (!drawn[k] && (around[k] & around[best]).area() > 0) fresh[k] = uncovered(k);
  }
  return drawn;
}

}  // namespace

std::array<Eigen::Vector2d, 4> ImageCorners(const cv::Size& size) {
  const double w = size.width - 1, h = size.height - 1;
  return {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0), Eigen::Vector2d(w, h), Eigen::Vector2d(0, h)};
}

int ThumbnailReduction(const cv::Size& image_size) {
  int reduce = 8;
  while (reduce > 1 && image_size.width / reduce < 120) reduce /= 2;
  return reduce;
}

Eigen::Matrix3d Enlarge(int reduce) {
  Eigen::Matrix3d R = Eigen::Matrix3d::Identity();
  R(0, 0) = R(1, 1) = reduce;
  R(0, 2) = R(1, 2) = (reduce - 1) / 2.0;
  return R;
}

SeamlessMap RenderSeamless(const std::vector<SeamlessFrame>& frames, const cv::Size& image_size,
                           const cv::Point2d& centre_px, int bands,
                           const std::function<cv::Mat(int k, const cv::Rect& region, cv::Point* origin)>& load) {
  SeamlessMap out;
  const int n = static_cast<int>(frames.size());
  if (n == 0) return out;
  std::vector<std::vector<cv::Point2f>> outline(n);  // each frame's, in map pixels
  std::vector<cv::Rect> box(n);
  std::vector<cv::Point2d> centre(n);
  // The extent is checked in floating point before any integer rectangle is made: a placement
  // near the horizon puts corners beyond int's range, where a rectangle's area overflows and
  // looked small (30 frames of an oblique video asked for 34 GB).
  constexpr double kInf = std::numeric_limits<double>::infinity();
  double x0 = kInf, y0 = kInf, x1 = -kInf, y1 = -kInf;
  for (int k = 0; k < n; ++k) {
    outline[k] = Outline(frames[k].H_map_img, image_size);
    for (const cv::Point2f& q : outline[k]) {
      if (!std::isfinite(q.x) || !std::isfinite(q.y)) throw std::runtime_error("seamless map: a frame's placement is not finite");
      x0 = std::min<double>(x0, q.x);
      x1 = std::max<double>(x1, q.x);
      y0 = std::min<double>(y0, q.y);
      y1 = std::max<double>(y1, q.y);
    }
  }
  constexpr double kMostPixels = 4e8;  // about 12 GB to render (pyramids, weights, labels)
  if ((x1 - x0 + 1) * (y1 - y0 + 1) > kMostPixels)
    throw std::runtime_error("seamless map: " + std::to_string(std::llround(x1 - x0 + 1)) + "x" +
                             std::to_string(std::llround(y1 - y0 + 1)) + " px is too large to render");
  cv::Rect content;
  for (int k = 0; k < n; ++k) {
    box[k] = cv::boundingRect(outline[k]);
    const Eigen::Vector2d c = Apply(frames[k].H_map_img, Eigen::Vector2d(centre_px.x, centre_px.y));
    centre[k] = cv::Point2d(c.x(), c.y());
    content = k == 0 ? box[k] : (content | box[k]);
  }

  const std::vector<uint8_t> drawn = FramesToDraw(outline, centre, content);

  // 2. Seams: the nearest drawn frame's centre wins each pixel of the footprints, each footprint
  // eroded by 2 px (its edge pixels mix with the outside). A footprint is a convex
  // quadrilateral, so on a row it is one run of pixels, between its four edges' lines; rows are
  // labelled in parallel.
  constexpr double kInsetPx = 2.0;
  std::vector<std::array<Eigen::Vector3d, 4>> edges(n);  // (a, b, c): a x + b y + c >= 0 inside, |(a, b)| = 1
  for (int k = 0; k < n; ++k) {
    const std::vector<cv::Point2f>& q = outline[k];
    double area2 = 0.0;
    for (int i = 0; i < 4; ++i) area2 += q[i].x * q[(i + 1) % 4].y - q[(i + 1) % 4].x * q[i].y;
    for (int i = 0; i < 4; ++i) {
      const cv::Point2d p0 = q[i], p1 = q[(i + 1) % 4];
      Eigen::Vector2d normal(-(p1.y - p0.y), p1.x - p0.x);  // left of p0 -> p1
      if (area2 < 0) normal = -normal;
      normal.normalize();
      edges[k][i] = Eigen::Vector3d(normal.x(), normal.y(), -(normal.x() * p0.x + normal.y() * p0.y));
    }
  }
  cv::Mat label(content.size(), CV_32S, cv::Scalar(-1));
  cv::parallel_for_(cv::Range(0, content.height), [&](const cv::Range& rows) {
    std::vector<float> best(content.width);
    for (int row = rows.start; row < rows.end; ++row) {
      const double y = row + content.y;
      std::fill(best.begin(), best.end(), std::numeric_limits<float>::max());
      int* l = label.ptr<int>(row);
      for (int k = 0; k < n; ++k) {
        if (!drawn[k] || y < box[k].y || y >= box[k].y + box[k].height) continue;
        double x0 = content.x, x1 = content.x + content.width - 1;
        for (const Eigen::Vector3d& e : edges[k]) {
          const double rest = kInsetPx - e.y() * y - e.z();  // a x >= rest
          if (std::abs(e.x()) < 1e-12) {
            if (rest > 0) x1 = x0 - 1;
          } else if (e.x() > 0) {
            x0 = std::max(x0, std::ceil(rest / e.x()));
          } else {
            x1 = std::min(x1, std::floor(rest / e.x()));
          }
        }
        const double dy = y - centre[k].y;
        for (int x = static_cast<int>(x0); x <= static_cast<int>(x1); ++x) {
          const double dx = x - centre[k].x;
          const float d2 = static_cast<float>(dx * dx + dy * dy);
          const int c = x - content.x;
          if (d2 < best[c]) {
            best[c] = d2;
            l[c] = k;
          }
        }
      }
    }
  });
  std::vector<cv::Rect> cell(n);
  std::vector<cv::Vec4i> span(n, cv::Vec4i(content.width, content.height, -1, -1));  // x0, y0, x1, y1
  for (int y = 0; y < content.height; ++y) {
    const int* l = label.ptr<int>(y);
    for (int x = 0; x < content.width; ++x) {
      if (l[x] < 0) continue;
      cv::Vec4i& s = span[l[x]];
      s[0] = std::min(s[0], x);
      s[1] = std::min(s[1], y);
      s[2] = std::max(s[2], x);
      s[3] = std::max(s[3], y);
    }
  }
  for (int k = 0; k < n; ++k)
    if (span[k][2] >= 0)
      cell[k] = cv::Rect(span[k][0] + content.x, span[k][1] + content.y, span[k][2] - span[k][0] + 1, span[k][3] - span[k][1] + 1);

  // 1. Exposure: one gain per frame, from the thumbnails warped at their scale (OpenCV's
  // compensator then costs little per pair of frames; it takes colour, so grey in three channels).
  const int reduce = ThumbnailReduction(image_size);
  const double small = 1.0 / reduce;
  std::vector<cv::Point> corners;
  std::vector<cv::UMat> images;
  std::vector<std::pair<cv::UMat, uchar>> masks;
  std::vector<int> fed;
  for (int k = 0; k < n; ++k)
    if (!cell[k].empty()) fed.push_back(k);
  corners.resize(fed.size());
  images.resize(fed.size());
  masks.resize(fed.size());
  // Thumbnails are warped in parallel (each one independent).
  cv::parallel_for_(cv::Range(0, static_cast<int>(fed.size())), [&](const cv::Range& range) {
    for (int i = range.start; i < range.end; ++i) {
      const int k = fed[i];
      const cv::Rect r(static_cast<int>(std::floor(box[k].x * small)), static_cast<int>(std::floor(box[k].y * small)),
                       static_cast<int>(std::ceil(box[k].width * small)) + 1,
                       static_cast<int>(std::ceil(box[k].height * small)) + 1);
      cv::Mat warped, mask;
      Warp(frames[k].thumbnail, frames[k].H_map_img, reduce, r, small, cv::BORDER_CONSTANT, &warped, &mask);
      cv::cvtColor(warped, warped, cv::COLOR_GRAY2BGR);
      corners[i] = r.tl();
      images[i] = warped.getUMat(cv::ACCESS_READ).clone();
      masks[i] = {mask.getUMat(cv::ACCESS_READ).clone(), uchar(255)};
    }
  });
  std::vector<double> gain(n, 1.0);
  if (fed.size() > 1) {
    cv::detail::GainCompensator compensator;
    compensator.feed(corners, images, masks);
    const std::vector<double> g = compensator.gains();
    for (size_t i = 0; i < fed.size(); ++i) gain[fed[i]] = std::isfinite(g[i]) ? std::clamp(g[i], 0.5, 2.0) : 1.0;
  }
  images.clear();
  masks.clear();

  // 3. Multi-band blending over the seams. Each frame is fed over its cell and a margin of the
  // blender's reach, with its border replicated beyond the footprint (never black).
  cv::detail::MultiBandBlender blender(false, bands);
  blender.prepare(content);
  const int margin = 2 << bands;
  // In batches, decoded and warped in parallel; the blender takes them in order on this thread
  // while the next batch is decoded and warped (a feed accumulates into the one set of pyramids).
  constexpr int kBatch = 8;
  struct Batch {
    std::vector<cv::Mat> img;  // 8-bit BGR, gain applied
    std::vector<cv::Rect> roi;
  };
  auto warp_batch = [&](size_t first) {
    const int count = static_cast<int>(std::min<size_t>(kBatch, fed.size() - first));
    Batch b{std::vector<cv::Mat>(count), std::vector<cv::Rect>(count)};
    cv::parallel_for_(cv::Range(0, count), [&](const cv::Range& range) {
      for (int i = range.start; i < range.end; ++i) {
        const int k = fed[first + i];
        b.roi[i] = (cell[k] + cv::Size(2 * margin, 2 * margin) - cv::Point(margin, margin)) & box[k] & content;
        // Only the part of the frame the roi maps back onto (and 2 px for interpolation) is
        // decoded: a frame's cell is a strip of it.
        std::vector<cv::Point2f> back;
        const Eigen::Matrix3d H_img_map = frames[k].H_map_img.inverse();
        for (const Eigen::Vector2d& q : ImageCorners(b.roi[i].size())) {
          const Eigen::Vector2d p = Apply(H_img_map, q + Eigen::Vector2d(b.roi[i].x, b.roi[i].y));
          back.emplace_back(static_cast<float>(p.x()), static_cast<float>(p.y()));
        }
        const cv::Rect needed =
            (cv::boundingRect(back) + cv::Size(6, 6) - cv::Point(3, 3)) & cv::Rect(cv::Point(0, 0), image_size);
        cv::Point origin;
        const cv::Mat part = load(k, needed, &origin);
        Eigen::Matrix3d T_img_part = Eigen::Matrix3d::Identity();  // part pixel -> frame pixel
        T_img_part(0, 2) = origin.x;
        T_img_part(1, 2) = origin.y;
        // The gain goes on the decoded part, before the warp, and the blender takes 8 bits: a
        // 16-bit copy of the warped frame is twice the memory, and fresh pages cost more than the
        // arithmetic (before: a third of the render's time was first touches of such copies).
        cv::Mat gained = part;
        if (gain[k] != 1.0) part.convertTo(gained, -1, gain[k]);
        Warp(gained, frames[k].H_map_img * T_img_part, 1, b.roi[i], 1.0, cv::BORDER_REPLICATE, &b.img[i], nullptr);
      }
    });
    return b;
  };
  std::future<Batch> next = std::async(std::launch::async, warp_batch, 0);
  for (size_t first = 0; first < fed.size(); first += kBatch) {
    const Batch b = next.get();
    if (first + kBatch < fed.size()) next = std::async(std::launch::async, warp_batch, first + kBatch);
    for (size_t i = 0; i < b.roi.size(); ++i) {
      const int k = fed[first + i];
      blender.feed(b.img[i], label(b.roi[i] - content.tl()) == k, b.roi[i].tl());
    }
  }
  cv::Mat result, result_mask;
  blender.blend(result, result_mask);
  result.convertTo(out.bgr, CV_8UC3);
  cv::bitwise_and(result_mask, label >= 0, out.mask);
  out.bgr.setTo(cv::Scalar::all(0), out.mask == 0);
  out.origin = content.tl();
  return out;
}

}  // namespace uav::vision
