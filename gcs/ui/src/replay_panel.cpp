// Replay controls, shown while a recorded flight plays (uav-gcs --replay): play/pause, a seek
// slider over the whole flight, the speed (0.1x to 10x), and where a damaged log stops.
#include <imgui.h>

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
  float speed = static_cast<float>(r->speed());
  ImGui::SetNextItemWidth(-1);
  if (ImGui::SliderFloat("##replay:speed", &speed, 0.1f, 10.0f, "x%.1f", ImGuiSliderFlags_Logarithmic)) r->SetSpeed(speed);
  RegisterLastItem(ctx, "replay:speed");
  ImGui::TextDisabled("%zu of %zu events; nothing is sent", r->dispatched(), r->events());
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", r->path().c_str());
  if (!r->damage().empty()) ImGui::TextColored(ImVec4(1, 0.6f, 0.3f, 1), "log damaged at %s", r->damage().c_str());
  ImGui::End();
}

}  // namespace uav::gcs
