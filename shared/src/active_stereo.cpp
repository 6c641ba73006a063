#include "uav/shared/active_stereo.hpp"

namespace uav {

// Active stereo: the height over the ground cluster (0 while there is none), its standard
// error, and the dot counts behind it.
const std::vector<Signal<ActiveStereoReport>>& ReportSignals<ActiveStereoReport>::Table() {
  using F = SignalFormat;
  using R = ActiveStereoReport;
  static const std::vector<Signal<R>> k = {
      {{"height", "height_m", "m", "over the ground, 0 none", F::kMetres}, [](const R& r) { return r.height_m; }},
      {{"height_sigma", "height_sigma_m", "m", "", F::kMetres}, [](const R& r) { return r.height_sigma_m; }},
      {{"points", "points", "1", "", F::kInteger}, [](const R& r) { return double(r.dots.size()); }},
      {{"left_dots", "left_dots", "1", "", F::kInteger}, [](const R& r) { return double(r.left_dots); }},
      {{"right_dots", "right_dots", "1", "", F::kInteger}, [](const R& r) { return double(r.right_dots); }},
      {{"ambiguous", "ambiguous", "1", "", F::kInteger}, [](const R& r) { return double(r.ambiguous); }},
      {{"clusters", "clusters", "1", "", F::kInteger}, [](const R& r) { return double(r.clusters.size()); }},
  };
  return k;
}

}  // namespace uav
