// Every received signal of the selected vehicle in a searchable tree grouped by message (thesis
// Fig. 2.8 left side): each message with its rate and age, each signal with its value, a tick
// box that puts it on the active plot and, once ticked, a box that moves it to the right axis.
#include <algorithm>
#include <cctype>
#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

bool Matches(const std::string& key, const std::string& filter) {
  if (filter.empty()) return true;
  // Case-insensitive substring.
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  return lower(key).find(lower(filter)) != std::string::npos;
}

}  // namespace

void DrawStateListPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Vehicle state");
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##filter", "search signals", &ctx.state.signal_filter);
  RegisterLastItem(ctx, "signals:search");
  const VehicleModel* v = model.selected();
  if (!v) {
    ImGui::TextDisabled("no vehicle");
    ImGui::End();
    return;
  }
  const int plot = model.active_plot();
  ImGui::TextDisabled("ticks go to Plot %d", plot + 1);
  const PlotSpec spec = model.plots()[plot];  // a copy: a tick changes the plots
  // Groups in the order their first signal arrived.
  std::vector<std::string> groups;
  for (const std::string& key : v->signal_order) {
    const std::string g = key.substr(0, key.find('.'));
    if (std::find(groups.begin(), groups.end(), g) == groups.end()) groups.push_back(g);
  }
  for (const std::string& g : groups) {
    int shown = 0;
    for (const std::string& key : v->signal_order)
      shown += key.compare(0, g.size() + 1, g + ".") == 0 && Matches(key, ctx.state.signal_filter);
    if (shown == 0) continue;
    const SignalGroup* stats = v->groups.count(g) ? &v->groups.at(g) : nullptr;
    char header[128];
    std::snprintf(header, sizeof header, "%s  %.0f Hz, age %.1f s###group:%s", g.c_str(),
                  stats ? stats->Rate(ctx.now) : 0.0, stats ? std::min(stats->Age(ctx.now), 999.9) : 999.9, g.c_str());
    ImGui::SetNextItemOpen(true, ImGuiCond_FirstUseEver);
    if (!ImGui::TreeNode(header)) continue;
    if (ImGui::BeginTable(("signals_" + g).c_str(), 4, ImGuiTableFlags_RowBg)) {
      ImGui::TableSetupColumn("plot", ImGuiTableColumnFlags_WidthFixed, 24);
      ImGui::TableSetupColumn("R", ImGuiTableColumnFlags_WidthFixed, 24);
      ImGui::TableSetupColumn("signal");
      ImGui::TableSetupColumn("value");
      for (const std::string& key : v->signal_order) {
        if (key.compare(0, g.size() + 1, g + ".") != 0 || !Matches(key, ctx.state.signal_filter)) continue;
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        auto it = spec.signals.find(key);
        bool ticked = it != spec.signals.end();
        if (ImGui::Checkbox(("##tick:" + key).c_str(), &ticked)) model.TogglePlotSignal(key);
        RegisterLastItem(ctx, "tick:" + key);
        ImGui::TableNextColumn();
        if (it != spec.signals.end()) {
          bool right = it->second == PlotAxis::kRight;
          if (ImGui::Checkbox(("##axis:" + key).c_str(), &right))
            model.SetSignalAxis(plot, key, right ? PlotAxis::kRight : PlotAxis::kLeft);
          RegisterLastItem(ctx, "axis:" + key);
          if (ImGui::IsItemHovered()) ImGui::SetTooltip("right y axis");
        }
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(key.c_str() + g.size() + 1);
        ImGui::TableNextColumn();
        ImGui::Text("%.6g", v->latest.at(key));
      }
      ImGui::EndTable();
    }
    ImGui::TreePop();
  }
  ImGui::End();
}

}  // namespace uav::gcs
