#include "number_field.hpp"

#include <cstdio>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/shared/decimal.hpp"

namespace uav::gcs {
namespace {

std::string Format(const char* format, double v) {
  char s[64];
  std::snprintf(s, sizeof s, format, v);
  return s;
}

const ImVec4 kRefusedFrame(0.55f, 0.12f, 0.10f, 1.0f);
const ImVec4 kRefusedText(1.0f, 0.45f, 0.35f, 1.0f);

}  // namespace

const std::string& NumberFieldRefusal(const UiContext& ctx, const std::string& id) {
  static const std::string kNone;
  const auto it = ctx.state.number_refused.find(id);
  return it == ctx.state.number_refused.end() ? kNone : it->second;
}

void DrawNumberFieldRefusals(const UiContext& ctx, const std::string& prefix) {
  ImGui::PushTextWrapPos(0.0f);
  for (const auto& [id, why] : ctx.state.number_refused)
    if (id.rfind(prefix, 0) == 0) ImGui::TextColored(kRefusedText, "%s: %s", id.substr(prefix.size()).c_str(), why.c_str());
  ImGui::PopTextWrapPos();
}

bool NumberField(UiContext& ctx, const std::string& id, double* value, double min, double max, const char* format,
                 const char* unit, float width) {
  UiState& st = ctx.state;
  const auto typing = st.number_edits.find(id);
  std::string text = typing != st.number_edits.end() ? typing->second : Format(format, *value);
  // Red while what is typed would be refused, and after a refusal until a good value is typed.
  const auto parsed = ParseDecimal(text);
  const bool bad = (typing != st.number_edits.end() && !(parsed && *parsed >= min && *parsed <= max)) ||
                   st.number_refused.count(id) > 0;
  if (bad) ImGui::PushStyleColor(ImGuiCol_FrameBg, kRefusedFrame);
  ImGui::SetNextItemWidth(width);
  if (ImGui::InputText(("##" + id).c_str(), &text)) st.number_edits[id] = text;
  const bool left = ImGui::IsItemDeactivatedAfterEdit();
  if (bad) ImGui::PopStyleColor();
  RegisterLastItem(ctx, id);
  const std::string limits = "[" + Format(format, min) + ", " + Format(format, max) + "] " + unit;
  if (ImGui::IsItemHovered() && !ImGui::IsItemActive())
    ImGui::SetTooltip("%s", st.number_refused.count(id) ? st.number_refused[id].c_str() : ("limits " + limits).c_str());
  if (!left) return false;
  const auto edit = st.number_edits.find(id);
  if (edit == st.number_edits.end()) return false;
  const std::string typed = edit->second;
  st.number_edits.erase(edit);
  const auto v = ParseDecimal(typed);
  const std::string stays = "; it stays " + Format(format, *value) + " " + unit;
  if (!v) {
    st.number_refused[id] = "\"" + typed + "\" is not a number" + stays;
    return false;
  }
  if (*v < min || *v > max) {
    st.number_refused[id] = typed + " is outside " + limits + stays;
    return false;
  }
  st.number_refused.erase(id);
  *value = *v;
  return true;
}

}  // namespace uav::gcs
