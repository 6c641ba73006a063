#include "uav/runtime/stitch_worker.hpp"

#include <cstdio>
#include <filesystem>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "uav/shared/text_file.hpp"
#include "uav/vision/map_export.hpp"
#include "uav/vision/map_stitcher.hpp"

namespace uav::runtime {

StitchWorker::StitchWorker(const CameraIntrinsics& camera, Blackboard& board, const Options& options)
    : VisionWorker(board), camera_(camera), options_(options), stitcher_(std::make_unique<vision::MapStitcher>(camera)) {
  std::filesystem::create_directories(options_.map_dir);
}

StitchWorker::~StitchWorker() = default;

int StitchWorker::frames() const { return stitcher_->frames(); }

void StitchWorker::Begin(int64_t /*utime*/) {
  captures_ = board_.captures.TakeAll();
  // The survey is over when the camera is off and the vehicle is on the ground: the map is
  // written then, so it is ready at landing.
  const BlackboardData d = board_.Snapshot();
  survey_over_ = !(d.capture_interval_s || d.capture_distance_m) && !d.airborne;
}

void StitchWorker::Work(Outbox& out) {
  std::vector<SurveyCapture> captures = std::move(captures_);
  captures_.clear();
  for (SurveyCapture& c : captures) {
    const cv::Mat image(c.height, c.width, CV_8UC3, c.bgr.data());
    const vision::StitchStep step = stitcher_->Add({image, c.utime, c.T_NC_estimate, {}});
    registered_ += step.registered;
  }
  // The live map: every changed tile, JPEG-compressed (unmapped pixels black).
  const vision::MapGrid grid = stitcher_->grid();
  for (vision::MapTile& t : stitcher_->TakeChangedTiles()) {
    cv::Mat shown = cv::Mat::zeros(t.bgr.size(), CV_8UC3);
    t.bgr.copyTo(shown, t.mask);
    MapTile live;
    live.map_id = maps_written_ + 1;
    live.tile_x = t.tx;
    live.tile_y = t.ty;
    live.tile_px = grid.tile_px;
    live.gsd_m = grid.gsd_m;
    live.origin_north_m = grid.origin_north_m;
    live.origin_east_m = grid.origin_east_m;
    live.georeferenced = grid.georeferenced;
    cv::imencode(".jpg", shown, live.jpeg, {cv::IMWRITE_JPEG_QUALITY, 75});
    if (live.jpeg.size() <= 60000) out.Post([live = std::move(live)](Blackboard& b) { b.tiles.Put({live.map_id, live.tile_x, live.tile_y}, live); });
  }
  if (stitcher_->frames() > 0 && survey_over_) Finish(out);
}

void StitchWorker::Finish(Outbox& out) {
  // The map offered for download: every frame adjusted jointly, then rendered again without
  // seams (the live tiles stay as they were flown).
  const vision::AlignmentReport alignment = stitcher_->Align();
  const vision::Mosaic map = stitcher_->RenderSeamless();
  char name[32];
  std::snprintf(name, sizeof name, "map_%d", maps_written_ + 1);
  const std::string prefix = (std::filesystem::path(options_.map_dir) / name).string();
  try {
    for (const std::string& path : vision::ExportMap(map, options_.home, prefix))
      out.Post([name = std::filesystem::path(path).filename().string(), contents = ReadTextFile(path, "map file")](
                   Blackboard& b) { b.downloads.Push({name, contents}); });
    ++maps_written_;
    last_map_ = prefix;
    char text[320];
    std::snprintf(text, sizeof text,
                  "map ready: %s.tif, %d frames (%d registered), %dx%d px at %.3f m/px; cross-line p95 %.1f -> %.1f px%s",
                  name, stitcher_->frames(), registered_, map.bgr.cols, map.bgr.rows, map.gsd_m,
                  alignment.cross_before.p95_px, alignment.cross_after.p95_px, alignment.adjusted ? "" : " (not adjusted)");
    out.PushStatus(Severity::kInfo, text);
  } catch (const std::exception& e) {
    out.PushStatus(Severity::kError, std::string("map not written: ") + e.what());
  }
  // The next survey starts a new map.
  stitcher_ = std::make_unique<vision::MapStitcher>(camera_);
  registered_ = 0;
}

}  // namespace uav::runtime
