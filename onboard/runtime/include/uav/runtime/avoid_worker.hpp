#pragma once
// AVD: obstacle avoidance's planning thread (thesis 7.2), off the control path like the vision
// workers: at avd_rate it fuses the perception results that have become visible into the 3-D
// map (each at its capture pose) and plans from the vehicle to the active task's goal; the plan
// reaches CTL's safety layer avd_latency later (measured at real time). At each landing the map
// is saved as an OctoMap file beside the flight log.
#include <string>
#include <vector>

#include "uav/runtime/vision_worker.hpp"
#include "uav/avoid/avoidance.hpp"

namespace uav::runtime {

class AvoidWorker : public VisionWorker {
 public:
  // `map_path`: where the map is written at landing and at exit ("" : not written).
  AvoidWorker(Blackboard& board, const avoid::AvoidanceParams& params, std::string map_path);
  ~AvoidWorker() override;
  void Begin(int64_t utime) override;
  void ApplyParameters(const ParameterSet& params) override;  // the avoidance planner's avd_*, obs_margin
  const avoid::AvoidanceParams& params() const { return planner_.params(); }
  void Work(Outbox& out) override;
  const avoid::OccupancyMap& map() const { return planner_.map(); }

 private:
  void Save(Outbox* out);
  // The plan and the map around the vehicle for the GCS (avoidance_t), at kReportPeriod.
  void Report(const avoid::AvoidancePlan& plan, const hal::VehicleEstimate& estimate, Outbox& out);

  avoid::AvoidancePlanner planner_;
  std::string map_path_;
  std::vector<avoid::PerceptionUpdate> updates_;  // taken at Begin
  bool was_airborne_ = false;
  bool saved_since_landing_ = true;
  int64_t last_report_utime_ = -1;
};

}  // namespace uav::runtime
