#include "uav/gcs/gcs_ui.hpp"

#include "uav/gcs/layout.hpp"

#include <imgui.h>
#include <imgui_internal.h>

namespace uav::gcs {

void RegisterLastItem(UiContext& ctx, const std::string& label) {
  // Only what a person could click: the widget's centre inside its window's visible area and
  // not under another window (z-order of the last frame).
  const ImVec2 a = ImGui::GetItemRectMin(), b = ImGui::GetItemRectMax();
  const ImVec2 centre(0.5f * (a.x + b.x), 0.5f * (a.y + b.y));
  ImGuiWindow* window = ImGui::GetCurrentWindowRead();
  if (!window->ClipRect.Contains(centre)) return;
  ImGuiWindow* root = window->RootWindow;
  const ImGuiContext& g = *ImGui::GetCurrentContext();
  bool above = false;
  for (ImGuiWindow* w : g.Windows) {
    if (w == root) {
      above = true;
      continue;
    }
    if (above && w->WasActive && !w->Hidden && w->RootWindow == w && !(w->Flags & ImGuiWindowFlags_Tooltip) &&
        w->Rect().Contains(centre))
      return;
  }
  const bool disabled = (g.LastItemData.InFlags & ImGuiItemFlags_Disabled) != 0;
  ctx.widgets[label] = {a.x, a.y, b.x, b.y, disabled ? (ctx.disabled_because.empty() ? "disabled" : ctx.disabled_because) : ""};
}

void BeginDisabledBecause(UiContext& ctx, bool disabled, const std::string& why) {
  ImGui::BeginDisabled(disabled);
  ctx.disabled_because = disabled ? why : "";
}

void EndDisabledBecause(UiContext& ctx) {
  ImGui::EndDisabled();
  ctx.disabled_because.clear();
}

void PlaceWindow(const char* window, bool always) {
  const WindowPlace* p = FindWindowPlace(window);
  if (!p) return;
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  const ImGuiCond when = always ? ImGuiCond_Always : ImGuiCond_FirstUseEver;
  ImGui::SetNextWindowPos(ImVec2(p->x0 * d.x, p->y0 * d.y), when);
  ImGui::SetNextWindowSize(ImVec2((p->x1 - p->x0) * d.x, (p->y1 - p->y0) * d.y), when);
  ImGui::SetNextWindowBgAlpha(1.0f);  // opaque: a window over another never shows both
}

void DrawGcs(GcsModel& model, UiContext& ctx) {
  ctx.widgets.clear();
  ctx.map.valid = false;
  // The default layout (layout.hpp) for a first run; afterwards the layout file keeps what the
  // operator arranged. The panels placed here open with it; the on-demand windows place
  // themselves when opened.
  PlaceWindow("Status", true);
  DrawStatusBarPanel(model, ctx);
  PlaceWindow("Vehicles");
  DrawVehiclesPanel(model, ctx);
  PlaceWindow("Vehicle state");
  DrawStateListPanel(model, ctx);
  PlaceWindow("Video");
  DrawVideoPanel(model, ctx);
  PlaceWindow("Plot");
  DrawPlotPanel(model, ctx);
  PlaceWindow("Command");
  DrawCommandBarPanel(model, ctx);
  PlaceWindow("Messages");
  DrawMessagesPanel(model, ctx);
  PlaceWindow("Obstacles");
  DrawObstacleViewPanel(model, ctx);
  PlaceWindow("Map");
  DrawMapPanel(model, ctx);
  PlaceWindow("Survey");
  DrawSurveyPanel(model, ctx);
  PlaceWindow("Live map");
  DrawLiveMapPanel(model, ctx);
  PlaceWindow("Sensing");
  DrawSensingPanel(model, ctx);
  if (ctx.replay) {  // the replay's controls in the pre-arm checklist's place
    PlaceWindow("Replay");
    DrawReplayPanel(model, ctx);
  } else {
    PlaceWindow("Pre-arm");
    DrawPreArmPanel(model, ctx);
  }
  DrawParametersPanel(model, ctx);  // a window of its own, opened from the status bar
  DrawMissionPanel(model, ctx);     // a window of its own, while the map edits the mission
  DrawSticksPanel(model, ctx);      // a window of its own, opened from the status bar
  DrawAttitudePanel(model, ctx);    // a window of its own, opened from the status bar
}

}  // namespace uav::gcs
