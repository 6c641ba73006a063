// Power lines (thesis 3.6) on the map and over the video.
#include <cstdio>
#include <vector>

#include "overlays.hpp"

namespace uav::gcs {

void DrawPowerLinesOnMap(const GcsModel& model, const VehicleModel& v, const MapCanvas& m, double now) {
  // Those in the newest report bright, earlier ones dim.
  auto draw_wire = [&](const std::vector<Eigen::Vector3d>& p_N, ImU32 colour, float width) {
    std::vector<ImVec2> pts;
    for (const auto& p : p_N) pts.push_back(m.ToScreen(p.x(), p.y()));
    if (pts.size() > 1) m.dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, 0, width);
  };
  for (const auto& w : v.wire_map) draw_wire(w, IM_COL32(255, 120, 40, 110), 1.5f);
  const WireWarningParams& wp = model.wires().params();
  if (const PowerLines* lines = v.reports.Fresh<PowerLines>(now, wp.stale_after_s))
    for (const PowerLine& w : lines->wires)
      draw_wire(w.p_N, w.range_m < wp.warn_distance_m ? IM_COL32(255, 60, 60, 255) : IM_COL32(255, 160, 40, 255), 3.0f);
}

void DrawPowerLinesOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                           double now) {
  // When they were found in this camera's image: red nearer than the warning distance, orange
  // ranged, thin yellow seen but not ranged.
  const WireWarningParams& wp = model.wires().params();
  const PowerLines* lines = v.reports.Fresh<PowerLines>(now, wp.stale_after_s);
  if (!lines || lines->camera != feed.camera) return;
  for (const PowerLine& w : lines->wires) {
    if (w.image_uv.size() < 2) continue;
    const bool near = w.ranged() && w.range_m < wp.warn_distance_m;
    const ImU32 colour = near ? IM_COL32(255, 60, 60, 255) : w.ranged() ? IM_COL32(255, 160, 40, 255) : IM_COL32(255, 230, 80, 200);
    std::vector<ImVec2> pts;
    for (const auto& uv : w.image_uv) pts.push_back(c.ToScreen(uv.x(), uv.y()));
    c.dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), colour, ImDrawFlags_None, w.ranged() ? 2.5f : 1.5f);
    if (w.ranged()) {
      char label[32];
      std::snprintf(label, sizeof label, "%.1f m", w.range_m);
      const ImVec2 at = pts[pts.size() / 2];
      c.dl->AddText(ImVec2(at.x + 4, at.y - 16), colour, label);
    }
  }
}

}  // namespace uav::gcs
