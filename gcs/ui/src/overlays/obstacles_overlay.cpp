// Stereo obstacles (thesis 3.5) on the map and over the video.
#include <algorithm>
#include <cstdio>

#include "overlays.hpp"

namespace uav::gcs {

constexpr ImU32 kObstacle = IM_COL32(200, 80, 255, 230);

void DrawObstaclesOnMap(const GcsModel& model, const VehicleModel& v, const MapCanvas& m, double now) {
  // To scale: the seen radius filled, the safety radius (radius plus margin) as a ring the
  // vehicle keeps out of.
  const Obstacles* obstacles = v.reports.Fresh<Obstacles>(now, model.obstacles().params().stale_after_s);
  if (!obstacles) return;
  for (const Obstacle& o : obstacles->obstacles) {
    const ImVec2 c = m.ToScreen(o.p_NE.x(), o.p_NE.y());
    const float r = std::max(2.0f, static_cast<float>(o.radius_m * m.px_per_m));
    m.dl->AddCircleFilled(c, r, IM_COL32(200, 80, 255, 150), 32);
    m.dl->AddCircle(c, static_cast<float>(o.safety_radius_m * m.px_per_m), kObstacle, 48, 1.5f);
  }
}

void DrawObstaclesOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                          double now) {
  // Boxes around their projected cylinders, labelled with the horizontal distance to their surface.
  const Obstacles* obstacles = v.reports.Fresh<Obstacles>(now, model.obstacles().params().stale_after_s);
  if (!obstacles || obstacles->camera != feed.camera) return;
  for (const Obstacle& o : obstacles->obstacles) {
    const ImVec2 a = c.ToScreen(o.image_box[0], o.image_box[1]), b = c.ToScreen(o.image_box[2], o.image_box[3]);
    c.dl->AddRect(a, b, kObstacle, 0, 0, 2.0f);
    char label[32];
    std::snprintf(label, sizeof label, "%.1f m", o.range_m);
    c.dl->AddText(ImVec2(a.x + 2, a.y + 2), kObstacle, label);
  }
}

}  // namespace uav::gcs
