#pragma once
#include "uav/gcs/gcs_model.hpp"
#include "uav/gcs/ui_context.hpp"

namespace uav::gcs {

// Draws every panel for one frame (between ImGui::NewFrame and ImGui::Render).
void DrawGcs(GcsModel& model, UiContext& ctx);
// Places the next window where the default layout (layout.hpp) puts `window`: on its first use,
// or `always`.
void PlaceWindow(const char* window, bool always = false);

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
void DrawAttitudePanel(GcsModel& model, UiContext& ctx);  // opened from the status bar

// The attitude indicator's horizon on screen (x right, y down): its ends `half_length_px` either
// side of where it crosses the wings' normal through `centre_px`, and that normal pointing down
// from the sky (the pitch ladder's direction). Banked right the right end rises; nose up the line
// moves down by pitch * px_per_rad.
struct HorizonLine {
  Eigen::Vector2d left_px, right_px, down_px;
};
HorizonLine AttitudeHorizon(double roll_rad, double pitch_rad, const Eigen::Vector2d& centre_px, double px_per_rad,
                            double half_length_px);
// Uploads the selected vehicle's changed live-map tiles into textures (shared by the Map and
// Live map panels).
void SyncLiveMapTextures(const VehicleModel& v, UiContext& ctx);
void DrawVideoPanel(GcsModel& model, UiContext& ctx);
// The mission's file row (survey panel and mission window): the path, Export and Import.
void DrawMissionFileRow(GcsModel& model, UiContext& ctx, const char* file_id, const char* export_id,
                        const char* import_id);
void DrawReplayPanel(GcsModel& model, UiContext& ctx);

}  // namespace uav::gcs
