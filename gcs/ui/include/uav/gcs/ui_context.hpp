#pragma once
// State of the user interface itself (not of the vehicles): what the operator is typing, the
// filters and plot settings, and where each clickable widget was drawn this frame. Owned by the
// application and passed to every panel; panels keep no state of their own.
#include <map>
#include <string>

struct ImVec2;

namespace uav::gcs {

struct WidgetRect {
  float x0, y0, x1, y1;
};

struct UiState {
  std::string command_text;
  int history_pos = -1;            // -1: editing a new line
  bool focus_command_bar = false;
  std::string pending_confirmation;  // command text awaiting "Confirm"
  std::string signal_filter;
  bool plot_paused = false;
  double plot_paused_at = 0.0;
  bool plot_auto_y = true;
  float plot_y_min = -10.0f, plot_y_max = 10.0f;
};

struct UiContext {
  double now = 0.0;         // GCS monotonic clock [s]
  double start_time = 0.0;  // GCS clock when the application started [s]
  UiState state;
  // Rebuilt every frame: label -> screen rectangle of the widget.
  std::map<std::string, WidgetRect> widgets;
};

// Records the last ImGui item under `label` (call right after drawing it).
void RegisterLastItem(UiContext& ctx, const std::string& label);

}  // namespace uav::gcs
