// One line across the top: link quality, task and battery of the selected vehicle.
#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawStatusBarPanel(GcsModel& model, UiContext& ctx) {
  const ImVec2 d = ImGui::GetIO().DisplaySize;
  ImGui::SetNextWindowPos(ImVec2(0, 0));
  ImGui::SetNextWindowSize(ImVec2(d.x, 0.04f * d.y));
  ImGui::Begin("Status", nullptr,
               ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
  const VehicleModel* v = model.selected();
  if (!v) {
    ImGui::Text("GCS %s  |  no vehicle on the bus", model.gcs_name().c_str());
    ImGui::End();
    return;
  }
  const bool up = v->LinkUp(ctx.now);
  ImGui::TextColored(up ? ImVec4(0.4f, 0.9f, 0.4f, 1) : ImVec4(1, 0.3f, 0.3f, 1), "%s link %s",
                     v->id.c_str(), up ? "UP" : "LOST");
  ImGui::SameLine();
  auto get = [&](const char* k) {
    auto it = v->latest.find(k);
    return it == v->latest.end() ? 0.0 : it->second;
  };
  ImGui::Text("| heartbeat %.1f s | %.0f msg/s | %lld lost | task %s | %s | mode %s | alt %.1f m | battery %.2f V (%.0f %%)",
              v->HeartbeatAge(ctx.now), v->MessageRate(ctx.now), static_cast<long long>(v->sequence_gaps),
              v->task.c_str(), v->armed ? "ARMED" : "disarmed", get("STATE.mode") > 0.5 ? "auto" : "manual",
              get("STATE.alt"), get("STATE.battery_v"), 100.0 * get("STATE.battery_remaining"));
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
