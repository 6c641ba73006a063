#include "uav/simflight/sim_flight.hpp"

#include <limits>

#include "uav/runtime/mission_store.hpp"
#include "uav/world/scene.hpp"

namespace uav::simflight {

SimFlight::SimFlight(const ParameterSet& params, const Options& o)
    : options_(o),
      vehicle_(sim::MakeSimulatedVehicle(params, o.home, o.start_utime)),
      imu_(*vehicle_, board_, nav::InsParams::FromParameters(params), o.home, control::LandDetectorParams::FromParameters(params)),
      ctl_(control::TaskParams::FromParameters(params), control::ControllerParams::FromParameters(params),
           control::FailsafeParams::FromParameters(params), kPeriodUs * 1e-6, board_, o.missions,
           avoid::AvoidanceParams::FromParameters(params), control::PreArmParams::FromParameters(params)),
      svo_(*vehicle_, board_, params.Get("rotor_input_idle"), hal::VehicleParams::FromParameters(params).attitude_mode),
      scheduler_({o.start_utime, kStepUs, o.speed, static_cast<int64_t>(o.duration_s * 1e6)}) {
  if (params.Get("vehicle_type") == static_cast<double>(VehicleType::kTailSitter))
    ctl_.UseTailSitter(control::TailSitterControlParams::FromParameters(params));
  if (o.scene) {
    rig_ = std::make_unique<SimRig>(*o.scene, params);
    rig_->RecordTruth(o.start_utime, TruthPose());
    // At real time the vision results are as late as their work takes; on a simulated clock
    // the vehicle file's latencies keep a run repeatable.
    sensing_ = std::make_unique<runtime::Sensing>(rig_->rig(), params, board_,
                                                  runtime::Sensing::Options{o.log_dir, o.start_utime, o.home, o.speed == 1.0});
  }
  // The simulator's faults, commanded like everything else ("gps 0"); applied at the next step.
  ctl_.SetFaultInjector([this](const Command& c) -> std::string {
    if (c.id != CommandId::kGps) return "the simulator has no fault '" + c.Name() + "'";
    gps_wanted_.store(c.args[0] != 0);
    return "";
  });
  scheduler_.AddWorker("IMU", 0, kPeriodUs, [this](int64_t t) { imu_.Tick(t); });
  scheduler_.AddWorker("CTL", 1, kPeriodUs, [this](int64_t t) { ctl_.Tick(t); });
  scheduler_.AddWorker("SVO", 2, kPeriodUs, [this](int64_t t) { svo_.Tick(t); });
  if (sensing_) sensing_->AddTo(scheduler_, kStepUs);
  // Indoors (a scene without sky) the receiver never has a fix, whatever "gps 1" asks.
  sky_view_ = !o.scene || o.scene->sky();
  gps_enabled_ = sky_view_;
  vehicle_->SetGpsEnabled(gps_enabled_);
  if (!sky_view_) board_.PushStatus(Severity::kWarning, "simulator: indoors, no GPS fix");
}

SimFlight::~SimFlight() = default;

Eigen::Isometry3d SimFlight::TruthPose() const {
  const sim::BodyTruth s = vehicle_->Truth();
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = s.q_NB.toRotationMatrix();
  T.translation() = s.p_N;
  return T;
}

void SimFlight::Run(const std::function<void(int64_t)>& each_period) {
  const int64_t start = options_.start_utime;
  scheduler_.Run([&](int64_t dt) {
    // The simulator's faults, commanded like everything else ("gps 0").
    if (const bool want = gps_wanted_.load() && sky_view_; want != gps_enabled_) {
      vehicle_->SetGpsEnabled(want);
      gps_enabled_ = want;
      board_.PushStatus(want ? Severity::kInfo : Severity::kWarning, want ? "simulator: GPS fix restored" : "simulator: GPS fix lost");
    }
    vehicle_->Step(dt);
    const int64_t now = scheduler_.now() + dt;
    const bool period = (now - start) % kPeriodUs == 0;
    if (options_.scene && period) {
      // The true clearance for the flight log (the flight stack never reads it).
      clearance_m_.store(options_.scene->Clearance(vehicle_->Truth().p_N, now * 1e-6));
    }
    // The state after the step is the truth at the next tick, recorded before any camera asks.
    if (rig_) rig_->RecordTruth(now, TruthPose());
    if (sensing_) sensing_->Monitor(scheduler_.now(), scheduler_);
    if (period && each_period) each_period(now);
  });
}

std::vector<runtime::LogColumn> SimFlight::LogColumns() const {
  return {{"clearance_m", [this] {
             const double c = clearance_m_.load();
             return c >= 0 ? c : std::numeric_limits<double>::quiet_NaN();
           }}};
}

}  // namespace uav::simflight
