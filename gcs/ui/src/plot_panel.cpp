// Plot panels: any number, stacked in the Plot window on one shared time axis, each with its
// ticked signals on a left and a right y axis, drawn with ImGui's draw list (Debian has no ImPlot). Mouse: the wheel zooms
// the time window, a drag pans it (and holds the time), hovering reads every value at that time.
// Each series is reduced to min/max per pixel column, so the cost is bounded by the plot width,
// not by the 30 minutes of history behind it. Values are drawn in display units (angles in
// degrees), as the telemetry tree shows them.
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

// Min/max of `s` per pixel column over [t0, t1]; empty columns have lo > hi. Uses the series'
// min/max pyramid, so a column costs O(log n) whatever the window.
std::vector<Column> Reduce(const SignalSeries& s, double t0, double t1, int width, double scale) {
  std::vector<Column> cols(width, {std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()});
  std::size_t i = s.LowerBound(t0);
  for (int c = 0; c < width && i < s.size(); ++c) {
    const double c_end = t0 + (t1 - t0) * (c + 1) / width;
    const std::size_t j = c + 1 == width ? s.UpperBound(t1) : s.LowerBoundFrom(c_end, i);
    if (j > i) {
      float lo, hi;
      s.MinMax(i, j, &lo, &hi);
      cols[c] = scale >= 0 ? Column{static_cast<float>(lo * scale), static_cast<float>(hi * scale)}
                           : Column{static_cast<float>(hi * scale), static_cast<float>(lo * scale)};
    }
    i = std::max(i, j);
  }
  return cols;
}

// One plotted signal reduced to a column per pixel.
struct Series {
  SignalRef signal;
  std::string key;
  PlotAxis axis;
  std::vector<Column> cols;
};

// The plot's controls: which plot ticks go to, close, and each axis auto or a fixed range.
// Returns false when the operator closed the plot.
bool DrawPlotControls(GcsModel& model, UiContext& ctx, int index, const PlotSpec& spec, const std::string& tag) {
  bool open = true;
  // Where ticks in the state list go.
  bool active = model.plots().active() == index;
  if (ImGui::RadioButton(("Plot " + std::to_string(index + 1)).c_str(), active)) model.plots().SetActive(index);
  RegisterLastItem(ctx, tag + ":select");
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("ticks in the state list go to this plot");
  ImGui::SameLine();
  if (model.plots().specs().size() > 1) {
    if (ImGui::SmallButton("x")) open = false;
    RegisterLastItem(ctx, tag + ":close");
    ImGui::SameLine();
  }
  // Per axis: auto or a fixed range.
  for (int a = 0; a < 2; ++a) {
    const PlotAxis axis = static_cast<PlotAxis>(a);
    bool auto_y = spec.auto_y[a];
    if (ImGui::Checkbox(((a == 0 ? "auto L##" : "auto R##") + tag).c_str(), &auto_y))
      model.plots().SetRange(index, axis, auto_y, spec.y_min[a], spec.y_max[a]);
    RegisterLastItem(ctx, tag + (a == 0 ? ":autoL" : ":autoR"));
    if (!spec.auto_y[a]) {
      ImGui::SameLine();
      float lo = static_cast<float>(spec.y_min[a]), hi = static_cast<float>(spec.y_max[a]);
      ImGui::SetNextItemWidth(140);
      if (ImGui::DragFloatRange2(("##range" + std::to_string(a) + tag).c_str(), &lo, &hi, 0.1f))
        model.plots().SetRange(index, axis, false, lo, hi);
    }
    if (a == 0) ImGui::SameLine();
  }

  return open;
}

