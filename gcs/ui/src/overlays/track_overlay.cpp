// The tracker's report (thesis 3.7) over the live video.
#include <cmath>
#include <cstdio>
#include <string>

#include "overlays.hpp"

namespace uav::gcs {

void DrawTrackOnImage(const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c, double now) {
  if (v.track && v.track->state == TrackStatus::kRejected && now - v.track_received < 5.0) {
    const std::string text = "TARGET REJECTED: " + v.track->reason;
    c.dl->AddText(ImVec2(c.p0.x + 6, c.p0.y + 6), IM_COL32(255, 90, 90, 255), text.c_str());
  } else if (v.track && v.track->state != TrackStatus::kIdle && now - v.track_received < 2.0 &&
             (v.track->camera.empty() || v.track->camera == feed.camera)) {
    const TrackStatus& t = *v.track;
    // The search window the next frame starts from (the whole picture while lost).
    c.dl->AddRect(c.ToScreen(t.window_x, t.window_y), c.ToScreen(t.window_x + t.window_width, t.window_y + t.window_height),
                  IM_COL32(80, 200, 255, 160), 0.0f, 0, 1.0f);
    const ImU32 colour = t.state == TrackStatus::kTracking ? IM_COL32(80, 255, 120, 255) : IM_COL32(255, 170, 60, 255);
    const double cs = std::cos(t.angle_rad), sn = std::sin(t.angle_rad);
    // Oriented box: normalised units scaled by the picture's aspect so the rotation is true.
    const double aspect = static_cast<double>(c.size.y) / c.size.x;
    ImVec2 q[4];
    const double hx[4] = {-0.5, 0.5, 0.5, -0.5}, hy[4] = {-0.5, -0.5, 0.5, 0.5};
    for (int i = 0; i < 4; ++i) {
      const double dx = hx[i] * t.width, dy = hy[i] * t.height * aspect;
      q[i] = c.ToScreen(t.center_x + cs * dx - sn * dy, t.center_y + (sn * dx + cs * dy) / aspect);
    }
    c.dl->AddPolyline(q, 4, colour, ImDrawFlags_Closed, 2.0f);
    const ImVec2 ctr = c.ToScreen(t.center_x, t.center_y);
    c.dl->AddLine(ImVec2(ctr.x - 8, ctr.y), ImVec2(ctr.x + 8, ctr.y), colour, 2.0f);
    c.dl->AddLine(ImVec2(ctr.x, ctr.y - 8), ImVec2(ctr.x, ctr.y + 8), colour, 2.0f);
    char label[96];
    std::snprintf(label, sizeof label, "%s %s %.2f", t.state == TrackStatus::kTracking ? "TRACKING" : "LOST",
                  t.tracker.c_str(), t.confidence);
    c.dl->AddText(ImVec2(q[0].x, q[0].y - 16), colour, label);
  } else if (v.track_target && v.track_target->method != TrackTarget::kCancel) {
    // Sent, no answer yet: the selection, thin.
    const TrackTarget& t = *v.track_target;
    c.dl->AddRect(c.ToScreen(t.x, t.y), c.ToScreen(t.x + t.width, t.y + t.height), IM_COL32(255, 255, 255, 180));
  }
}

}  // namespace uav::gcs
