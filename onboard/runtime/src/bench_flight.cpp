#include "uav/runtime/bench_flight.hpp"

#include <algorithm>

#include "uav/shared/frames.hpp"
#include "uav/shared/pre_arm.hpp"

namespace uav::runtime {

BenchFlight::BenchFlight(const ParameterSet& params, const RigFile& rig, const Options& o)
    : rig_(rig),
      options_(o),
      scheduler_({o.start_utime, kStepUs, o.speed,
                  o.duration_s > 0          ? static_cast<int64_t>(o.duration_s * 1e6)
                  : rig.end_utime() >= 0    ? rig.end_utime() - o.start_utime
                                            : 0}) {
  Sensing::Options so{o.log_dir, o.start_utime, o.home, o.speed == 1.0};
  // The odometry is gyro-aided where the bench has an IMU's attitude, as in flight (not from the
  // truth: that would be aiding it with the answer).
  so.imu = rig.pose_source() == RigFile::PoseSource::kImuOdometry;
  sensing_ = std::make_unique<Sensing>(rig.rig(), params, board_, so);
  scheduler_.AddWorker("POSE", 0, kPeriodUs, [this](int64_t t) { Tick(t); });
  sensing_->AddTo(scheduler_, kStepUs);
  board_.PushStatus(Severity::kWarning, std::string(kControlOff) + "; " + PoseDescription());
}

std::string BenchFlight::PoseDescription() const {
  switch (rig_.pose_source()) {
    case RigFile::PoseSource::kTruth: return "pose from the recorded ground truth";
    case RigFile::PoseSource::kImuOdometry: return "attitude from the recorded IMU, position from the visual odometry";
    case RigFile::PoseSource::kOdometry: return "pose from the visual odometry";
    case RigFile::PoseSource::kFixed: break;
  }
  return "pose fixed at home";
}

void BenchFlight::Tick(int64_t utime) {
  const BlackboardData d = board_.Snapshot();
  // Where the vehicle is: the recording's truth at this time, the odometry's newest position
  // (held between its frames), or home.
  Eigen::Isometry3d T_NB = Eigen::Isometry3d::Identity();
  const RigFile::PoseSource source = rig_.pose_source();
  if (source == RigFile::PoseSource::kTruth) {
    T_NB = rig_.TruthAt(utime);
  } else if (source == RigFile::PoseSource::kImuOdometry || source == RigFile::PoseSource::kOdometry) {
    if (d.vision_position && d.vision_position->utime != vision_utime_) {
      vision_utime_ = d.vision_position->utime;
      p_N_vision_ = d.vision_position->p_N;
    }
    T_NB.translation() = p_N_vision_;
  }
  if (const std::vector<ImuSample>* imu = rig_.imu()) {
    // Every recorded sample up to now, in order.
    const int64_t until = utime + rig_.imu_offset_us();
    for (; imu_next_ < imu->size() && (*imu)[imu_next_].t_us <= until; ++imu_next_)
      imu_attitude_.Update((*imu)[imu_next_].t_us, (*imu)[imu_next_].gyro_B, (*imu)[imu_next_].accel_B);
    T_NB.linear() = imu_attitude_.q_NB().toRotationMatrix();
  }
  hal::VehicleEstimate est;
  // Without an attitude yet (the IMU still levelling) the estimate is not aligned (utime 0), and
  // the odometry takes no rotation from it.
  est.utime = rig_.imu() && !imu_attitude_.aligned() ? 0 : utime;
  if (rig_.imu()) est.attitude_covariance_B = imu_attitude_.Covariance();
  est.p_N = est.p_O = T_NB.translation();
  est.q_NB = Eigen::Quaterniond(T_NB.linear());
  est.euler = EulerFromRotationNB(T_NB.linear());
  if (last_T_NB_ && utime > last_utime_)
    est.v_N = (T_NB.translation() - last_T_NB_->translation()) / ((utime - last_utime_) * 1e-6);
  last_T_NB_ = T_NB;
  last_utime_ = utime;
  // Commands: none moves a vehicle without actuators. Each is answered, so the GCS is not left
  // waiting (target selection goes to the tracker by its own path).
  std::vector<CommandAck> acks;
  for (const auto& req : board_.commands.TakeAll())
    acks.push_back({req.source, req.seq, req.command.Name(), CommandResult::kRejected, 0, kControlOff});
  board_.task_reports.PushAll(acks);
  board_.Update([&](BlackboardData& b) {
    b.estimate = est;
    b.ground_state = control::GroundState::kOnGround;
    b.armed = b.airborne = false;
    b.position_source = source == RigFile::PoseSource::kOdometry || source == RigFile::PoseSource::kImuOdometry
                            ? PositionSource::kVision
                            : PositionSource::kGps;
  });
  // The pre-arm report, once a second, says why this vehicle cannot arm.
  if (last_prearm_utime_ < 0 || utime - last_prearm_utime_ >= 1'000'000) {
    last_prearm_utime_ = utime;
    PreArmReport report;
    report.utime = utime;
    report.checks = {{"bench", false, kControlOff}};
    board_.reports.Put(std::move(report));
  }
}

}  // namespace uav::runtime