// Hover readout: values of every series at the time under the cursor.
void DrawReadout(UiContext& ctx, const VehicleModel& v, const std::vector<Series>& reduced, ImDrawList* dl, ImVec2 p0,
                 ImVec2 p1, double t_start, double t_end) {
  UiState& st = ctx.state;
  const float width = p1.x - p0.x;
  const float mx = ImGui::GetIO().MousePos.x;
  dl->AddLine(ImVec2(mx, p0.y), ImVec2(mx, p1.y), IM_COL32(200, 200, 200, 120));
  const double t = t_start + (mx - p0.x) / width * (t_end - t_start);
  char line[128];
  std::snprintf(line, sizeof line, "t = %.2f s", t);
  st.plot_readout = line;
  for (const auto& r : reduced) {
    const SignalSeries& s = *v.History(r.signal);
    const std::size_t i = std::min(s.LowerBound(t), s.size() - 1);
    const SignalDef& def = Def(r.signal);
    const std::string unit(DisplayUnit(def));
    std::snprintf(line, sizeof line, "\n%s = %.6g %s", Key(r.signal).c_str(), DisplayValue(def, s.ValueAt(i)),
                  unit.c_str());
    st.plot_readout += line;
  }
  ImGui::SetTooltip("%s", st.plot_readout.c_str());
}

