#pragma once
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/ui_context.hpp"

namespace uav::gcs {

// Draws every panel for one frame (between ImGui::NewFrame and ImGui::Render).
void DrawGcs(GcsModel& model, UiContext& ctx);

// The panels, one file each.
void DrawVehiclesPanel(GcsModel& model, UiContext& ctx);
void DrawStateListPanel(GcsModel& model, UiContext& ctx);
void DrawPlotPanel(GcsModel& model, UiContext& ctx);
void DrawCommandBarPanel(GcsModel& model, UiContext& ctx);
void DrawStatusBarPanel(GcsModel& model, UiContext& ctx);
void DrawMessagesPanel(GcsModel& model, UiContext& ctx);
void DrawMapPanel(GcsModel& model, UiContext& ctx);
void DrawSurveyPanel(GcsModel& model, UiContext& ctx);
void DrawMissionPanel(GcsModel& model, UiContext& ctx);  // while the map edits the mission
void DrawSticksPanel(GcsModel& model, UiContext& ctx);   // opened from the status bar
void DrawLiveMapPanel(GcsModel& model, UiContext& ctx);
void DrawObstacleViewPanel(GcsModel& model, UiContext& ctx);
void DrawSensingPanel(GcsModel& model, UiContext& ctx);
void DrawPreArmPanel(GcsModel& model, UiContext& ctx);
void DrawParametersPanel(GcsModel& model, UiContext& ctx);
// Uploads the selected vehicle's changed live-map tiles into textures (shared by the Map and
// Live map panels).
void SyncLiveMapTextures(const VehicleModel& v, UiContext& ctx);
void DrawVideoPanel(GcsModel& model, UiContext& ctx);
void DrawReplayPanel(GcsModel& model, UiContext& ctx);

}  // namespace uav::gcs
