#pragma once
// Onboard 2-D map stitching (thesis ch. 6) with what the thesis named as next steps (6.5).
//
// Per frame: register it to the previous one (FrameRegistration: KLT + RANSAC/LM homography,
// Algorithm 1's checks). The first frame, and any frame whose registration fails, is placed by
// the navigation solution: its camera pose projected onto the ground plane (the first frame so
// "parallel to the ground", 6.3.1; the fallback homography of Algorithm 1). A registered frame
// is placed by the navigation solution corrected by a rotation and shift in map space that
// carry its matched corners onto where the previous frame put them; the correction is carried
// from frame to frame (the chain of Eq. 6.4) and decays by `nav_anchor_gain` each frame, so
// neighbouring frames join by image registration while the map keeps the navigation
// solution's ground position, scale and perspective over 1000 frames. Each warped frame is
// gain-compensated block by block against the map under it (exposure and cloud-shadow steps do
// not show as patches), then written newest-on-top (Eq. 6.5, feathered at its edge) into 256 px tiles of a north-up
// canvas in local NED metres: memory grows with the area covered, not with a fixed canvas.
// That is the live map. Each frame is also kept (JPEG) with its matches: at the end of the
// survey Align() adjusts all placements jointly (cross-line matches, navigation prior) and
// RenderSeamless() renders the map offered for download again, without seams between lines.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <opencv2/core/mat.hpp>

#include "uav/shared/camera_intrinsics.hpp"
#include "uav/vision/frame_registration.hpp"
#include "uav/vision/global_alignment.hpp"

namespace uav::vision {

struct StitcherParams {
  double gsd_m = 0.0;              // [m/px] of the map; 0: the first frame's ground sample distance
  int tile_px = 256;               // canvas tile size
  double nav_anchor_gain = 0.2;    // share of the image-registration correction dropped per frame
  double ground_down_m = 0.0;      // ground plane, NED down [m]
  bool gain_compensation = true;
  int gain_blocks = 4;             // gain grid per frame (gain_blocks x gain_blocks)
  int feather_px = 24;             // [map px] a new frame fades in over this distance from its edge
  RegistrationParams registration;
  // Frames wider than this are registered (live and for the alignment) at 1/2, 1/4 or 1/8 of
  // their size: Lucas-Kanade's sub-pixel accuracy there is still well under a map pixel and the
  // cost falls with the square. [px], 160..20000.
  int registration_width_px = 800;
  // false: frames are placed and kept but no live tiles are written (an offline run that only
  // wants the final, adjusted map).
  bool live_map = true;
  // The final map (Align, RenderSeamless).
  AlignmentParams alignment;
  int cross_pairs_per_frame = 2;     // earlier passes each frame is matched against; 0..8
  double cross_min_overlap = 0.25;   // footprint overlap, of the smaller footprint, to match a pair; (0, 1]
  int blend_bands = 5;               // multi-band blending levels; 1..8
  int kept_jpeg_quality = 95;        // frames are kept JPEG-compressed for the final render; 50..100
};

// One image with the navigation solution's camera pose when it was taken.
struct StitchInput {
  cv::Mat image;                 // 8-bit BGR, the camera's size; may be empty when `encoded` is given
  int64_t utime = 0;
  // Camera in local NED (the navigation estimate). Without poses the map is in the first
  // frame's pixels (gsd 1, not geo-referenced) and frames chain by registration alone (Eq. 6.4).
  std::optional<Eigen::Isometry3d> T_NC;
  // The image's file as read (JPEG, PNG), when there is one: kept as it is for the final render
  // (no second compression) when the lens has no distortion to undo. Without `image` it is
  // decoded only as far as the stitcher needs (no live map, no distortion: grey, at the
  // registration's scale, which JPEG decodes several times faster than the whole image). Files
  // are decoded as stored, without turning them by their EXIF orientation: the intrinsics and
  // the pose describe the sensor's pixel grid.
  std::vector<uint8_t> encoded = {};
};

// A frame made ready to be added (MapStitcher::Prepare): decoded, undistorted, in grey at the
// registration's scale with its features found, and its file for the final render.
struct PreparedFrame {
  int64_t utime = 0;
  std::optional<Eigen::Isometry3d> T_NC;
  cv::Mat image;            // undistorted BGR at the camera's size; empty when there is no live map to write
  cv::Mat grey;             // undistorted grey at 1/reduce of the camera's size
  FrameFeatures features;   // in `grey`, for registering the next frame against this one
  cv::Mat thumbnail;        // grey, a few pixels across: for the final render's exposure gains
  std::vector<uint8_t> kept;  // the undistorted image as a file (the input's own, or JPEG)
  double seconds = 0.0;     // spent preparing
};

struct StitchStep {
  bool placed = false;      // false: the frame could not be placed at all (camera not seeing the ground)
  bool registered = false;  // placed by image registration (else by the navigation fallback)
  std::string failure;      // why registration failed, if it did
  Registration registration;
  double seconds = 0.0;     // processing time
};

// The map cropped to its content, north up: pixel (c, r) covers north = north_top_m - (r + 0.5)
// gsd, east = east_left_m + (c + 0.5) gsd.
struct Mosaic {
  bool georeferenced = false;  // false: the first frame had no pose; units are its pixels
  cv::Mat bgr;
  cv::Mat mask;  // 255 where an image was written
  double north_top_m = 0.0;
  double east_left_m = 0.0;
  double gsd_m = 0.0;
};

// One canvas tile as it is now (for the live map): tile (tx, ty) covers map pixels
// [tx * tile_px, (tx + 1) * tile_px) x [ty * tile_px, ...); map pixel (c, r) is centred on
// north = origin_north_m - r gsd, east = origin_east_m + c gsd.
struct MapTile {
  int tx = 0, ty = 0;
  cv::Mat bgr;   // tile_px x tile_px
  cv::Mat mask;  // 255 where mapped
};

struct MapGrid {
  double gsd_m = 0.0;
  double origin_north_m = 0.0, origin_east_m = 0.0;
  int tile_px = 0;
  bool georeferenced = false;
};

// Where a frame is on the map.
struct FramePlacement {
  int64_t utime = 0;
  bool registered = false;
  Eigen::Matrix3d H_map_img = Eigen::Matrix3d::Identity();  // undistorted image pixel -> map pixel
  // Ground (north, east) [m] of the image corners: top-left, top-right, bottom-right,
  // bottom-left (map pixels (x, y) when the map is not geo-referenced).
  std::array<Eigen::Vector2d, 4> corners_NE;
};

struct AlignmentReport {
  bool adjusted = false;
  std::string message;  // the solver's summary, or why nothing was adjusted
  int frames = 0, consecutive_pairs = 0, cross_pairs = 0;
  ResidualStats cross_before, cross_after;  // matches between passes [map px]
  ResidualStats all_before, all_after;      // every match
  int iterations = 0, matches_dropped = 0, pairs_rejected = 0;
  double seconds_matching = 0.0, seconds_solving = 0.0;
};

class MapStitcher {
 public:
  // Throws std::invalid_argument naming a bad intrinsic or parameter.
  MapStitcher(const CameraIntrinsics& camera, const StitcherParams& params = StitcherParams());
  ~MapStitcher();
  MapStitcher(MapStitcher&&) noexcept;

