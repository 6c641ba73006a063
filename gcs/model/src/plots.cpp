#include "uav/gcs/plots.hpp"

#include <cmath>
#include <limits>

#include "uav/shared/text_file.hpp"

namespace uav::gcs {

std::set<SignalRef> PlotSet::ticked() const {
  std::set<SignalRef> all;
  for (const auto& p : plots_)
    for (const auto& [s, axis] : p.signals) all.insert(s);
  return all;
}

int PlotSet::Add() {
  plots_.emplace_back();
  active_ = static_cast<int>(plots_.size()) - 1;
  return active_;
}

void PlotSet::Remove(int index) {
  if (plots_.size() <= 1 || index < 0 || index >= static_cast<int>(plots_.size())) return;
  plots_.erase(plots_.begin() + index);
  active_ = std::min(active_, static_cast<int>(plots_.size()) - 1);
}

void PlotSet::SetActive(int index) {
  if (index >= 0 && index < static_cast<int>(plots_.size())) active_ = index;
}

void PlotSet::Toggle(SignalRef s) { Toggle(active_, s, PlotAxis::kLeft); }

void PlotSet::Toggle(int plot, SignalRef s, PlotAxis axis) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return;
  auto& signals = plots_[plot].signals;
  if (!signals.erase(s)) signals[s] = axis;
}

void PlotSet::SetAxis(int plot, SignalRef s, PlotAxis axis) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return;
  auto it = plots_[plot].signals.find(s);
  if (it != plots_[plot].signals.end()) it->second = axis;
}

bool PlotSet::SetRange(int plot, PlotAxis axis, bool auto_y, double lo, double hi) {
  if (plot < 0 || plot >= static_cast<int>(plots_.size())) return false;
  PlotSpec& p = plots_[plot];
  const int a = static_cast<int>(axis);
  if (auto_y) {
    p.auto_y[a] = true;
    return true;
  }
  if (!std::isfinite(lo) || !std::isfinite(hi) || !(lo < hi)) return false;
  p.auto_y[a] = false;
  p.y_min[a] = lo;
  p.y_max[a] = hi;
  return true;
}

void PlotSet::SetWindow(double seconds) {
  if (seconds >= kMinWindow && seconds <= kMaxWindow) window_ = seconds;
}

void PlotSet::Hold(double t_end) {
  if (std::isfinite(t_end)) hold_ = t_end;
}

bool PlotSet::ExportCsv(const VehicleTelemetry* v, const std::string& vehicle_id, const std::string& path, double t0,
                        double t1, double now, MessageLog& log) const {
  const std::set<SignalRef> signals = ticked();
  if (!v || signals.empty() || !std::isfinite(t0) || !std::isfinite(t1) || !(t0 <= t1)) {
    log.Add(now, "", "CSV export: nothing to export (no vehicle, no ticked signal or an empty range)", Severity::kWarning);
    return false;
  }
  // Columns in the order of their names ("STATE.alt" before "STATE.x").
  std::map<std::string, const SignalSeries*> by_name;
  for (const SignalRef s : signals)
    if (const SignalSeries* h = v->History(s)) by_name[Key(s)] = h;
  std::vector<const SignalSeries*> series;
  std::vector<std::string> names;
  for (const auto& [name, h] : by_name) {
    series.push_back(h);
    names.push_back(name);
  }
  // Merge the sample times of all series (signals of one message share them).
  std::vector<std::size_t> next(series.size());
  for (std::size_t k = 0; k < series.size(); ++k) next[k] = series[k]->LowerBound(t0);
  std::string out = "t";
  for (const auto& n : names) out += "," + n;
  out += "\n";
  char buf[64];
  std::size_t rows = 0;
  for (;;) {
    double t = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < series.size(); ++k)
      if (next[k] < series[k]->size()) t = std::min(t, series[k]->TimeAt(next[k]));
    if (!(t <= t1)) break;
    std::snprintf(buf, sizeof buf, "%.3f", t);
    out += buf;
    for (std::size_t k = 0; k < series.size(); ++k) {
      out += ',';
      if (next[k] < series[k]->size() && series[k]->TimeAt(next[k]) == t) {
        std::snprintf(buf, sizeof buf, "%.9g", series[k]->ValueAt(next[k]));
        out += buf;
        ++next[k];
      }
    }
    out += '\n';
    ++rows;
  }
  try {
    WriteFileAtomically(path, out);
  } catch (const std::exception& e) {
    log.Add(now, "", std::string("CSV export failed: ") + e.what(), Severity::kWarning);
    return false;
  }
  std::snprintf(buf, sizeof buf, "%.1f..%.1f s", t0, t1);
  log.Add(now, vehicle_id,
          "exported " + std::to_string(rows) + " rows of " + std::to_string(names.size()) + " signals (" + buf +
              ") to " + path,
          Severity::kInfo);
  return true;
}

}  // namespace uav::gcs
