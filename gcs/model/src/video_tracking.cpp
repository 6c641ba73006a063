#include "uav/gcs/video_tracking.hpp"

#include <algorithm>

#include <stb_image.h>

#include <cmath>
#include <cstdio>

namespace uav::gcs {

bool DecodeJpeg(const std::vector<uint8_t>& jpeg, int width, int height, std::vector<uint8_t>* rgba,
                std::string* problem) {
  if (jpeg.empty() || jpeg.size() > kMaxJpegBytes) {
    *problem = "JPEG of " + std::to_string(jpeg.size()) + " bytes (1.." + std::to_string(kMaxJpegBytes) + " allowed)";
    return false;
  }
  int w = 0, h = 0, channels = 0;
  unsigned char* pixels = stbi_load_from_memory(jpeg.data(), static_cast<int>(jpeg.size()), &w, &h, &channels, 4);
  if (!pixels) {
    *problem = std::string("undecodable JPEG: ") + stbi_failure_reason();
    return false;
  }
  if (w != width || h != height) {
    *problem = "JPEG is " + std::to_string(w) + "x" + std::to_string(h) + ", message says " + std::to_string(width) +
               "x" + std::to_string(height);
    stbi_image_free(pixels);
    return false;
  }
  rgba->assign(pixels, pixels + static_cast<size_t>(w) * h * 4);
  stbi_image_free(pixels);
  return true;
}

bool VideoTracking::ChooseCamera(VehicleVideo& v, const std::string& camera) {
  if (std::find(v.cameras.begin(), v.cameras.end(), camera) == v.cameras.end()) return false;
  if (camera != v.camera) {
    v.camera = camera;
    v.video = VideoFeed{};  // the other camera's picture is not this one's
  }
  return true;
}

double VideoFeed::Rate(double now) const {
  int n = 0;
  for (double t : recent) n += now - t <= 1.0;
  return n;
}

void VideoTracking::OnVideoFrame(VehicleVideo& v, const std::string& vehicle_id, const VideoFrame& f, double now,
                                 MessageLog& log) {
  if (std::find(v.cameras.begin(), v.cameras.end(), f.camera) == v.cameras.end()) v.cameras.push_back(f.camera);
  if (v.camera.empty()) v.camera = f.camera;
  if (f.camera != v.camera) return;
  std::string problem;
  VideoPixels pixels{f.camera, f.utime, f.width, f.height, {}};
  if (!DecodeJpeg(f.jpeg, f.width, f.height, &pixels.rgba, &problem)) {
    if (v.video.rejected++ == 0) log.Add(now, vehicle_id, "video frame rejected: " + problem, Severity::kWarning);
    return;
  }
  OnVideoPixels(v, std::move(pixels), now);
  v.video.source_width = f.source_width;
  v.video.source_height = f.source_height;
}

void VideoTracking::OnVideoPixels(VehicleVideo& v, VideoPixels pixels, double now) {
  if (std::find(v.cameras.begin(), v.cameras.end(), pixels.camera) == v.cameras.end()) v.cameras.push_back(pixels.camera);
  if (v.camera.empty()) v.camera = pixels.camera;
  if (pixels.camera != v.camera) return;
  VideoFeed& feed = v.video;
  feed.rgba = std::move(pixels.rgba);
  feed.width = feed.source_width = pixels.width;
  feed.height = feed.source_height = pixels.height;
  feed.camera = pixels.camera;
  feed.utime = pixels.utime;
  ++feed.frames;
  feed.recent.push_back(now);
  while (!feed.recent.empty() && now - feed.recent.front() > 1.0) feed.recent.pop_front();
}

bool VideoTracking::OnTrackStatus(VehicleVideo& v, const std::string& vehicle_id, const TrackStatus& st, double now,
                                  MessageLog& log) {
  const bool finite = std::isfinite(st.center_x) && std::isfinite(st.center_y) && std::isfinite(st.width) &&
                      std::isfinite(st.height) && std::isfinite(st.angle_rad) && std::isfinite(st.window_x) &&
                      std::isfinite(st.window_y) && std::isfinite(st.window_width) && std::isfinite(st.window_height) &&
                      std::isfinite(st.confidence);
  const bool known_state = st.state == TrackStatus::kIdle || st.state == TrackStatus::kTracking ||
                           st.state == TrackStatus::kLost || st.state == TrackStatus::kRejected;
  // A box may reach past the edge, but a centre far outside the image is a broken message.
  const bool plausible = finite && std::abs(st.center_x - 0.5) <= 1.0 && std::abs(st.center_y - 0.5) <= 1.0 &&
                         st.width >= 0 && st.height >= 0 && st.width <= 2 && st.height <= 2;
  if (!known_state || !plausible) {
    log.Add(now, vehicle_id, "track status refused: not finite, unknown state or outside the image", Severity::kWarning);
    return false;
  }
  // A status answers one selection (target_seq): once this GCS has sent one, statuses about an
  // earlier (or another GCS's) selection describe a target the operator has replaced.
  if (v.track_target && st.target_seq != v.track_target->target_seq) {
    ++v.stale_track_statuses;
    return false;
  }
  // Rejections and losses are worth a line in the log, once per change.
  const bool changed = !v.track || v.track->state != st.state || v.track->target_seq != st.target_seq;
  if (changed && st.state == TrackStatus::kRejected)
    log.Add(now, vehicle_id, "target " + std::to_string(st.target_seq) + " rejected: " + st.reason, Severity::kWarning);
  else if (changed && st.state == TrackStatus::kLost)
    log.Add(now, vehicle_id, "target " + std::to_string(st.target_seq) + " lost" + (st.reason.empty() ? "" : ": " + st.reason),
            Severity::kWarning);
  v.track = st;
  v.track_received = now;
  return true;
}

bool VideoTracking::Freeze(const VehicleVideo* v, const std::string& vehicle_id, bool freeze) {
  if (!freeze) {
    frozen_.reset();
    frozen_vehicle_.clear();
    return true;
  }
  if (!v || v->video.frames == 0) return false;
  frozen_ = v->video;
  frozen_vehicle_ = vehicle_id;
  return true;
}

bool VideoTracking::SelectTarget(VehicleVideo* v, const std::string& vehicle_id, const TrackTarget& target, double now,
                                 MessageLog& log) {
  error_.clear();
  if (!v) {
    error_ = "no vehicle selected";
    return false;
  }
  if (target.method != TrackTarget::kCancel) {
    auto inside = [](double c) { return std::isfinite(c) && c >= 0.0 && c <= 1.0; };
    bool ok = inside(target.x) && inside(target.y) && inside(target.x + target.width) &&
              inside(target.y + target.height);
    for (const auto& c : target.corners) ok = ok && inside(c[0]) && inside(c[1]);
    if (!ok) {
      error_ = "target outside the image (coordinates must be finite, within 0..1)";
      return false;
    }
    if (!(target.width >= kMinTargetSide && target.height >= kMinTargetSide)) {
      error_ = "target too small: at least 0.5 % of the image on each side";
      return false;
    }
  }
  const int64_t seq = next_target_seq_++;
  TrackTarget sent = target;
  sent.vehicle_id = vehicle_id;
  sent.target_seq = seq;
  outgoing_.push_back(sent);
  v->track_target = sent;
  v->track.reset();  // until the vehicle answers this selection
  ++v->track_targets_sent;
  char buf[160];
  if (target.method == TrackTarget::kCancel)
    std::snprintf(buf, sizeof buf, "tracking cancelled");
  else
    std::snprintf(buf, sizeof buf, "target %lld sent (%s): x %.3f y %.3f w %.3f h %.3f", static_cast<long long>(seq),
                  target.method == TrackTarget::kFourClicks ? "four corners" : "drag", target.x, target.y,
                  target.width, target.height);
  log.Add(now, vehicle_id, buf, Severity::kInfo);
  return true;
}

}  // namespace uav::gcs
