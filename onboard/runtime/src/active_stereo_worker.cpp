#include "uav/runtime/active_stereo_worker.hpp"

#include <algorithm>

#include "uav/shared/frames.hpp"

namespace uav::runtime {

ActiveStereoWorkerParams ActiveStereoWorkerParams::FromParameters(const ParameterSet& p) {
  ActiveStereoWorkerParams a;
  a.enabled = p.Get("asv_enable") != 0.0;
  a.to_ins = p.Get("asv_to_ins") != 0.0;
  a.height_noise_m = p.Get("asv_height_noise");
  a.stereo.threshold_dn = p.Get("asv_threshold");
  a.stereo.min_points = static_cast<int>(p.Get("asv_min_points"));
  a.stereo.Validate();
  return a;
}

ActiveStereoWorker::ActiveStereoWorker(hal::StereoCamera& camera, Blackboard& board, const ActiveStereoWorkerParams& params)
    : VisionWorker(board),
      camera_(camera),
      params_(params),
      stereo_({camera.left().intrinsics, camera.right().intrinsics, camera.T_LR()}, params.stereo),
      preview_(camera.left().name, camera.left().preview_rate_hz) {}

void ActiveStereoWorker::Work(Outbox& out) {
  const int64_t utime = utime_;
  const BlackboardData& d = at_begin_;
  const hal::StereoImages pair = TimedCapture([&] { return camera_.Capture(utime, hal::Emitter::kOn); });
  if (pair.left.empty()) return;  // the camera's problem shows in the sensing health
  vision::ActiveStereoResult r = stereo_.Process(pair.left, pair.right, camera_.left().T_BC, RotationNBFromEuler(d.estimate.euler));
  ground_.Apply(&r, d.estimate.p_N.z(), utime);
  ActiveStereoReport report;
  report.utime = utime;
  report.camera = camera_.left().name;
  report.healthy = r.healthy;
  report.reason = r.reason;
  report.height_m = r.healthy ? r.height_m : 0.0;
  report.height_sigma_m = r.healthy ? r.height_sigma_m : 0.0;
  report.left_dots = r.left_dots;
  report.right_dots = r.right_dots;
  report.ambiguous = r.ambiguous;
  if (r.healthy) {
    const double w = std::max(1, pair.left.cols), h = std::max(1, pair.left.rows);
    for (const vision::LaserPoint& p : r.points) report.dots.push_back({p.left_px.x / w, p.left_px.y / h, p.down_m, p.cluster});
    report.clusters = r.clusters;
  }
  out.Post([report](Blackboard& b) { b.reports.Put(report); });
  if (r.healthy && params_.to_ins) {
    // Stamped with its capture time: the INS fuses it against where it was then.
    const BlackboardData::VisionHeight height{utime, r.height_m, std::max(r.height_sigma_m, params_.height_noise_m)};
    out.Post([height](Blackboard& b) { b.Update([&](BlackboardData& data) { data.vision_height = height; }); });
  }
  if (preview_.Due(utime)) out.Post([f = preview_.Encode(utime, pair.left)](Blackboard& b) { b.previews.Put(f.camera, f); });
  ++frames_;
  unhealthy_ += !r.healthy;
}

}  // namespace uav::runtime
