#pragma once
// The plot panels: their signals (each on the left or right y axis), each axis's range, the
// shared time axis (window, follow or hold), and CSV export of the ticked signals.
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "uav/gcs/message_log.hpp"
#include "uav/gcs/telemetry.hpp"

namespace uav::gcs {

enum class PlotAxis { kLeft = 0, kRight = 1 };
struct PlotSpec {
  std::map<SignalRef, PlotAxis> signals;
  bool auto_y[2] = {true, true};
  double y_min[2] = {-10, -10}, y_max[2] = {10, 10};
};

class PlotSet {
 public:
  static constexpr double kMinWindow = 1.0, kMaxWindow = 1800.0;  // [s]

  // There is always at least one plot; ticking puts a signal on the active one.
  int Add();                 // a new, empty, active plot; returns its index
  void Remove(int index);    // the last one stays
  void SetActive(int index);
  void Toggle(SignalRef s);  // on the active plot, left axis
  void Toggle(int plot, SignalRef s, PlotAxis axis);
  void SetAxis(int plot, SignalRef s, PlotAxis axis);
  // Fixed range of one axis (auto off); refused unless finite with lo < hi.
  bool SetRange(int plot, PlotAxis axis, bool auto_y, double lo, double hi);
  void SetWindow(double seconds);  // kMinWindow..kMaxWindow, else ignored
  // The shared time axis: following the newest sample, or held at `t_end` (plot time, seconds
  // since the vehicle's first sample) by pause or by panning.
  void Hold(double t_end);
  void Follow() { hold_.reset(); }
  // Writes the ticked signals (all plots) of `v` over [t0, t1] (plot time) as CSV: a column t,
  // then one per signal ("STATE.alt", SI units), a row per sample time (empty where a signal
  // has no sample then). Written to a temporary name and renamed; the outcome is logged.
  bool ExportCsv(const VehicleTelemetry* v, const std::string& vehicle_id, const std::string& path, double t0,
                 double t1, double now, MessageLog& log) const;

  const std::vector<PlotSpec>& specs() const { return plots_; }
  int active() const { return active_; }
  std::set<SignalRef> ticked() const;  // on any plot
  double window() const { return window_; }
  const std::optional<double>& hold() const { return hold_; }

 private:
  std::vector<PlotSpec> plots_ = std::vector<PlotSpec>(1);
  int active_ = 0;
  double window_ = 60.0;
  std::optional<double> hold_;
};

}  // namespace uav::gcs
