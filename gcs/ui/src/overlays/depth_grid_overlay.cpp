// Depth from motion (thesis 3.4, Fig. 3.11) over the video.
#include <cstdio>

#include "overlays.hpp"

namespace uav::gcs {

void DrawDepthGridOnImage(const GcsModel& model, const VehicleModel& v, const VideoFeed& feed, const ImageCanvas& c,
                          double now) {
  // The grid over the picture, each cell's depth and state (red obstacle, green free, grey
  // unknown with its reason on hover).
  const DepthGrid* grid = v.DepthGridOver(feed, now, model.obstacles().params());
  if (!grid) return;
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  for (int r = 0; r < grid->rows; ++r)
    for (int col = 0; col < grid->cols; ++col) {
      const DepthCell& cell = grid->at(r, col);
      const ImU32 colour = cell.state == CellState::kObstacle ? IM_COL32(255, 70, 70, 220)
                           : cell.state == CellState::kFree   ? IM_COL32(90, 230, 110, 200)
                                                              : IM_COL32(170, 170, 170, 150);
      const ImVec2 a = c.ToScreen(static_cast<double>(col) / grid->cols, static_cast<double>(r) / grid->rows);
      const ImVec2 b = c.ToScreen(static_cast<double>(col + 1) / grid->cols, static_cast<double>(r + 1) / grid->rows);
      c.dl->AddRect(a, b, colour, 0, 0, 1.0f);
      char label[48];
      if (cell.state == CellState::kUnknown) std::snprintf(label, sizeof label, "?");
      else std::snprintf(label, sizeof label, "%.1f m %s", cell.depth_m, cell.state == CellState::kObstacle ? "OBST" : "");
      c.dl->AddText(ImVec2(a.x + 4, a.y + 3), colour, label);
      if (cell.state == CellState::kUnknown && mouse.x >= a.x && mouse.x < b.x && mouse.y >= a.y && mouse.y < b.y &&
          ImGui::IsWindowHovered())
        ImGui::SetTooltip("%s", grid->healthy ? cell.reason.c_str() : grid->reason.c_str());
    }
}

}  // namespace uav::gcs
