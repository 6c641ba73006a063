#pragma once
// A valid example of each report of the list (tests of the report seam).
#include <type_traits>

#include "uav/shared/reports.hpp"

namespace uav {

// A report with a time and, where the type has them, a health and a reason, as workers send.
template <class T>
T ExampleReport() {
  T r{};
  r.utime = 1'795'000'000'123'456;
  if constexpr (std::is_same_v<T, ActiveStereoReport> || std::is_same_v<T, DepthGrid> ||
                std::is_same_v<T, VisualOdometryReport>) {
    r.healthy = false;
    r.reason = "too few features";
  }
  if constexpr (std::is_same_v<T, DepthGrid>) {  // the grid a worker sends is never empty
    r.cols = 2, r.rows = 1;
    r.cells.resize(2);
    r.cells[0].reason = r.cells[1].reason = "no features";
    r.obstacle_depth_m = 8.0;
  }
  if constexpr (std::is_same_v<T, VisualOdometryReport>) {
    r.method = "pnp";
    r.disparity_offset_px = 0.25, r.disparity_offset_sigma_px = 0.01;
  }
  if constexpr (std::is_same_v<T, PreArmReport>)
    r.checks = {{"gps", false, "no 3-D fix (fix 0, 0 satellites)"}, {"battery", true, "100 % remaining"}};
  if constexpr (std::is_same_v<T, ParameterTable>) {
    r.version = 2;
    r.entries = {{"ctl_speed_max_xy", "m/s", "horizontal speed limit", 4.0, 5.0, 0.5, 15.0, ParamApply::kInFlight},
                 {"mass", "kg", "total platform mass", 1.37, 1.37, 0.1, 50.0, ParamApply::kAtStart}};
  }
  return r;
}

}  // namespace uav
