// Sensing: the selected vehicle's vision workers, one row each: its camera, the rate it achieves
// against the rate asked of it (and its camera's, where the vehicle lowered it on purpose), the latency from exposure to result (p50/p99), the compute time, frames
// dropped while it was busy, and healthy or why not. Above them, the control loop's wall-clock
// period (vision runs off that path and must never stretch it). A report that stops coming is a
// warning too.
#include <cstdio>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawSensingPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Sensing");
  const VehicleModel* v = model.selected();
  const Received<SensingReport>* received = v ? &v->reports.Get<SensingReport>() : nullptr;
  if (!received || !received->newest) {
    ImGui::TextDisabled("no sensing report (the vehicle runs no cameras)");
    ImGui::End();
    return;
  }
  const ImVec4 red(1, 0.3f, 0.3f, 1), amber(1, 0.7f, 0.2f, 1);
  const SensingReport& r = *received->newest;
  const double age_s = ctx.now - received->at;
  if (age_s > 3.0 && v->LinkUp(ctx.now, model.telemetry_params()))
    ImGui::TextColored(amber, "no sensing report for %.0f s", age_s);
  ImGui::Text("control period %.1f ms p50, %.1f p99, %.1f max (nominal 20); latency %s", r.control_period_p50_ms,
              r.control_period_p99_ms, r.control_period_max_ms, r.measured_latency ? "measured" : "from the vehicle file");
  constexpr ImGuiTableFlags kFlags = ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_SizingFixedFit;
  if (ImGui::BeginTable("sensing:workers", 7, kFlags)) {
    for (const char* heading : {"worker", "camera", "rate Hz", "latency ms", "compute ms", "dropped", "status"})
      ImGui::TableSetupColumn(heading);
    ImGui::TableHeadersRow();
    for (const SensingWorker& w : r.workers) {
      ImGui::TableNextRow();
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(w.name.c_str());
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(w.rig.c_str());
      ImGui::TableNextColumn();
      if (w.configured_rate_hz <= 0) ImGui::Text("%.1f (queue)", w.rate_hz);
      else if (w.configured_rate_hz < w.camera_rate_hz - 1e-3)
        ImGui::Text("%.1f / %.1f of %.0f", w.rate_hz, w.configured_rate_hz, w.camera_rate_hz);
      else ImGui::Text("%.1f / %.1f", w.rate_hz, w.configured_rate_hz);
      ImGui::TableNextColumn();
      ImGui::Text("%.0f / %.0f", w.latency_p50_ms, w.latency_p99_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%.1f", w.compute_p50_ms);
      ImGui::TableNextColumn();
      ImGui::Text("%lld", static_cast<long long>(w.dropped));
      ImGui::TableNextColumn();
      if (!w.healthy) ImGui::TextColored(red, "%s", w.reason.c_str());
      else if (!w.reason.empty()) ImGui::TextColored(amber, "%s", w.reason.c_str());  // a rate lowered on purpose
      else ImGui::TextUnformatted("ok");
    }
    ImGui::EndTable();
  }
  RegisterLastItem(ctx, "sensing:workers");
  ImGui::End();
}

}  // namespace uav::gcs
