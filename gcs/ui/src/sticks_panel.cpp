// The Sticks window: manual flight from the GCS (QGroundControl's virtual joystick). Two
// self-centring on-screen sticks in mode 2 (left: yaw and climb, right: move), held while dragged
// (the deadman), or a gamepad when one is connected (either bumper is the deadman). "Sticks on"
// sends them at 20 Hz; `sticks` puts the vehicle in the task that flies them.
#include <algorithm>
#include <cmath>
#include <string>

#include <imgui.h>

#include "number_field.hpp"
#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

// One on-screen stick: drag inside the square; released, it springs back to the centre. Returns
// whether it is held. x right, y up, each in [-1, 1].
bool Pad(UiContext& ctx, const char* id, double* x, double* y, float side) {
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton(id, ImVec2(side, side));
  RegisterLastItem(ctx, id);
  const bool held = ImGui::IsItemActive();
  if (held) {
    const ImVec2 m = ImGui::GetIO().MousePos;
    *x = std::clamp(2.0 * (m.x - p0.x) / side - 1.0, -1.0, 1.0);
    *y = std::clamp(1.0 - 2.0 * (m.y - p0.y) / side, -1.0, 1.0);
  }
  ImDrawList* dl = ImGui::GetWindowDrawList();
  dl->AddRect(p0, ImVec2(p0.x + side, p0.y + side), IM_COL32(140, 140, 150, 255), 6.0f);
  dl->AddLine(ImVec2(p0.x + side / 2, p0.y), ImVec2(p0.x + side / 2, p0.y + side), IM_COL32(80, 80, 90, 255));
  dl->AddLine(ImVec2(p0.x, p0.y + side / 2), ImVec2(p0.x + side, p0.y + side / 2), IM_COL32(80, 80, 90, 255));
  const ImVec2 knob(p0.x + static_cast<float>((*x + 1.0) / 2.0) * side, p0.y + static_cast<float>((1.0 - *y) / 2.0) * side);
  dl->AddCircleFilled(knob, side * 0.09f, held ? IM_COL32(255, 190, 60, 255) : IM_COL32(170, 170, 180, 255));
  return held;
}

// A numeric axis (for scripts and precise input) in [-1, 1]; a value outside is refused, not
// clamped (number_field.hpp).
void Axis(UiContext& ctx, const char* label, const char* id, double* v) {
  NumberField(ctx, id, v, -1.0, 1.0, "%.2f", "of full deflection", 60);
  ImGui::SameLine();
  ImGui::TextUnformatted(label);
}

}  // namespace

void DrawSticksPanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  if (!st.show_sticks) return;
  PlaceWindow("Sticks");
  if (!ImGui::Begin("Sticks", &st.show_sticks)) {
    ImGui::End();
    return;
  }
  StickInput& sticks = model.sticks();
  bool on = sticks.enabled();
  if (ImGui::Checkbox("Sticks on (20 Hz to the selected vehicle)", &on)) sticks.SetEnabled(on);
  RegisterLastItem(ctx, "sticks:on");
  const VehicleModel* v = model.selected();
  const bool flying_sticks = v && v->task == Task::kSticks;
  BeginDisabledBecause(ctx, !v || flying_sticks, !v ? "no vehicle selected" : "the vehicle already flies by the sticks");
  if (ImGui::Button("Fly by sticks")) model.SubmitCommand("sticks", ctx.now);
  RegisterLastItem(ctx, "sticks:fly");
  EndDisabledBecause(ctx);
  ImGui::TextDisabled(sticks.has_gamepad() ? "gamepad connected: it flies (hold a bumper as the deadman)"
                                           : "no gamepad: drag the sticks (held = deadman), or type the axes");
  ManualSticks& vs = sticks.virtual_sticks();
  Axis(ctx, "forward", "sticks:forward", &vs.forward);
  ImGui::SameLine();
  Axis(ctx, "right", "sticks:right_axis", &vs.right);
  ImGui::SameLine();
  Axis(ctx, "up", "sticks:up", &vs.up);
  ImGui::SameLine();
  Axis(ctx, "yaw", "sticks:yaw", &vs.yaw);
  DrawNumberFieldRefusals(ctx, "sticks:");
  bool latch = st.sticks_deadman_latched;
  if (ImGui::Checkbox("deadman held", &latch)) st.sticks_deadman_latched = latch;
  RegisterLastItem(ctx, "sticks:deadman");
  const float side = std::clamp(std::min(ImGui::GetContentRegionAvail().x * 0.45f, ImGui::GetContentRegionAvail().y - 30.0f),
                                60.0f, 200.0f);
  const bool left = Pad(ctx, "sticks:left", &vs.yaw, &vs.up, side);
  ImGui::SameLine();
  const bool right = Pad(ctx, "sticks:right", &vs.right, &vs.forward, side);
  // Self-centring: a stick let go springs back (typed axes stay).
  if (st.sticks_left_held && !left) vs.yaw = vs.up = 0.0;
  if (st.sticks_right_held && !right) vs.right = vs.forward = 0.0;
  st.sticks_left_held = left, st.sticks_right_held = right;
  vs.deadman = left || right || st.sticks_deadman_latched;
  const ManualSticks& c = sticks.current();
  ImGui::Text("sending fwd %+.2f right %+.2f up %+.2f yaw %+.2f %s (%ld sent)", c.forward, c.right, c.up, c.yaw,
              c.deadman ? "DEADMAN" : "released", sticks.sent());
  ImGui::End();
}

}  // namespace uav::gcs
