// Parameters: the selected vehicle's parameter table, as QGroundControl's parameter editor: search
// by name or description, edit a value (checked against its limits and whether it may change now,
// then sent as a signed `param` command; the vehicle's answer is in the messages and the table),
// reset to the default, save to and load from a file in our vehicle-file format or QGroundControl's
// .params. Opened from the status bar.
#include <cstdio>
#include <string>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

bool Matches(const ParameterEntry& e, const std::string& filter) {
  if (filter.empty()) return true;
  auto lower = [](std::string s) {
    for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return s;
  };
  const std::string f = lower(filter);
  return lower(e.name).find(f) != std::string::npos || lower(e.description).find(f) != std::string::npos;
}

void DrawFileRow(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  ImGui::SetNextItemWidth(220);
  ImGui::InputText("##params:file", &st.params_file);
  RegisterLastItem(ctx, "params:file");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(150);
  const char* formats[] = {"vehicle file", "QGroundControl"};
  ImGui::Combo("##params:format", &st.params_format, formats, 2);
  ImGui::SameLine();
  if (ImGui::Button("Save")) model.SaveParameters(st.params_file, st.params_format == 1 ? ParameterFileFormat::kQgc : ParameterFileFormat::kVehicle, ctx.now);
  RegisterLastItem(ctx, "params:save");
  ImGui::SameLine();
  BeginDisabledBecause(ctx, model.replay(), model.commands().refusal());
  if (ImGui::Button("Load")) model.LoadParameters(st.params_file, ctx.now);  // reads either format
  RegisterLastItem(ctx, "params:load");
  EndDisabledBecause(ctx);
}

void DrawRow(GcsModel& model, UiContext& ctx, const ParameterEntry& e, bool armed) {
  UiState& st = ctx.state;
  const ImVec4 grey(0.6f, 0.6f, 0.6f, 1), amber(1, 0.7f, 0.2f, 1);
  ImGui::TableNextRow();
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(e.name.c_str());
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", e.description.c_str());
  ImGui::TableNextColumn();
  const bool locked = e.apply == ParamApply::kAtStart || (e.apply == ParamApply::kOnGround && armed);
  BeginDisabledBecause(ctx, locked || model.replay(),
                       model.replay() ? model.commands().refusal()
                       : e.apply == ParamApply::kAtStart ? e.name + " is read only at start"
                                                         : e.name + " changes only while disarmed");
  auto it = st.params_edits.find(e.name);
  if (it == st.params_edits.end()) it = st.params_edits.emplace(e.name, FormatParameterValue(e.value)).first;
  ImGui::SetNextItemWidth(-1);
  const bool entered = ImGui::InputText(("##params:value:" + e.name).c_str(), &it->second, ImGuiInputTextFlags_EnterReturnsTrue);
  const bool editing = ImGui::IsItemActive();
  RegisterLastItem(ctx, "params:value:" + e.name);
  EndDisabledBecause(ctx);
  if (entered) {
    model.SetParameter(e.name, it->second, ctx.now);
    st.params_edits.erase(it);  // shows the vehicle's value again, whatever it answers
  } else if (!editing) {
    it->second = FormatParameterValue(e.value);
  }
  ImGui::TableNextColumn();
  ImGui::TextUnformatted(e.unit.c_str());
  ImGui::TableNextColumn();
  ImGui::TextColored(grey, "%s .. %s", FormatParameterValue(e.min).c_str(), FormatParameterValue(e.max).c_str());
  ImGui::TableNextColumn();
  if (e.default_value == e.value || e.default_value != e.default_value) {
    ImGui::TextColored(grey, "%s", FormatParameterValue(e.default_value).c_str());
  } else {
    BeginDisabledBecause(ctx, locked || model.replay(), "cannot change now");
    if (ImGui::SmallButton(("reset to " + FormatParameterValue(e.default_value) + "##" + e.name).c_str()))
      model.SetParameter(e.name, FormatParameterValue(e.default_value), ctx.now);
    RegisterLastItem(ctx, "params:reset:" + e.name);
    EndDisabledBecause(ctx);
  }
  ImGui::TableNextColumn();
  ImGui::TextColored(e.apply == ParamApply::kInFlight ? ImVec4(0.4f, 0.9f, 0.4f, 1) : e.apply == ParamApply::kOnGround ? amber : grey,
                     "%s", Name(e.apply));
}

}  // namespace

void DrawParametersPanel(GcsModel& model, UiContext& ctx) {
  UiState& st = ctx.state;
  if (!st.show_parameters) return;
  // Over the plots, leaving the command bar, the map and the messages in view.
  PlaceWindow("Parameters");
  if (!ImGui::Begin("Parameters", &st.show_parameters)) {
    ImGui::End();
    return;
  }
  const VehicleModel* v = model.selected();
  const Received<ParameterTable>* received = v ? &v->reports.Get<ParameterTable>() : nullptr;
  if (!received || !received->newest) {
    ImGui::TextDisabled(v ? "no parameter table from %s yet" : "no vehicle selected", model.selected_id().c_str());
    ImGui::End();
    return;
  }
  const ParameterTable& table = *received->newest;
  ImGui::Text("%s: %zu parameters, %lld changed over the link, received %.0f s ago", model.selected_id().c_str(),
              table.entries.size(), static_cast<long long>(table.version), ctx.now - received->at);
  ImGui::TextDisabled("changes: flight = at once, ground = while disarmed, start = vehicle file or --param");
  ImGui::SetNextItemWidth(-1);
  ImGui::InputTextWithHint("##params:search", "search names and descriptions", &st.params_filter);
  RegisterLastItem(ctx, "params:search");
  DrawFileRow(model, ctx);
  const ImGuiTableFlags flags = ImGuiTableFlags_RowBg | ImGuiTableFlags_ScrollY | ImGuiTableFlags_BordersInnerV | ImGuiTableFlags_Resizable;
  if (ImGui::BeginTable("params", 6, flags)) {
    ImGui::TableSetupScrollFreeze(0, 1);
    ImGui::TableSetupColumn("name", ImGuiTableColumnFlags_WidthStretch, 2.0f);
    ImGui::TableSetupColumn("value", ImGuiTableColumnFlags_WidthStretch, 1.2f);
    ImGui::TableSetupColumn("unit", ImGuiTableColumnFlags_WidthStretch, 0.6f);
    ImGui::TableSetupColumn("limits", ImGuiTableColumnFlags_WidthStretch, 1.4f);
    ImGui::TableSetupColumn("default", ImGuiTableColumnFlags_WidthStretch, 1.2f);
    ImGui::TableSetupColumn("changes", ImGuiTableColumnFlags_WidthStretch, 0.7f);
    ImGui::TableHeadersRow();
    for (const ParameterEntry& e : table.entries)
      if (Matches(e, st.params_filter)) DrawRow(model, ctx, e, v->armed);
    ImGui::EndTable();
  }
  ImGui::End();
}

}  // namespace uav::gcs
