#pragma once
// The reports the vehicle publishes (its perception, its sensing health, its pre-arm checks, its
// parameter table),
// listed once. The vehicle's blackboard slots and
// outbound translators, the GCS's decoders (and so the log replay), the fuzz target's topics and
// its seeds all follow from this list; uav/wire/reports.hpp gives each its message and topic.
// Each report's signals (ReportSignals<T>, uav/shared/signals.hpp) are declared beside its
// struct: the GCS's telemetry groups and the vehicle's flight-log columns follow from them.
// Adding a report: its plain struct here in uav/shared, its LCM type and conversions in the wire
// (docs/developer/adding.md).
#include <cstddef>
#include <type_traits>

#include "uav/shared/active_stereo.hpp"
#include "uav/shared/avoidance_report.hpp"
#include "uav/shared/mono_depth.hpp"
#include "uav/shared/obstacles.hpp"
#include "uav/shared/parameter_table.hpp"
#include "uav/shared/power_lines.hpp"
#include "uav/shared/pre_arm.hpp"
#include "uav/shared/sensing.hpp"
#include "uav/shared/visual_odometry.hpp"

namespace uav {

template <class... Ts>
struct TypeList {
  static constexpr std::size_t kSize = sizeof...(Ts);
};

using VehicleReports =
    TypeList<PowerLines, Obstacles, PointCloud, DepthGrid, ActiveStereoReport, VisualOdometryReport, SensingReport,
             PreArmReport, ParameterTable, AvoidanceReport>;

// The position of T in a TypeList (a compile error when it is not in it).
template <class T, class... Ts>
constexpr std::size_t IndexOf(TypeList<Ts...>) {
  constexpr bool kIs[] = {std::is_same_v<T, Ts>...};
  for (std::size_t i = 0; i < sizeof...(Ts); ++i)
    if (kIs[i]) return i;
  throw "not in the list";
}

// Calls f(static_cast<T*>(nullptr)) for each type T of the list, in order.
template <class... Ts, class F>
void ForEachType(TypeList<Ts...>, F&& f) {
  (f(static_cast<Ts*>(nullptr)), ...);
}

}  // namespace uav
