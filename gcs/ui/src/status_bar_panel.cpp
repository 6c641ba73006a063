// One line across the top: every vehicle's link quality (heartbeat age, message rate, messages
// lost to sequence gaps), then the selected vehicle's flight mode, task, battery and failsafe.
#include <algorithm>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawStatusBarPanel(GcsModel& model, UiContext& ctx) {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(d.x, 0.04f * d.y));
  ImGui::Begin("Status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
  if (model.vehicles().empty()) {
    ImGui::Text("GCS %s  |  no vehicle on the bus", model.gcs_name().c_str());
    ImGui::End();
    return;
  }
  for (const auto& [id, veh] : model.vehicles()) {
    const bool up = veh.LinkUp(ctx.now);
    const bool sel = id == model.selected_id();
    ImGui::TextColored(up ? ImVec4(0.4f, 0.9f, 0.4f, 1) : ImVec4(1, 0.3f, 0.3f, 1), "%s%s %s %.1fs %.0f/s %lld lost",
                       sel ? ">" : "", id.c_str(), up ? "UP" : "LOST", std::min(veh.HeartbeatAge(ctx.now), 99.9),
                       veh.MessageRate(ctx.now), static_cast<long long>(veh.sequence_gaps));
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("%s: heartbeat %.1f s ago, %.0f messages/s, %lld messages lost (sequence gaps)", id.c_str(),
                        veh.HeartbeatAge(ctx.now), veh.MessageRate(ctx.now), static_cast<long long>(veh.sequence_gaps));
    ImGui::SameLine();
    ImGui::TextDisabled("|");
    ImGui::SameLine();
  }
  const VehicleModel* v = model.selected();
  auto get = [&](const char* k) {
    auto it = v->latest.find(k);
    return it == v->latest.end() ? 0.0 : it->second;
  };
  ImGui::Text("%s: task %s | %s | mode %s | alt %.1f m | battery %.2f V (%.0f %%)", v->id.c_str(), v->task.c_str(),
              v->armed ? "ARMED" : "disarmed", get("STATE.mode") > 0.5 ? "auto" : "manual", get("STATE.alt"),
              get("STATE.battery_v"), 100.0 * get("STATE.battery_remaining"));
  // The vehicle's failsafe in red, so it cannot be missed (the reason is in the messages).
  static const char* const kFailsafe[] = {"", "HOLD", "RETURN", "LAND", "PILOT (RC switch)"};
  const int fs = static_cast<int>(get("STATE.failsafe"));
  if (fs > 0 && fs < 5) {
    ImGui::SameLine();
    ImGui::TextColored(ImVec4(1, 0.3f, 0.3f, 1), "| FAILSAFE %s", kFailsafe[fs]);
  }
  ImGui::End();
}

}  // namespace uav::gcs
