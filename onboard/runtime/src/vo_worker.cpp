#include "uav/runtime/vo_worker.hpp"

#include <algorithm>
#include <filesystem>
#include <regex>
#include <stdexcept>
#include <vector>

#include <opencv2/imgproc.hpp>

#include "uav/shared/frames.hpp"

namespace uav::runtime {

VoWorkerParams VoWorkerParams::FromParameters(const ParameterSet& p) {
  VoWorkerParams v;
  v.enabled = p.Get("vo_enable") != 0.0;
  v.position_noise_m = p.Get("vo_position_noise");
  const int method = static_cast<int>(p.Get("vo_method"));
  v.vo.method = method == 1 ? vision::VoMethod::kEpnp : method == 2 ? vision::VoMethod::kRigid : vision::VoMethod::kPnp;
  v.vo.max_features = static_cast<int>(p.Get("vo_max_features"));
  v.vo.disparity_offset_prior_sigma_px = p.Get("vo_offset_prior");
  v.vo.Validate();
  return v;
}

VoWorker::VoWorker(hal::StereoCamera& camera, Blackboard& board, const VoWorkerParams& params)
    : VisionWorker(board),
      camera_(camera),
      params_(params),
      rectifier_({camera.left().intrinsics, camera.right().intrinsics, camera.T_LR()}),
      vo_(rectifier_.geometry(), params.vo),
      preview_(camera.left().name, camera.left().preview_rate_hz) {
  T_BC_ = camera.left().T_BC;
  T_BC_.linear() = T_BC_.linear() * rectifier_.geometry().R_L_rect;
  std::error_code ec;
  if (!params.poses_path.empty()) std::filesystem::create_directories(std::filesystem::path(params.poses_path).parent_path(), ec);
  if (!params.poses_path.empty() && !(poses_ = std::fopen(params.poses_path.c_str(), "w")))
    throw std::runtime_error("cannot write the odometry's poses to '" + params.poses_path + "'");
}

VoWorker::~VoWorker() {
  if (poses_) std::fclose(poses_);
}

void VoWorker::Work(Outbox& out) {
  const int64_t utime = utime_;
  const BlackboardData& d = at_begin_;
  const hal::StereoImages pair = TimedCapture([&] { return camera_.Capture(utime, hal::Emitter::kOff); });
  vision::RectifiedPair rect;
  rect.left_utime = pair.left_utime;
  rect.right_utime = pair.right_utime;
  // The INS's attitude of the rectified left camera and its covariance there: the odometry
  // weighs its rotation against the IMU's (gyro-aided; see RectifiedPair::R_XC).
  if (params_.gyro_aided && d.estimate.utime > 0) {  // aligned
    const Eigen::Matrix3d R_BC = T_BC_.linear();
    rect.R_XC = d.estimate.q_NB.toRotationMatrix() * R_BC;
    rect.R_XC_covariance = R_BC.transpose() * d.estimate.attitude_covariance_B * R_BC;
  }
  vision::VoResult r;
  try {
    if (pair.left.empty() && !camera_.problem().empty()) throw std::runtime_error("camera: " + camera_.problem());
    rectifier_.Rectify(pair.left, pair.right, &rect.left, &rect.right);
    r = vo_.Process(rect);
  } catch (const std::exception& e) {  // no pair, or one of the wrong size or type: the pose holds
    r.healthy = false;
    r.reason = e.what();
    r.T_WC = last_T_WC_;
  }
  last_T_WC_ = r.T_WC;
  VisualOdometryReport report;
  report.utime = utime;
  report.healthy = r.healthy;
  report.reason = r.reason;
  report.method = vision::Name(params_.vo.method);
  report.segment = r.segment;
  report.keyframe_points = r.keyframe_points;
  report.tracked = r.tracked;
  report.inliers = r.inliers;
  report.rms_px = r.rms_px;
  report.disparity_offset_px = r.disparity_offset_px;
  report.disparity_offset_sigma_px = r.disparity_offset_sigma_px;
  if (pair.truth_T_NB) report.truth_N = pair.truth_T_NB->translation();
  std::optional<BlackboardData::VisionPosition> position;
  if (r.healthy) {
    // The segment's frame W in N: where the INS puts this camera now (Eq. 5.49-5.50 with R_NB
    // from the INS), so that odometry and INS agree when the segment starts.
    if (!T_NW_ || T_NW_->first != r.segment) T_NW_ = std::make_pair(r.segment, d.estimate.T_NB() * T_BC_ * r.T_WC.inverse());
    const Eigen::Isometry3d T_NB_vo = T_NW_->second * r.T_WC * T_BC_.inverse();
    position = BlackboardData::VisionPosition{utime, T_NB_vo.translation(), params_.position_noise_m, r.segment};
  }
  // The position is stamped with its capture time: the INS fuses it against where it was then.
  out.Post([reason = r.reason, position, report = std::move(report)](Blackboard& b) {
    VisualOdometryReport sent = report;
    b.Update([&](BlackboardData& data) {
      data.vision_unhealthy_reason = reason;
      if (position) data.vision_position = position;
      // With the VO+IMU filter's track and where the INS takes its position from now.
      sent.track_N = data.vo_track_N;
      sent.source = data.position_source;
    });
    b.reports.Put(std::move(sent));
  });
  if (params_.stream_video && !pair.left.empty() && preview_.Due(utime))
    out.Post([f = preview_.Encode(utime, pair.left)](Blackboard& b) { b.previews.Put(f.camera, f); });
  if (poses_) {
    // One line per pair, as uav-vo writes them: the rectified left camera in its segment's first
    // frame (an unhealthy pair holds the last pose).
    const Eigen::Matrix<double, 3, 4> P = r.T_WC.matrix().topRows<3>();
    for (int i = 0; i < 12; ++i) std::fprintf(poses_, i ? " %.9e" : "%.9e", P(i / 4, i % 4));
    std::fputc('\n', poses_);
    std::fflush(poses_);
  }
  ++frames_;
  unhealthy_ += !r.healthy;
  if (!r.healthy) ++reasons_[std::regex_replace(r.reason, std::regex("[0-9]+(\\.[0-9]+)?"), "#")];
}

std::string VoWorker::UnhealthySummary(int top) const {
  std::vector<std::pair<int, std::string>> by_count;
  for (const auto& [reason, n] : reasons_) by_count.emplace_back(n, reason);
  std::sort(by_count.rbegin(), by_count.rend());
  std::string out;
  for (int i = 0; i < top && i < static_cast<int>(by_count.size()); ++i)
    out += (i ? "; " : "") + std::to_string(by_count[i].first) + " x " + by_count[i].second;
  return out;
}

}  // namespace uav::runtime
