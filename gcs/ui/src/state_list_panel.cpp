// Every received signal of the selected vehicle in a searchable tree grouped by message (thesis
// Fig. 2.8 left side), from the signal tables: each message with its rate and age, each signal
// with its value in display units (angles in degrees), its frame, a tick box that puts it on
// the active plot and, once ticked, a box that moves it to the right axis.
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
  const int plot = model.plots().active();
  ImGui::TextDisabled("ticks go to Plot %d", plot + 1);
  const PlotSpec spec = model.plots().specs()[plot];  // a copy: a tick changes the plots
  for (int gi = 0; gi < kSignalGroups; ++gi) {
    const auto group = static_cast<SignalGroupId>(gi);
    const SignalGroup& stats = v->group(group);
    if (stats.latest.empty()) continue;  // nothing of this message received yet
    const std::string g(GroupName(group));
    const auto& defs = GroupSignals(group);
    int shown = 0;
    for (const SignalDef& d : defs) shown += Matches(g + "." + std::string(d.name), ctx.state.signal_filter);
    if (shown == 0) continue;
    char header[128];
    std::snprintf(header, sizeof header, "%s  %.0f Hz, age %.1f s###group:%s", g.c_str(), stats.Rate(ctx.now),
                  std::min(stats.Age(ctx.now), 999.9), g.c_str());
    ImGui::SetNextItemOpen(true, ImGuiCond_FirstUseEver);
    if (!ImGui::TreeNode(header)) continue;
    if (ImGui::BeginTable(("signals_" + g).c_str(), 5, ImGuiTableFlags_RowBg)) {
      ImGui::TableSetupColumn("plot", ImGuiTableColumnFlags_WidthFixed, 24);
      ImGui::TableSetupColumn("R", ImGuiTableColumnFlags_WidthFixed, 24);
      ImGui::TableSetupColumn("signal");
      ImGui::TableSetupColumn("value");
      ImGui::TableSetupColumn("frame");
      for (int i = 0; i < static_cast<int>(defs.size()); ++i) {
        const SignalRef signal{group, i};
        const std::string key = Key(signal);
        if (!Matches(key, ctx.state.signal_filter)) continue;
        ImGui::TableNextRow();
        ImGui::TableNextColumn();
        auto it = spec.signals.find(signal);
        bool ticked = it != spec.signals.end();
        const bool plottable = v->History(signal) != nullptr;  // the heartbeat has no time base
        ImGui::BeginDisabled(!plottable);
        if (ImGui::Checkbox(("##tick:" + key).c_str(), &ticked)) model.plots().Toggle(signal);
        ImGui::EndDisabled();
        RegisterLastItem(ctx, "tick:" + key);
        ImGui::TableNextColumn();
        if (it != spec.signals.end()) {
          bool right = it->second == PlotAxis::kRight;
          if (ImGui::Checkbox(("##axis:" + key).c_str(), &right))
            model.plots().SetAxis(plot, signal, right ? PlotAxis::kRight : PlotAxis::kLeft);
          RegisterLastItem(ctx, "axis:" + key);
          if (ImGui::IsItemHovered()) ImGui::SetTooltip("right y axis");
        }
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(defs[i].name.data(), defs[i].name.data() + defs[i].name.size());
        ImGui::TableNextColumn();
        ImGui::TextUnformatted(FormatForDisplay(defs[i], stats.latest[i]).c_str());
        ImGui::TableNextColumn();
        ImGui::TextDisabled("%.*s", static_cast<int>(defs[i].frame.size()), defs[i].frame.data());
      }
      ImGui::EndTable();
    }
    ImGui::TreePop();
  }
  ImGui::End();
}

}  // namespace uav::gcs
