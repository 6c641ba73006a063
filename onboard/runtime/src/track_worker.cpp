#include "uav/runtime/track_worker.hpp"

#include "uav/runtime/mono_depth_worker.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "uav/shared/frames.hpp"

namespace uav::runtime {

TrackWorkerParams TrackWorkerParams::FromParameters(const ParameterSet& p) {
  TrackWorkerParams t;
  // trk_tracker's values are TrackerKind's (0 CamShift, 1 KCF, 2 CSRT, 3 auto, 4 dcf).
  t.tracker.kind = static_cast<vision::TrackerKind>(static_cast<int>(p.Get("trk_tracker")));
  t.tracker.window = p.Get("trk_window") != 0.0 ? vision::SearchWindowMode::kStatic : vision::SearchWindowMode::kAdaptive;
  t.tracker.Validate();
  t.gimbal_pitch_rad = p.Get("gimbal_pitch") * M_PI / 180.0;
  t.gimbal_gain = p.Get("trk_gimbal_gain");
  t.buffer_s = p.Get("trk_buffer_s");
  return t;
}

TrackWorker::TrackWorker(hal::GimbalCamera& camera, Blackboard& board, const TrackWorkerParams& params)
    : VisionWorker(board),
      camera_(camera),
      params_(params),
      preview_(camera.info().name, camera.info().preview_rate_hz),
      tracker_(params.tracker) {
  camera_.SetPitch(params.gimbal_pitch_rad);
  board_.Update([&](BlackboardData& b) { b.tracking_camera = camera_.info().name; });
}

void TrackWorker::Begin(int64_t utime) {
  VisionWorker::Begin(utime);
  for (TrackTarget& r : board_.track_requests.TakeAll()) requests_.push_back(std::move(r));
}

void TrackWorker::Work(Outbox& out) {
  const int64_t utime = utime_;
  const BlackboardData& d = at_begin_;
  hal::CameraFrame frame = TimedCapture([&] { return camera_.Capture(utime); });
  if (frame.image.empty()) return;  // the camera's problem shows in the sensing health; requests wait
  ++frames_;
  if (preview_.Due(utime)) out.Post([f = preview_.Encode(utime, frame.image)](Blackboard& b) { b.previews.Put(f.camera, f); });
  buffer_.push_back({utime, frame.image});
  if (EstimateMatchesFrame(d.estimate, utime))
    ShareFrame(out, d, camera_.info().name, utime, frame.image,
               hal::GimbalCameraPose(d.estimate.T_NB(), camera_.info().T_BC, camera_.pitch_rad()));
  else
    ShareFrame(out, d, camera_.info().name, utime, frame.image, std::nullopt);
  while (!buffer_.empty() && buffer_.front().utime < utime - static_cast<int64_t>(params_.buffer_s * 1e6)) buffer_.pop_front();

  bool started_now = false;
  const std::vector<TrackTarget> requests = std::move(requests_);
  requests_.clear();
  for (const TrackTarget& r : requests) started_now = Handle(r, out) || (started_now && tracker_.state() != vision::TrackState::kIdle);
  if (tracker_.state() == vision::TrackState::kIdle) {
    target_ = TrackedTarget{};
    out.Post([](Blackboard& b) { b.Update([](BlackboardData& data) { data.target = TrackedTarget{}; }); });
    return;
  }
  vision::TrackResult r;
  if (started_now) {
    r = last_result_;
  } else {
    r = tracker_.Update(frame.image, utime * 1e-6);
    last_result_ = r;
  }
  Report(utime, r, out);
  PlaceOnGround(utime, r, d.estimate, out);
}

TrackStatus TrackWorker::NewReport(int64_t utime, int64_t target_seq, TrackStatus::State state) const {
  TrackStatus rep;
  rep.utime = utime;
  rep.target_seq = target_seq;
  rep.camera = camera_.info().name;
  rep.tracker = vision::Name(tracker_.state() == vision::TrackState::kIdle ? params_.tracker.kind : tracker_.method());
  rep.state = state;
  return rep;
}

void TrackWorker::Reject(const TrackTarget& request, const std::string& reason, Outbox& out) {
  TrackStatus rep = NewReport(request.frame_utime, request.target_seq, TrackStatus::State::kRejected);
  rep.reason = reason;
  out.Post([rep](Blackboard& b) { b.track_reports.Push(rep); });
  out.PushStatus(Severity::kWarning, "target " + std::to_string(request.target_seq) + " rejected: " + reason);
}

bool TrackWorker::Handle(const TrackTarget& request, Outbox& out) {
  if (request.method == TrackTarget::Method::kCancel) {
    tracker_.Stop();
    target_seq_ = request.target_seq;
    out.Post([rep = NewReport(buffer_.back().utime, request.target_seq, TrackStatus::State::kIdle)](Blackboard& b) {
      b.track_reports.Push(rep);
    });
    out.PushStatus(Severity::kInfo, "tracking stopped");
    return false;
  }
  if (request.camera != camera_.info().name) {
    Reject(request, "picked in camera '" + request.camera + "', the tracker runs on '" + camera_.info().name + "'", out);
    return false;
  }
  // The frame it was picked in: the buffered one nearest its time, within half a frame period.
  const int64_t half_period = static_cast<int64_t>(0.5e6 / camera_.info().rate_hz);
  std::size_t k = buffer_.size();
  for (std::size_t i = 0; i < buffer_.size(); ++i)
    if (std::llabs(buffer_[i].utime - request.frame_utime) <= half_period) {
      k = i;
      break;
    }
  if (k == buffer_.size()) {
    char why[160];
    std::snprintf(why, sizeof why, "the frame it was picked in (%.1f s before the newest) is not among the %.1f s kept (trk_buffer_s): pick again",
                  (buffer_.back().utime - request.frame_utime) * 1e-6, params_.buffer_s);
    Reject(request, why, out);
    return false;
  }
  const cv::Mat& image = buffer_[k].image;
  const double W = image.cols, H = image.rows;
  const cv::Rect2d box(request.x * W, request.y * H, request.width * W, request.height * H);
  std::vector<cv::Point2f> polygon;
  if (request.method == TrackTarget::Method::kFourClicks)
    for (const Eigen::Vector2d& c : request.corners) polygon.emplace_back(static_cast<float>(c.x() * W), static_cast<float>(c.y() * H));
  vision::TargetTracker fresh(params_.tracker);
  try {
    fresh.Start(image, buffer_[k].utime * 1e-6, box, polygon);
  } catch (const std::invalid_argument& e) {
    Reject(request, e.what(), out);  // the target tracked before (if any) carries on
    return false;
  }
  // Catch up from the picked frame to now.
  vision::TrackResult r;
  r.state = vision::TrackState::kTracking;
  r.confidence = 1.0;
  r.box = cv::RotatedRect(cv::Point2f(static_cast<float>(box.x + 0.5 * box.width), static_cast<float>(box.y + 0.5 * box.height)),
                          cv::Size2f(static_cast<float>(box.width), static_cast<float>(box.height)), 0.0f);
  r.search_window = box;
  for (std::size_t i = k + 1; i < buffer_.size(); ++i) r = fresh.Update(buffer_[i].image, buffer_[i].utime * 1e-6);
  tracker_ = std::move(fresh);
  last_result_ = r;
  target_seq_ = request.target_seq;
  const std::string how = tracker_.method_reason().empty() ? "" : ": " + tracker_.method_reason();
  out.PushStatus(Severity::kInfo, "tracking target " + std::to_string(request.target_seq) + " (" +
                                     vision::Name(tracker_.method()) + how + ")");
  return true;
}

void TrackWorker::Report(int64_t utime, const vision::TrackResult& r, Outbox& out) {
  const double W = camera_.info().intrinsics.width, H = camera_.info().intrinsics.height;
  TrackStatus rep = NewReport(utime, target_seq_,
                              r.state == vision::TrackState::kTracking ? TrackStatus::State::kTracking
                              : r.state == vision::TrackState::kLost   ? TrackStatus::State::kLost
                                                                       : TrackStatus::State::kIdle);
  rep.center_x = r.box.center.x / W;
  rep.center_y = r.box.center.y / H;
  rep.width = r.box.size.width / W;
  rep.height = r.box.size.height / H;
  rep.angle_rad = r.box.angle * M_PI / 180.0;
  rep.window_x = r.search_window.x / W;
  rep.window_y = r.search_window.y / H;
  rep.window_width = r.search_window.width / W;
  rep.window_height = r.search_window.height / H;
  rep.confidence = r.confidence;
  if (r.state == vision::TrackState::kLost) rep.reason = r.lost_reason;
  out.Post([rep](Blackboard& b) { b.track_reports.Push(rep); });
}

void TrackWorker::PlaceOnGround(int64_t utime, const vision::TrackResult& r, const hal::VehicleEstimate& estimate,
                                Outbox& out) {
  // Lost: where it was last seen stays (follow holds on it).
  TrackedTarget t = target_;
  t.locked = r.state == vision::TrackState::kTracking;
  t.utime = utime;
  const CameraIntrinsics& k = camera_.info().intrinsics;
  t.image_x = r.box.center.x / k.width;
  t.image_y = r.box.center.y / k.height;
  t.gimbal_pitch_rad = camera_.pitch_rad();
  if (t.locked) {
    t.last_seen_utime = utime;
    const Eigen::Isometry3d T_NC = hal::GimbalCameraPose(estimate.T_NB(), camera_.info().T_BC, camera_.pitch_rad());
    const Eigen::Vector3d ray_N = T_NC.linear() * Unproject(k, Eigen::Vector2d(r.box.center.x, r.box.center.y)).homogeneous();
    t.bearing_rad = std::atan2(ray_N.y(), ray_N.x());
    // The ground is d = 0 in the home frame (flat ground assumed).
    const double s = ray_N.z() > 1e-3 ? -T_NC.translation().z() / ray_N.z() : -1.0;
    t.on_ground = s > 0;
    if (t.on_ground) t.p_N = T_NC.translation() + s * ray_N;
    // Gimbal: turn part of the way to the box centre's elevation each frame, so the target
    // sits mid-image (a target below the centre needs the camera pitched further down).
    if (params_.gimbal_gain > 0) {
      const double offset = std::atan2(r.box.center.y - k.cy, k.fy);
      camera_.SetPitch(camera_.pitch_rad() - params_.gimbal_gain * offset);
    }
  }
  target_ = t;
  out.Post([t](Blackboard& b) { b.Update([&](BlackboardData& data) { data.target = t; }); });
}

}  // namespace uav::runtime
