// Pre-arm: the selected vehicle's pre-arm checks as a checklist, each in green (passed) or red
// (failing, with why), as QGroundControl shows them before arming. `arm` is refused by the
// vehicle while one fails; the refusal names them too.
#include <imgui.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawPreArmPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Pre-arm");
  const VehicleModel* v = model.selected();
  const Received<PreArmReport>* received = v ? &v->reports.Get<PreArmReport>() : nullptr;
  if (v && v->armed) {
    ImGui::TextDisabled("armed: the checks passed when it armed");
  } else if (!received || !received->newest) {
    ImGui::TextDisabled("no pre-arm report yet");
  } else {
    const PreArmReport& r = *received->newest;
    const ImVec4 red(1, 0.3f, 0.3f, 1), green(0.4f, 0.9f, 0.4f, 1), amber(1, 0.7f, 0.2f, 1);
    if (ctx.now - received->at > 3.0) ImGui::TextColored(amber, "report %.0f s old", ctx.now - received->at);
    if (r.Ready()) ImGui::TextColored(green, "ready to arm");
    else ImGui::TextColored(red, "arming refused until these pass");
    for (const PreArmCheck& c : r.checks)
      ImGui::TextColored(c.passed ? green : red, "%s %-9s %s", c.passed ? "[ok]" : "[X] ", c.name.c_str(), c.reason.c_str());
  }
  ImGui::End();
}

}  // namespace uav::gcs