void DrawOnePlot(GcsModel& model, UiContext& ctx, int index, double t_end, float height) {
  const PlotSpec spec = model.plots().specs()[index];  // a copy: the buttons below may add a plot
  const VehicleModel* v = model.selected();
  const std::string tag = "plot:" + std::to_string(index + 1);
  ImGui::BeginChild(tag.c_str(), ImVec2(0, height), false, ImGuiWindowFlags_NoScrollbar);
  const bool open = DrawPlotControls(model, ctx, index, spec, tag);
  const ImVec2 p0 = ImGui::GetCursorScreenPos();
  ImVec2 size = ImGui::GetContentRegionAvail();
  size.x = std::max(size.x, 100.0f);
  size.y = std::max(size.y - 4.0f, 40.0f);
  ImGui::InvisibleButton((tag + ":canvas").c_str(), size);
  RegisterLastItem(ctx, tag + ":canvas");
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 p1(p0.x + size.x, p0.y + size.y);
  dl->AddRectFilled(p0, p1, IM_COL32(20, 22, 28, 255));
  dl->AddRect(p0, p1, IM_COL32(90, 90, 100, 255));
  const double t_start = t_end - model.plots().window();

  // Mouse: wheel zooms the time window about the newest time (with Shift: the y axes, below), a
  // drag pans and holds the time.
  const bool shift_wheel = hovered && ImGui::GetIO().MouseWheel != 0.0f && ImGui::GetIO().KeyShift;
  if (hovered && ImGui::GetIO().MouseWheel != 0.0f && !shift_wheel)
    model.plots().SetWindow(std::clamp(model.plots().window() * std::pow(1.25, -ImGui::GetIO().MouseWheel), 1.0, 1800.0));
  if (ImGui::IsItemActive() && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 2.0f)) {
    const float dx = ImGui::GetIO().MouseDelta.x;
    if (dx != 0.0f) model.plots().Hold(t_end - dx / size.x * model.plots().window());
  }

  if (!v || spec.signals.empty()) {
    dl->AddText(ImVec2(p0.x + 10, p0.y + 10), IM_COL32(160, 160, 160, 255),
                "tick signals in the state list to plot them here");
    ImGui::EndChild();
    if (!open) model.plots().Remove(index);
    return;
  }
  const int width = std::max(2, static_cast<int>(size.x));
  std::vector<Series> reduced;
  float lo[2] = {std::numeric_limits<float>::max(), std::numeric_limits<float>::max()};
  float hi[2] = {-std::numeric_limits<float>::max(), -std::numeric_limits<float>::max()};
  bool has[2] = {false, false};
  for (const auto& [signal, axis] : spec.signals) {
    const SignalSeries* history = v->History(signal);
    if (!history) continue;
    const int a = static_cast<int>(axis);
    has[a] = true;
    // Display units are a linear scale of SI (degrees, percent): scale the reduced columns.
    const SignalDef& def = Def(signal);
    const std::string unit(DisplayUnit(def));
    reduced.push_back({signal, Key(signal) + (unit.empty() ? "" : " [" + unit + "]"), axis,
                       Reduce(*history, t_start, t_end, width, DisplayValue(def, 1.0))});
    for (const Column& c : reduced.back().cols)
      if (c.lo <= c.hi) lo[a] = std::min(lo[a], c.lo), hi[a] = std::max(hi[a], c.hi);
  }
  for (int a = 0; a < 2; ++a) {
    if (!spec.auto_y[a]) lo[a] = static_cast<float>(spec.y_min[a]), hi[a] = static_cast<float>(spec.y_max[a]);
    if (!(lo[a] <= hi[a])) lo[a] = -1, hi[a] = 1;
    if (hi[a] - lo[a] < 1e-6f) lo[a] -= 0.5f, hi[a] += 0.5f;
    if (spec.auto_y[a]) {
      const float margin = 0.05f * (hi[a] - lo[a]);
      lo[a] -= margin;
      hi[a] += margin;
    }
  }
  if (shift_wheel) {
    // Both y axes zoom about their middle and become fixed ranges (auto L / auto R undo it).
    const double f = std::pow(1.25, -ImGui::GetIO().MouseWheel);
    for (int a = 0; a < 2; ++a) {
      const double mid = 0.5 * (lo[a] + hi[a]), half = 0.5 * (hi[a] - lo[a]) * f;
      model.plots().SetRange(index, static_cast<PlotAxis>(a), false, mid - half, mid + half);
    }
  }
  auto Y = [&](int a, float val) { return p1.y - (val - lo[a]) / (hi[a] - lo[a]) * size.y; };

  // Grid with the left axis's labels on the left, the right axis's on the right.
  for (int i = 0; i <= 4; ++i) {
    const float y = p1.y - size.y * i / 4.0f;
    dl->AddLine(ImVec2(p0.x, y), ImVec2(p1.x, y), IM_COL32(50, 52, 60, 255));
    char buf[32];
    for (int a = 0; a < 2; ++a) {
      if (!has[a]) continue;
      std::snprintf(buf, sizeof buf, "%.3g", lo[a] + (hi[a] - lo[a]) * i / 4.0f);
      const float x = a == 0 ? p0.x + 4 : p1.x - 4 - ImGui::CalcTextSize(buf).x;
      dl->AddText(ImVec2(x, std::clamp(y - 14, p0.y + 2, p1.y - 16)), IM_COL32(150, 150, 150, 255), buf);
    }
  }
  char tbuf[64];
  std::snprintf(tbuf, sizeof tbuf, "%.1f .. %.1f s%s", t_start, t_end, model.plots().hold() ? " (held)" : "");
  dl->AddText(ImVec2(p0.x + size.x * 0.5f - 60, p1.y - 16), IM_COL32(150, 150, 150, 255), tbuf);

  dl->PushClipRect(p0, p1, true);
  std::vector<ImVec2> line;
  for (std::size_t k = 0; k < reduced.size(); ++k) {
    const ImU32 color = kColors[k % (sizeof kColors / sizeof kColors[0])];
    const int a = static_cast<int>(reduced[k].axis);
    const auto& cols = reduced[k].cols;
    // The min..max of each column as a 1 px bar, the mid-points as one polyline (a gap breaks it).
    line.clear();
    for (int c = 0; c <= width; ++c) {
      if (c == width || cols[c].lo > cols[c].hi) {
        if (line.size() > 1) dl->AddPolyline(line.data(), static_cast<int>(line.size()), color, 0, 1.5f);
        line.clear();
        continue;
      }
      const float x = p0.x + c;
      const float y_lo = Y(a, cols[c].lo), y_hi = Y(a, cols[c].hi);
      if (y_lo - y_hi > 1.0f) dl->AddRectFilled(ImVec2(x, y_hi), ImVec2(x + 1, y_lo), color);
      line.emplace_back(x, 0.5f * (y_lo + y_hi));
    }
    const std::string label = reduced[k].key + (a == 1 ? " (R)" : "");
    dl->AddText(ImVec2(p0.x + 60 + 160.0f * static_cast<float>(k % 5), p0.y + 4 + 16.0f * static_cast<float>(k / 5)),
                color, label.c_str());
  }
  if (hovered) DrawReadout(ctx, *v, reduced, dl, p0, p1, t_start, t_end);
  dl->PopClipRect();
  ImGui::EndChild();
  if (!open) model.plots().Remove(index);
}

}  // namespace

