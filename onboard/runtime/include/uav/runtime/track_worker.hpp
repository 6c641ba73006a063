#pragma once
// TRK: the gimballed camera on the vehicle clock and the operator's target (thesis 3.7). A thin
// shell around hal::GimbalCamera and vision::TargetTracker: takes a frame at the camera rate,
// keeps the last seconds of frames keyed by time (a target is picked on a frozen frame the GCS
// saw a moment ago), starts the tracker on the frame the target was picked in and catches up to
// now, then tracks every frame. It reports track_status_t every frame while a target is set,
// answers each selection (a refusal names why), pitches the gimbal to keep the target centred
// while it tracks, and posts the target's place on the ground (navigation estimate, never the
// truth) for follow. Streams the camera's preview to the GCS.
#include <deque>
#include <string>

#include <opencv2/core/mat.hpp>

#include "uav/runtime/vision_worker.hpp"
#include "uav/runtime/preview_stream.hpp"
#include "uav/hal/camera.hpp"
#include "uav/shared/parameters.hpp"
#include "uav/vision/target_tracker.hpp"

namespace uav::runtime {

struct TrackWorkerParams {
  vision::TrackerParams tracker;  // trk_tracker, trk_window
  double gimbal_pitch_rad = -0.35;  // gimbal_pitch: where the gimbal points before a target is locked
  double gimbal_gain = 0.5;         // trk_gimbal_gain: fraction of the vertical offset corrected per frame (0: fixed)
  double buffer_s = 10.0;           // trk_buffer_s: frames kept for selections picked on older frames
  static TrackWorkerParams FromParameters(const ParameterSet& p);
};

class TrackWorker : public VisionWorker {
 public:
  TrackWorker(hal::GimbalCamera& camera, Blackboard& board, const TrackWorkerParams& params);
  void Begin(int64_t utime) override;
  void Work(Outbox& out) override;
  int frames() const { return frames_; }

 private:
  struct Buffered {
    int64_t utime;
    cv::Mat image;
  };
  // Returns true when a new target was started (and caught up to the newest frame).
  bool Handle(const TrackTarget& request, Outbox& out);
  void Reject(const TrackTarget& request, const std::string& reason, Outbox& out);
  TrackStatus NewReport(int64_t utime, int64_t target_seq, TrackStatus::State state) const;
  void Report(int64_t utime, const vision::TrackResult& r, Outbox& out);
  void PlaceOnGround(int64_t utime, const vision::TrackResult& r, const hal::VehicleEstimate& estimate, Outbox& out);

  hal::GimbalCamera& camera_;
  std::vector<TrackTarget> requests_;  // taken at Begin
  TrackWorkerParams params_;
  PreviewStream preview_;
  vision::TargetTracker tracker_;
  vision::TrackResult last_result_;  // of the newest frame tracked
  std::deque<Buffered> buffer_;
  int64_t target_seq_ = 0;
  TrackedTarget target_;  // what was last posted for follow
  int frames_ = 0;
};

}  // namespace uav::runtime
