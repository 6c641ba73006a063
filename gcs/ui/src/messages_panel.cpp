// Events from the vehicles and the GCS: status texts, acknowledgements, link changes.
#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawMessagesPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Messages");
  BeginDisabledBecause(ctx, !ctx.state.speech_unavailable.empty(), ctx.state.speech_unavailable);
  ImGui::Checkbox("speak warnings", &ctx.state.speak_alerts);
  RegisterLastItem(ctx, "messages:speak");
  EndDisabledBecause(ctx);
  if (!ctx.state.speech_unavailable.empty()) {
    ImGui::SameLine();
    ImGui::TextDisabled("off: %s", ctx.state.speech_unavailable.c_str());
  }
  ImGui::BeginChild("log");
  // Whole texts, wrapped at the panel's edge: "failsafe land: ... (landing where it is)" must
  // never end at "(landing".
  ImGui::PushTextWrapPos(0.0f);
  for (const LogLine& l : model.log().lines()) {
    const ImVec4 color = l.severity == Severity::kError     ? ImVec4(1, 0.35f, 0.3f, 1)
                         : l.severity == Severity::kWarning ? ImVec4(1, 0.8f, 0.3f, 1)
                                                            : ImVec4(0.8f, 0.8f, 0.8f, 1);
    ImGui::TextColored(color, "%7.1f  %s  %s", l.t - ctx.start_time, l.vehicle_id.c_str(), l.text.c_str());
  }
  ImGui::PopTextWrapPos();
  if (!model.log().lines().empty()) RegisterLastItem(ctx, "messages:last");
  if (ImGui::GetScrollY() >= ImGui::GetScrollMaxY() - 20) ImGui::SetScrollHereY(1.0f);
  ImGui::EndChild();
  ImGui::End();
}

}  // namespace uav::gcs