void DrawPlotPanel(GcsModel& model, UiContext& ctx) {
  ImGui::Begin("Plot");
  UiState& st = ctx.state;
  // The shared time axis: the newest sample of any plotted signal, unless held.
  double t_end = -1e300;
  if (const VehicleModel* v = model.selected())
    for (const SignalRef signal : model.plots().ticked())
      if (const SignalSeries* h = v->History(signal); h && !h->empty()) t_end = std::max(t_end, h->LastTime());
  if (t_end < -1e299) t_end = 0.0;
  if (model.plots().hold()) t_end = *model.plots().hold();
  const double t_start = t_end - model.plots().window();
  float window = static_cast<float>(model.plots().window());
  ImGui::SetNextItemWidth(140);
  if (ImGui::SliderFloat("window [s]", &window, 1.0f, 1800.0f, "%.0f", ImGuiSliderFlags_Logarithmic))
    model.plots().SetWindow(window);
  ImGui::SameLine();
  bool paused = model.plots().hold().has_value();
  if (ImGui::Checkbox("pause", &paused)) paused ? model.plots().Hold(t_end) : model.plots().Follow();
  RegisterLastItem(ctx, "plot:pause");
  ImGui::SameLine();
  if (ImGui::Button("+ plot")) model.plots().Add();
  RegisterLastItem(ctx, "plot:add");
  ImGui::SameLine();
  ImGui::TextDisabled("wheel: zoom time, shift+wheel: zoom y, drag: pan, hover: values");
  const float export_row = ImGui::GetFrameHeightWithSpacing();
  const int n = static_cast<int>(model.plots().specs().size());
  const float each = std::max(60.0f, (ImGui::GetContentRegionAvail().y - export_row) / n);
  for (int i = 0; i < n && i < static_cast<int>(model.plots().specs().size()); ++i) DrawOnePlot(model, ctx, i, t_end, each);
  {
    // CSV export of the ticked signals (all plots) over a chosen time range; an empty end is
    // the visible window's.
    if (ImGui::Button("Export CSV")) {
      char* e1 = nullptr;
      char* e2 = nullptr;
      const double from = std::strtod(st.plot_export_from.c_str(), &e1);
      const double to = std::strtod(st.plot_export_to.c_str(), &e2);
      model.ExportPlotCsv(st.plot_csv_file, *e1 == '\0' && e1 != st.plot_export_from.c_str() ? from : t_start,
                          *e2 == '\0' && e2 != st.plot_export_to.c_str() ? to : t_end, ctx.now);
    }
    RegisterLastItem(ctx, "plot:export");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(60);
    ImGui::InputTextWithHint("##plot:from", "start", &st.plot_export_from);
    RegisterLastItem(ctx, "plot:from");
    ImGui::SameLine();
    ImGui::TextUnformatted("to");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(60);
    ImGui::InputTextWithHint("##plot:to", "end", &st.plot_export_to);
    RegisterLastItem(ctx, "plot:to");
    ImGui::SameLine();
    ImGui::TextUnformatted("s into");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(180);
    ImGui::InputText("##plot:file", &st.plot_csv_file);
    RegisterLastItem(ctx, "plot:file");
  }

  ImGui::End();
}

}  // namespace uav::gcs
