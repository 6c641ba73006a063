// Vehicles discovered by heartbeat; the selected one is what the other panels show and command.
// A MAVLink vehicle's row ends with its autopilot and mode; its tooltip says the rest of its
// link: frame, endpoint, signing, frames lost and refused, parameters read.
#include <cstdio>
#include <string>

#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawVehiclesPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Vehicles");
  if (model.vehicles().empty()) ImGui::TextDisabled("waiting for a heartbeat...");
  for (const auto& [id, v] : model.vehicles()) {
    char line[200];
    const std::string autopilot = v.mavlink ? "  [" + v.mavlink->autopilot + " " + v.mavlink->mode + "]" : "";
    std::snprintf(line, sizeof line, "%-8s %-4s  hb %4.1fs  %3.0f msg/s  %s%s%s", id.c_str(),
                  v.LinkUp(ctx.now, model.telemetry_params()) ? "up" : "LOST", v.HeartbeatAge(ctx.now),
                  v.MessageRate(ctx.now), v.task ? std::string(Name(*v.task)).c_str() : "unknown",
                  v.armed ? " (armed)" : "", autopilot.c_str());
    // The ID ignores the changing numbers, or a click would land on a different item each frame.
    if (ImGui::Selectable((std::string(line) + "###vehicle:" + id).c_str(), id == model.selected_id()))
      model.SelectVehicle(id);
    RegisterLastItem(ctx, "vehicle:" + id);
    if (v.mavlink && ImGui::IsItemHovered()) {
      const MavlinkLinkInfo& m = *v.mavlink;
      ImGui::SetTooltip("%s %s, mode %s\nMAVLink system %d on %s, %s\nframes lost %lld, refused %lld\nparameters %d of %d",
                        m.autopilot.c_str(), m.frame.c_str(), m.mode.c_str(), m.system_id, m.endpoint.c_str(),
                        m.signing ? "signed" : "unsigned", static_cast<long long>(v.sequence_gaps),
                        static_cast<long long>(m.refused_frames), m.parameters_received, m.parameters_total);
    }
  }
  ImGui::End();
}

}  // namespace uav::gcs
