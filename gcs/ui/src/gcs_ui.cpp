#include "uav/gcs/gcs_ui.hpp"

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

namespace {
// Default layout for a first run; afterwards imgui.ini keeps what the operator arranged.
void Place(float x, float y, float w, float h) {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(x * d.x, y * d.y), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(w * d.x, h * d.y), ImGuiCond_FirstUseEver);
}
}  // namespace

void DrawGcs(GcsModel& model, UiContext& ctx) {
  ctx.widgets.clear();
  ctx.map.valid = false;
  DrawStatusBarPanel(model, ctx);
  Place(0.0f, 0.04f, 0.22f, 0.18f);
  DrawVehiclesPanel(model, ctx);
  Place(0.0f, 0.22f, 0.22f, 0.42f);
  DrawStateListPanel(model, ctx);
  Place(0.0f, 0.64f, 0.22f, 0.36f);
  DrawVideoPanel(model, ctx);
  Place(0.22f, 0.04f, 0.40f, 0.51f);
  DrawPlotPanel(model, ctx);
  Place(0.22f, 0.55f, 0.40f, 0.22f);
  DrawCommandBarPanel(model, ctx);
  Place(0.22f, 0.77f, 0.26f, 0.23f);
  DrawMessagesPanel(model, ctx);
  Place(0.48f, 0.77f, 0.14f, 0.23f);
  DrawObstacleViewPanel(model, ctx);
  Place(0.62f, 0.04f, 0.38f, 0.46f);
  DrawMapPanel(model, ctx);
  Place(0.62f, 0.50f, 0.38f, 0.32f);
  DrawSurveyPanel(model, ctx);
  Place(0.62f, 0.82f, 0.38f, 0.18f);
  DrawLiveMapPanel(model, ctx);
  Place(0.0f, 0.10f, 0.22f, 0.12f);  // over the Vehicles panel's empty lower half: the replay's
  if (ctx.replay) DrawReplayPanel(model, ctx);  // controls, or live, the pre-arm checklist
  else DrawPreArmPanel(model, ctx);
  Place(0.0f, 0.50f, 0.22f, 0.14f);  // over the state list's lower rows
  DrawSensingPanel(model, ctx);
  DrawParametersPanel(model, ctx);  // a window of its own, opened from the status bar
  DrawMissionPanel(model, ctx);     // a window of its own, while the map edits the mission
  DrawSticksPanel(model, ctx);      // a window of its own, opened from the status bar
  DrawAttitudePanel(model, ctx);    // a window of its own, opened from the status bar
}

}  // namespace uav::gcs
