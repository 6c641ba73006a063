// Replay controls, shown while a recorded flight plays (uav-gcs --replay): play/pause, a seek
// slider over the whole flight, the speed (0.1x to 10x: presets or typed), and where a damaged
// log stops.
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/shared/decimal.hpp"

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawReplayPanel(GcsModel& model, UiContext& ctx) {
  ReplayControl* r = ctx.replay;
  if (!r) return;
  ImGui::Begin("Replay");
  if (ImGui::Button(r->paused() ? "Play" : "Pause")) r->paused() ? r->Play() : r->Pause();
  RegisterLastItem(ctx, "replay:play");
  ImGui::SameLine();
  float t = ctx.state.replay_seek >= 0 ? ctx.state.replay_seek : static_cast<float>(r->position());
  ImGui::SetNextItemWidth(-1);
  if (ImGui::SliderFloat("##replay:seek", &t, 0.0f, static_cast<float>(r->duration()), "%.1f s")) ctx.state.replay_seek = t;
  RegisterLastItem(ctx, "replay:seek");
  if (ImGui::IsItemDeactivatedAfterEdit()) {  // seek when the slider is let go: seeking back replays from the start
    r->Seek(ctx.state.replay_seek);
    ctx.state.replay_seek = -1.0f;
  }
  // Speed: presets, or a typed value (Enter applies it; scripts: set replay:speed 5).
  ImGui::Text("speed x%.2g", r->speed());
  for (double preset : {0.5, 1.0, 2.0, 5.0, 10.0}) {
    ImGui::SameLine();
    char label[24];
    std::snprintf(label, sizeof label, "x%g", preset);
    if (ImGui::Button(label)) r->SetSpeed(preset), ctx.state.replay_speed_error.clear();
    RegisterLastItem(ctx, std::string("replay:") + label);
  }
  ImGui::SameLine();
  ImGui::SetNextItemWidth(80);
  if (ImGui::InputTextWithHint("##replay:speed", "0.1-10", &ctx.state.replay_speed_text, ImGuiInputTextFlags_EnterReturnsTrue)) {
    const std::optional<double> v = ParseDecimal(ctx.state.replay_speed_text);
    ctx.state.replay_speed_error = v && r->SetSpeed(*v) ? "" : "speed '" + ctx.state.replay_speed_text + "' refused: give 0.1 to 10";
    ctx.state.replay_speed_text.clear();
  }
  RegisterLastItem(ctx, "replay:speed");
  if (!ctx.state.replay_speed_error.empty()) ImGui::TextColored(ImVec4(1, 0.45f, 0.35f, 1), "%s", ctx.state.replay_speed_error.c_str());
  ImGui::TextDisabled("%zu of %zu events; nothing is sent", r->dispatched(), r->events());
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", r->path().c_str());
  if (!r->damage().empty()) ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "log damaged at %s", r->damage().c_str());
  ImGui::End();
}

}  // namespace uav::gcs
