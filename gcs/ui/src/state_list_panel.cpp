// Every received signal of the selected vehicle, grouped by message (thesis Fig. 2.8 left
// side), with a tick box that puts it on the plot.
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {

void DrawStateListPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Vehicle state");
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##filter", "search signals", &ctx.state.signal_filter);
  const VehicleModel* v = model.selected();
  if (!v) {
    ImGui::TextDisabled("no vehicle");
    ImGui::End();
    return;
  }
  std::string group;
  bool open = false;
  for (const std::string& key : v->signal_order) {
    const double value = v->latest.at(key);
    const std::string g = key.substr(0, key.find('.'));
    if (!ctx.state.signal_filter.empty() && key.find(ctx.state.signal_filter) == std::string::npos)
      continue;
    if (g != group) {
      if (open) ImGui::EndTable();
      if (!group.empty() && open) ImGui::TreePop();
      group = g;
      ImGui::SetNextItemOpen(true, ImGuiCond_FirstUseEver);
      open = ImGui::TreeNode(g.c_str());
      if (open) {
        ImGui::BeginTable(("signals_" + g).c_str(), 3, ImGuiTableFlags_RowBg);
        ImGui::TableSetupColumn("plot", ImGuiTableColumnFlags_WidthFixed, 24);
        ImGui::TableSetupColumn("signal");
        ImGui::TableSetupColumn("value");
      }
    }
    if (!open) continue;
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    bool ticked = model.plot_signals().count(key) != 0;
    if (ImGui::Checkbox(("##tick:" + key).c_str(), &ticked)) model.TogglePlotSignal(key);
    RegisterLastItem(ctx, "tick:" + key);
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(key.c_str() + g.size() + 1);
    ImGui::TableNextColumn();
    ImGui::Text("%.4g", value);
  }
  if (open) {
    ImGui::EndTable();
    ImGui::TreePop();
  }
  ImGui::End();
}

}  // namespace uav::gcs
