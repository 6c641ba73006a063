// Survey planner: camera and survey parameters, live statistics of the plan the map draws, the
// reason it cannot be flown (and the speed that can), upload to the selected vehicle with its
// progress, and .plan / QGC WPL export and import.
#include <cmath>
#include <cstdio>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "number_field.hpp"
#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

// A number field that edits `value` (shown in `scale` units, e.g. percent) and replans. The
// label is drawn apart so the registered rectangle is the field a person clicks into.
bool Field(UiContext& ctx, SurveyPlanner& planner, const char* label, const char* id, double* value,
           double scale, const char* format) {
  double shown = *value * scale;
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted(label);
  ImGui::SameLine();
  // Any decimal is taken (the planner names a value it cannot plan with); "inf" or "nan" is refused.
  const bool changed = NumberField(ctx, id, &shown, -1e6, 1e6, format, "", 70);
  if (changed) {
    *value = shown / scale;
    planner.ParamsChanged();
  }
  return changed;
}

}  // namespace

void DrawSurveyPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Survey");
  SurveyPlanner& planner = model.missions().planner();
  waypoints::SurveyParams& p = planner.params();

  const auto& cams = planner.cameras();
  ImGui::SetNextItemWidth(220);
  if (ImGui::BeginCombo("camera", cams[planner.camera_index()].name.c_str())) {
    for (std::size_t i = 0; i < cams.size(); ++i)
      if (ImGui::Selectable(cams[i].name.c_str(), static_cast<int>(i) == planner.camera_index()))
        planner.SelectCamera(static_cast<int>(i));
    ImGui::EndCombo();
  }
  RegisterLastItem(ctx, "survey:camera");
  bool portrait = !p.camera.landscape;
  ImGui::SameLine();
  if (ImGui::Checkbox("portrait", &portrait)) {
    p.camera.landscape = !portrait;
    planner.ParamsChanged();
  }
  RegisterLastItem(ctx, "survey:portrait");
  // The speed and turn radius the selected vehicle flies (a tail-sitter's cruise and turns).
  ImGui::SameLine();
  ImGui::BeginDisabled(!model.selected());
  if (ImGui::Button("fit to vehicle")) model.FitSurveyToVehicle(ctx.now);
  ImGui::EndDisabled();
  RegisterLastItem(ctx, "survey:fit");

  Field(ctx, planner, "altitude [m]", "survey:altitude", &p.altitude_m, 1.0, "%.1f");
  ImGui::SameLine();
  Field(ctx, planner, "speed [m/s]", "survey:speed", &p.speed_m_s, 1.0, "%.1f");
  Field(ctx, planner, "front overlap [%]", "survey:front", &p.front_overlap, 100.0, "%.0f");
  ImGui::SameLine();
  Field(ctx, planner, "side overlap [%]", "survey:side", &p.side_overlap, 100.0, "%.0f");
  Field(ctx, planner, "grid angle [deg]", "survey:angle", &p.grid_angle_deg, 1.0, "%.1f");
  ImGui::SameLine();
  Field(ctx, planner, "turnaround [m]", "survey:turnaround", &p.turnaround_m, 1.0, "%.1f");
  Field(ctx, planner, "capture rate [Hz]", "survey:rate", &p.capture_rate_hz, 1.0, "%.1f");
  ImGui::SameLine();
  Field(ctx, planner, "trigger dist [m]", "survey:trigger", &p.trigger_distance_m, 1.0, "%.1f");
  ImGui::SetNextItemWidth(110);
  if (ImGui::SliderInt("entry corner", &p.entry_corner, 0, 3)) planner.ParamsChanged();
  RegisterLastItem(ctx, "survey:entry");
  ImGui::SameLine();
  if (ImGui::Checkbox("crosshatch", &p.crosshatch)) planner.ParamsChanged();
  RegisterLastItem(ctx, "survey:crosshatch");
  // A fixed wing (U-Lion on its wing) cannot turn tighter than this: consecutive lines are then
  // flown at least two radii apart, the lines between taken later (0: a multicopter turns on the spot).
  ImGui::SameLine();
  Field(ctx, planner, "turn radius [m]", "survey:turn_radius", &p.turn_radius_m, 1.0, "%.1f");
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("a fixed wing's: cruise speed^2 / (g tan bank), 27 m for U-Lion at 12 m/s and 28.6 deg");

  ImGui::Separator();
  if (const auto& plan = planner.plan()) {
    ImGui::Text("GSD %.2f cm/px at %.1f m   footprint %.1f x %.1f m", plan->footprint.gsd_cm_per_px,
                plan->altitude_m, plan->footprint.across_m, plan->footprint.along_m);
    ImGui::Text("%d lines %.1f m apart   %zu images every %.2f m (front overlap needs <= %.2f m)", plan->lines,
                plan->line_spacing_m, plan->captures.size(), plan->capture_spacing_m, plan->required_trigger_distance_m);
    ImGui::Text("path %.0f m   flight %.0f min %02.0f s   area %.0f m^2   covered %.0f m^2", plan->path_length_m,
                std::floor(plan->flight_time_s / 60), std::fmod(plan->flight_time_s, 60.0), plan->polygon_area_m2,
                plan->covered_area_m2);
  }
  if (!planner.problem().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", planner.problem().c_str());
  DrawNumberFieldRefusals(ctx, "survey:");

  ImGui::BeginDisabled(!planner.problem().empty() || !model.selected());
  if (ImGui::Button("Upload to vehicle")) model.UploadMission(ctx.now);
  ImGui::EndDisabled();
  RegisterLastItem(ctx, "survey:upload");
  ImGui::SameLine();
  if (ImGui::Button("Clear area")) planner.Clear();
  RegisterLastItem(ctx, "survey:clear");
  if (const VehicleModel* v = model.selected(); v && v->upload) {
    const auto& up = *v->upload;
    using State = waypoints::MissionUploader::State;
    if (up.state() == State::kSending) {
      ImGui::ProgressBar(static_cast<float>(up.acknowledged_items()) / std::max(1, up.total_items()), ImVec2(-1, 0),
                         "uploading");
    } else if (up.state() == State::kAccepted) {
      ImGui::TextColored(ImVec4(0.4f, 1, 0.4f, 1), "%s holds this mission (%d items)", v->id.c_str(), up.total_items());
    } else {
      ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "upload %s: %s", up.state() == State::kRejected ? "rejected" : "failed",
                         up.reason().c_str());
    }
  }
  if (!model.missions().error().empty()) ImGui::TextColored(ImVec4(1, 0.4f, 0.3f, 1), "%s", model.missions().error().c_str());

  DrawMissionFileRow(model, ctx, "survey:file", "survey:export", "survey:import");
  ImGui::End();
}

void DrawMissionFileRow(GcsModel& model, UiContext& ctx, const char* file_id, const char* export_id,
                        const char* import_id) {
  ImGui::AlignTextToFramePadding();
  ImGui::TextUnformatted("file (.plan, .waypoints)");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(220);
  ImGui::InputText((std::string("##") + file_id).c_str(), &ctx.state.survey_file);
  RegisterLastItem(ctx, file_id);
  ImGui::SameLine();
  if (ImGui::Button("Export")) model.ExportMission(ctx.state.survey_file, ctx.now);
  RegisterLastItem(ctx, export_id);
  ImGui::SameLine();
  if (ImGui::Button("Import")) model.ImportMission(ctx.state.survey_file, ctx.now);
  RegisterLastItem(ctx, import_id);
}

}  // namespace uav::gcs
