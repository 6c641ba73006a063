// Active stereo (thesis ch. 4) over the video.
#include <cstdio>

#include "overlays.hpp"

namespace uav::gcs {

void DrawActiveStereoOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed,
                             const ImageCanvas& c, double now) {
  // Each triangulated laser dot, green on the ground cluster the height is measured to, orange on
  // a nearer cluster (a table, a wall, a ledge), and the height.
  const ActiveStereoReport* as = v.ActiveStereoOver(feed, now, model.obstacles().params());
  if (!as) return;
  for (const LaserDotReport& d : as->dots) {
    const bool ground = d.cluster < static_cast<int>(as->clusters.size()) && as->clusters[d.cluster].ground;
    c.dl->AddCircle(c.ToScreen(d.u, d.v), 4.0f, ground ? IM_COL32(90, 230, 110, 230) : IM_COL32(255, 160, 40, 230), 0, 1.5f);
  }
  char label[96];
  if (as->healthy)
    std::snprintf(label, sizeof label, "height %.2f m (%zu dots, %zu clusters)", as->height_m, as->dots.size(),
                  as->clusters.size());
  else
    std::snprintf(label, sizeof label, "no height: %s", as->reason.c_str());
  c.dl->AddText(c.ToScreen(0.02, 0.02), as->healthy ? IM_COL32(90, 230, 110, 255) : IM_COL32(255, 90, 90, 255), label);
}

}  // namespace uav::gcs
