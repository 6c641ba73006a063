// Live plot of the ticked signals on a shared time axis, drawn with ImGui's draw list (Debian
// has no ImPlot). Each series is reduced to min/max per pixel column, so the cost is bounded
// by the plot width, not by the 30 minutes of history behind it.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include <imgui.h>
#include <imgui_stdlib.h>

#include "uav/gcs/gcs_ui.hpp"

namespace uav::gcs {
namespace {

const ImU32 kColors[] = {IM_COL32(80, 170, 255, 255), IM_COL32(255, 140, 60, 255),
                         IM_COL32(90, 220, 120, 255), IM_COL32(240, 90, 90, 255),
                         IM_COL32(200, 130, 255, 255), IM_COL32(240, 220, 80, 255),
                         IM_COL32(80, 230, 230, 255), IM_COL32(255, 120, 200, 255)};

struct Column {
  float lo, hi;
};

// Min/max of `s` per pixel column over [t0, t1]; empty columns have lo > hi.
std::vector<Column> Reduce(const SignalSeries& s, double t0, double t1, int width) {
  std::vector<Column> cols(width, {std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()});
  for (std::size_t i = s.LowerBound(t0); i < s.size(); ++i) {
    const double t = s.TimeAt(i);
    if (t > t1) break;
    const int c = std::clamp(static_cast<int>((t - t0) / (t1 - t0) * (width - 1)), 0, width - 1);
    const float v = static_cast<float>(s.ValueAt(i));
    cols[c].lo = std::min(cols[c].lo, v);
    cols[c].hi = std::max(cols[c].hi, v);
  }
  return cols;
}

}  // namespace

void DrawPlotPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Plot");
  UiState& st = ctx.state;
  const VehicleModel* v = model.selected();
  float window = static_cast<float>(model.plot_window());
  ImGui::SetNextItemWidth(160);
  if (ImGui::SliderFloat("window [s]", &window, 5.0f, 1800.0f, "%.0f", ImGuiSliderFlags_Logarithmic))
    model.SetPlotWindow(window);
  ImGui::SameLine();
  if (ImGui::Checkbox("pause", &st.plot_paused) && st.plot_paused) st.plot_paused_at = -1.0;
  RegisterLastItem(ctx, "plot:pause");
  ImGui::SameLine();
  ImGui::Checkbox("auto y", &st.plot_auto_y);
  if (!st.plot_auto_y) {
    ImGui::SameLine();
    ImGui::SetNextItemWidth(200);
    ImGui::DragFloatRange2("y range", &st.plot_y_min, &st.plot_y_max, 0.1f);
  }

  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 100.0f);
  size.y = std::max(size.y - 30.0f, 60.0f);  // room for the export row below
  ImGui::InvisibleButton("plot_canvas", size);
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->AddRectFilled(p0, p1, IM_COL32(20, 22, 28, 255));
  dl->AddRect(p0, p1, IM_COL32(90, 90, 100, 255));

  if (!v || model.plot_signals().empty()) {
    dl->AddText(ImVec2(p0.x + 10, p0.y + 10), IM_COL32(160, 160, 160, 255),
                "tick signals in the state list to plot them");
    ImGui::End();
    return;
  }
  // Time axis: the newest sample of any plotted signal (or the frozen time when paused).
  double t_end = -1e300;
  for (const auto& key : model.plot_signals())
    if (auto it = v->history.find(key); it != v->history.end() && !it->second.empty())
      t_end = std::max(t_end, it->second.LastTime());
  if (t_end < -1e299) t_end = 0.0;
  if (st.plot_paused) {
    if (st.plot_paused_at < 0.0) st.plot_paused_at = t_end;
    t_end = st.plot_paused_at;
  }
  const double t_start = t_end - model.plot_window();
  // CSV export of what the plot shows (ticked signals over the visible window).
  ImGui::SetCursorScreenPos(ImVec2(p0.x, p1.y + 2));
  if (ImGui::Button("Export CSV")) model.ExportPlotCsv(st.plot_csv_file, t_start, t_end, ctx.now);
  RegisterLastItem(ctx, "plot:export");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(220);
  ImGui::InputText("##plot:file", &st.plot_csv_file);
  RegisterLastItem(ctx, "plot:file");
  const int width = std::max(2, static_cast<int>(size.x));

  std::vector<std::pair<std::string, std::vector<Column>>> reduced;
  float y_lo = std::numeric_limits<float>::max(), y_hi = -std::numeric_limits<float>::max();
  for (const auto& key : model.plot_signals()) {
    auto it = v->history.find(key);
    if (it == v->history.end()) continue;
    reduced.emplace_back(key, Reduce(it->second, t_start, t_end, width));
    for (const Column& c : reduced.back().second)
      if (c.lo <= c.hi) y_lo = std::min(y_lo, c.lo), y_hi = std::max(y_hi, c.hi);
  }
  if (!st.plot_auto_y) y_lo = st.plot_y_min, y_hi = st.plot_y_max;
  if (!(y_lo <= y_hi)) y_lo = -1, y_hi = 1;
  if (y_hi - y_lo < 1e-6f) y_lo -= 0.5f, y_hi += 0.5f;
  const float margin = 0.05f * (y_hi - y_lo);
  y_lo -= margin;
  y_hi += margin;
  auto Y = [&](float val) { return p1.y - (val - y_lo) / (y_hi - y_lo) * size.y; };

  // Grid with value labels.
  for (int i = 0; i <= 4; ++i) {
    const float val = y_lo + (y_hi - y_lo) * i / 4.0f;
    const float y = Y(val);
    dl->AddLine(ImVec2(p0.x, y), ImVec2(p1.x, y), IM_COL32(50, 52, 60, 255));
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", val);
    dl->AddText(ImVec2(p0.x + 4, std::clamp(y - 14, p0.y + 2, p1.y - 16)), IM_COL32(150, 150, 150, 255), buf);
  }
  char tbuf[64];
  std::snprintf(tbuf, sizeof tbuf, "t = %.1f s", t_end);
  dl->AddText(ImVec2(p1.x - 90, p1.y - 16), IM_COL32(150, 150, 150, 255), tbuf);

  dl->PushClipRect(p0, p1, true);
  for (std::size_t k = 0; k < reduced.size(); ++k) {
    const ImU32 color = kColors[k % (sizeof kColors / sizeof kColors[0])];
    const auto& cols = reduced[k].second;
    ImVec2 prev(-1, -1);
    for (int c = 0; c < width; ++c) {
      if (cols[c].lo > cols[c].hi) continue;
      const float x = p0.x + c;
      if (cols[c].hi - cols[c].lo > 0) dl->AddLine(ImVec2(x, Y(cols[c].lo)), ImVec2(x, Y(cols[c].hi)), color);
      const ImVec2 cur(x, Y(0.5f * (cols[c].lo + cols[c].hi)));
      if (prev.x >= 0) dl->AddLine(prev, cur, color, 1.5f);
      prev = cur;
    }
    dl->AddText(ImVec2(p0.x + 60 + 150.0f * static_cast<float>(k % 6), p0.y + 4 + 16.0f * static_cast<float>(k / 6)),
                color, reduced[k].first.c_str());
  }
  // Hover readout: values of every series at the time under the cursor.
  if (hovered) {
    const float mx = ImGui::GetIO().MousePos.x;
    dl->AddLine(ImVec2(mx, p0.y), ImVec2(mx, p1.y), IM_COL32(200, 200, 200, 120));
    const double t = t_start + (mx - p0.x) / size.x * (t_end - t_start);
    ImGui::BeginTooltip();
    ImGui::Text("t = %.2f s", t);
    for (const auto& [key, cols] : reduced) {
      const SignalSeries& s = v->history.at(key);
      const std::size_t i = std::min(s.LowerBound(t), s.size() - 1);
      ImGui::Text("%s = %.4g", key.c_str(), s.ValueAt(i));
    }
    ImGui::EndTooltip();
  }
  dl->PopClipRect();
  ImGui::End();
}

}  // namespace uav::gcs
