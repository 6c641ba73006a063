#include "uav/runtime/mono_depth_worker.hpp"

#include <cstdlib>

#include <opencv2/core/mat.hpp>

#include "uav/avoid/depth_grid_scan.hpp"

namespace uav::runtime {

bool EstimateMatchesFrame(const hal::VehicleEstimate& estimate, int64_t frame_utime) {
  constexpr int64_t kMatchUs = 20000;  // one control period
  return estimate.utime > 0 && std::llabs(estimate.utime - frame_utime) <= kMatchUs;
}

void ShareFrame(Outbox& out, const BlackboardData& d, const std::string& camera, int64_t utime, const cv::Mat& image,
                const std::optional<Eigen::Isometry3d>& T_NC_estimate) {
  if (d.depth_camera != camera || image.empty()) return;
  SharedFrame f;
  f.utime = utime;
  f.camera = camera;
  f.width = image.cols;
  f.height = image.rows;
  const cv::Mat bgr = image.isContinuous() ? image : image.clone();
  f.bgr.assign(bgr.data, bgr.data + bgr.total() * bgr.elemSize());
  if (T_NC_estimate) {
    f.T_OC_estimate = *T_NC_estimate;
    f.T_OC_estimate->translation() -= d.estimate.p_NO();
    f.v_N_estimate = d.estimate.v_N;
  }
  out.Post([f = std::move(f)](Blackboard& b) { b.frame.Put(f); });
}

MonoDepthWorkerParams MonoDepthWorkerParams::FromParameters(const ParameterSet& p) {
  MonoDepthWorkerParams m;
  m.camera = static_cast<int>(p.Get("mdp_camera"));
  m.estimator.obstacle_depth_m = p.Get("mdp_obstacle_depth");
  m.estimator.max_features = static_cast<int>(p.Get("mdp_max_features"));
  m.estimator.Validate();
  m.to_map = p.Get("avd_enable") != 0.0;
  return m;
}

MonoDepthWorker::MonoDepthWorker(const hal::CameraInfo& camera, Blackboard& board, const vision::MonoDepthParams& params,
                                 bool to_map)
    : VisionWorker(board),
      camera_(camera.name),
      intrinsics_(camera.intrinsics),
      to_map_(to_map),
      rate_hz_(camera.rate_hz),
      estimator_(camera.intrinsics, params) {
  board_.Update([&](BlackboardData& b) { b.depth_camera = camera_; });
}

void MonoDepthWorker::Begin(int64_t) { frame_ = board_.frame.Take(); }

void MonoDepthWorker::Work(Outbox& out) {
  const std::optional<SharedFrame> f = std::move(frame_);
  frame_.reset();
  if (!f || f->camera != camera_) return;
  const cv::Mat image(f->height, f->width, CV_8UC3, const_cast<uint8_t*>(f->bgr.data()));
  DepthGrid g = estimator_.Update(image, f->utime, f->T_OC_estimate, f->v_N_estimate);
  g.camera = camera_;
  ++frames_;
  if (to_map_ && g.healthy && f->T_OC_estimate) {
    avoid::PerceptionUpdate u;
    u.utime = f->utime;
    u.watches_ahead = false;
    u.scan = avoid::DepthGridScan(g, intrinsics_, *f->T_OC_estimate);
    if (!u.scan->p_N.empty()) out.Post([u = std::move(u)](Blackboard& b) { b.perception.Push(u); });
  }
  out.Post([g = std::move(g)](Blackboard& b) { b.reports.Put(g); });
}

}  // namespace uav::runtime