  // Add(Prepare(frame)).
  StitchStep Add(const StitchInput& frame);
  // The work on a frame that does not depend on the frames before it. Reads only what Add never
  // changes: one thread can prepare the next frame while another adds this one (one Prepare at a
  // time). Throws std::invalid_argument naming what is wrong: no image, a file that is not an
  // image, an image of another size or type than the camera's, a non-finite pose.
  PreparedFrame Prepare(StitchInput frame) const;
  // Registers the frame to the previous one and places it. Throws std::invalid_argument for a
  // frame Prepare did not make.
  StitchStep Add(PreparedFrame frame);

  // The live map: the tiles as written frame by frame.
  Mosaic Render() const;
  // Global alignment of every frame so far (global_alignment.hpp): each frame is matched with
  // the overlapping frames of earlier passes (a survey's neighbouring lines), then all
  // placements are solved together with the frame-to-frame matches and the navigation prior.
  // The live tiles stay as they were; PlacedCentreNE, Placements and RenderSeamless then use the
  // adjusted placements.
  AlignmentReport Align();
  // The final map: every kept frame rendered again at its current placement, with exposure
  // compensation, nearest-nadir seams and multi-band blending (seamless_render.hpp).
  Mosaic RenderSeamless() const;
  std::vector<FramePlacement> Placements() const;
  // Tiles written since the last call (each once, as it is now).
  std::vector<MapTile> TakeChangedTiles();
  MapGrid grid() const;
  int frames() const;
  // Ground position (north, east) [m] where frame k's principal point was placed, and the
  // placed ground size of one image pixel there [m] (for accuracy checks and reports).
  Eigen::Vector2d PlacedCentreNE(int k) const;
  double PlacedPixelSize(int k) const;
  size_t tiles() const;
  size_t memory_bytes() const;  // the tiles and the kept frames

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace uav::vision
