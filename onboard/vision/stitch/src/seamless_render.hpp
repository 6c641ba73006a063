#pragma once
// The final map of a survey, rendered again from every frame once the placements are adjusted
// (internal to the stitcher). Three steps, as OpenCV's stitching pipeline:
//   1. exposure: one gain per frame from the overlaps (cv::detail::GainCompensator), on the
//      frames' grey thumbnails (the brightness of an overlap: a mean, for which 120 px across a
//      frame are plenty);
//   2. seams: each map pixel is taken from the frame whose centre (principal point) is nearest,
//      the most nadir view, with the least relief displacement and lens error (a Voronoi seam on
//      the frames' centres, clipped to their footprints). Of frames whose centres nearly
//      coincide (a video, a dense survey), only those the coverage needs are drawn;
//   3. multi-band blending across those seams (cv::detail::MultiBandBlender, Burt and Adelson),
//      so brightness differences fade over a band-dependent width while edges stay sharp.
#include <array>
#include <functional>
#include <vector>

#include <Eigen/Core>
#include <opencv2/core/mat.hpp>

namespace uav::vision {

// The image's corner pixels: top-left, top-right, bottom-right, bottom-left.
std::array<Eigen::Vector2d, 4> ImageCorners(const cv::Size& size);
// Pixel of an image decoded at 1/reduce -> pixel of the full image.
Eigen::Matrix3d Enlarge(int reduce);

// A frame's thumbnail is its grey image at 1/ThumbnailReduction of its size (pixel centres as
// Enlarge maps them): 1/8, or less reduced for frames under 960 px across.
int ThumbnailReduction(const cv::Size& image_size);

struct SeamlessFrame {
  Eigen::Matrix3d H_map_img;  // undistorted image pixel -> map pixel
  cv::Mat thumbnail;          // 8-bit grey, undistorted, at 1/ThumbnailReduction
};

struct SeamlessMap {
  cv::Mat bgr, mask;  // content only
  cv::Point origin;   // map pixel of bgr(0, 0)
};

// load(k, region, origin): frame k, undistorted 8-bit BGR, at least its pixels in `region` (of
// the full frame, clipped to it), *origin the full frame's pixel at the result's (0, 0); called
// from several threads at once.
// centre_px: the principal point; image_size: the frames' size. bands: multi-band levels.
SeamlessMap RenderSeamless(const std::vector<SeamlessFrame>& frames, const cv::Size& image_size,
                           const cv::Point2d& centre_px, int bands,
                           const std::function<cv::Mat(int k, const cv::Rect& region, cv::Point* origin)>& load);

}  // namespace uav::vision
