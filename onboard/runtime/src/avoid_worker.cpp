#include "uav/runtime/avoid_worker.hpp"

namespace uav::runtime {

namespace {
// The GCS's picture of the plan and the map: 2 Hz is what an operator follows, and a report of
// the whole window (up to avoidance_t.MAX_CELLS cells) stays under 80 kB.
constexpr int64_t kReportPeriodUs = 500'000;
}  // namespace

AvoidWorker::AvoidWorker(Blackboard& board, const avoid::AvoidanceParams& params, std::string map_path)
    : VisionWorker(board), planner_(params), map_path_(std::move(map_path)) {}

AvoidWorker::~AvoidWorker() {
  if (!saved_since_landing_) Save(nullptr);
}

void AvoidWorker::Begin(int64_t utime) {
  VisionWorker::Begin(utime);
  // Taken on the clock's thread: which results a plan includes is the same in every run.
  updates_ = board_.perception.TakeAll();
}

void AvoidWorker::ApplyParameters(const ParameterSet& params) {
  // Settings changed over the link (the control thread checked them before accepting).
  planner_.SetParams(avoid::AvoidanceParams::FromParameters(params));
}

void AvoidWorker::Save(Outbox* out) {
  saved_since_landing_ = true;
  if (map_path_.empty()) return;
  const std::string error = planner_.map().SaveBinary(map_path_);
  if (out) {
    if (error.empty()) out->PushStatus(Severity::kInfo, "obstacle map saved: " + map_path_);
    else out->PushStatus(Severity::kWarning, "obstacle map not saved: " + error);
  }
}

void AvoidWorker::Work(Outbox& out) {
  const BlackboardData& d = at_begin_;
  // The map and the planning are in the odometry frame O (VehicleEstimate::p_O): the results
  // arrive in it; the task's goal and the plan cross between N and O here.
  const Eigen::Vector3d p_NO = d.estimate.p_NO();
  for (const avoid::PerceptionUpdate& u : updates_) {
    const std::string said = planner_.Add(u, d.estimate.p_O);
    if (!said.empty()) out.PushStatus(Severity::kWarning, said);
  }
  updates_.clear();
  if (d.airborne) saved_since_landing_ = false;
  if (was_airborne_ && !d.airborne) Save(&out);
  was_airborne_ = d.airborne;
  if (!d.avoid_request.active) {
    planner_.Reset();
    return;
  }
  const avoid::AvoidancePlan plan_O = planner_.Plan(utime_, d.estimate.p_O, d.avoid_request.via_N - p_NO,
                                                    d.avoid_request.goal_N - p_NO, d.avoid_request.map_only, d.estimate.v_N);
  auto plan = std::make_shared<const avoid::AvoidancePlan>(avoid::Translated(plan_O, p_NO));
  out.Post([plan](Blackboard& b) { b.Update([&](BlackboardData& data) { data.avoid_plan = plan; }); });
  Report(*plan, d.estimate, out);
}

void AvoidWorker::Report(const avoid::AvoidancePlan& plan, const hal::VehicleEstimate& estimate, Outbox& out) {
  if (last_report_utime_ >= 0 && utime_ - last_report_utime_ < kReportPeriodUs) return;
  last_report_utime_ = utime_;
  AvoidanceReport r;
  r.utime = plan.utime;
  r.state = plan.state;
  r.reason = plan.reason;
  r.goal_N = plan.goal_N;
  r.path_N = plan.path_N;
  r.seen_free_m = plan.seen_free_m;
  r.planning_ms = plan.planning_ms;
  r.map_cells = static_cast<int64_t>(plan.map_cells);
  r.origin_N = estimate.p_N;
  r.cell_m = planner_.grid_m();
  const avoid::AvoidanceParams& p = planner_.params();
  r.occupied_N = planner_.OccupiedAround(estimate.p_O, Eigen::Vector3d(p.window_m, p.window_m, p.window_up_m));
  const Eigen::Vector3f p_NO = estimate.p_NO().cast<float>();
  for (Eigen::Vector3f& c : r.occupied_N) c += p_NO;
  out.Post([r = std::move(r)](Blackboard& b) { b.reports.Put(r); });
}

}  // namespace uav::runtime
