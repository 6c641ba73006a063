#pragma once
// State of the user interface itself (not of the vehicles): what the operator is typing, the
// filters and plot settings, and where each clickable widget was drawn this frame. Owned by the
// application and passed to every panel; panels keep no state of their own.
#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "uav/gcs/replay_control.hpp"

struct ImVec2;

namespace uav::gcs {

struct WidgetRect {
  float x0, y0, x1, y1;
  std::string disabled;  // why it does not respond now (empty: it does); scripts are told
};

struct UiState {
  std::string command_text;
  int history_pos = -1;            // -1: editing a new line
  bool focus_command_bar = false;
  std::string pending_confirmation;  // command text awaiting "Confirm"
  int emergency_stop_asked = 0;
  bool speak_alerts = true;         // warnings and failsafes spoken (uav-gcs --no-speech: off)
  std::string speech_unavailable;   // why they cannot be ("" : they can)      // emergency stop: 0 not asked, 1 asked once, 2 asked twice
  std::string signal_filter;
  std::string plot_csv_file = "plot.csv";
  // CSV export range [s of plot time]; empty: that end of the visible window.
  std::string plot_export_from, plot_export_to;
  std::string plot_readout;  // the hover readout of the last frame the mouse was over a plot
  // Map view: centre [m north, east of the map origin] and zoom.
  double map_center_n = 0.0, map_center_e = 0.0;
  double map_px_per_m = 3.0;
  bool map_edit_survey = false;  // clicks edit the survey polygon (off: a click only pans)
  bool map_edit_mission = false; // clicks edit the mission's items (never both at once)
  bool map_follow = false;       // the map keeps the selected vehicle in its centre
  int map_pressed_item = -1;     // the mission item under the pointer when the button went down
  double map_goto_n = 0.0, map_goto_e = 0.0;  // [m] where a right click offered to go
  int map_pressed_vertex = -1;   // vertex under the pointer when the button went down
  bool map_dragged = false;
  float map_press_x = 0, map_press_y = 0;
  // Map panel's basemap: the file to load, and which load is in the texture.
  std::string basemap_file = "maps/map.tif";
  int64_t basemap_version = -1;
  void* basemap_texture = nullptr;
  // Survey panel.
  std::string survey_file = "survey.plan";
  // Live map panel: where downloads are saved, and the tile textures (per tile: the version
  // uploaded, its texture, its slot) of which vehicle's which map.
  std::string download_dir = "maps";
  struct TileTexture {
    int64_t version = -1;
    void* texture = nullptr;
    int slot = 0;
  };
  std::map<std::pair<int, int>, TileTexture> live_tiles;
  std::string live_map_vehicle;
  double live_zoom = 1.0;                  // 1: the whole map fits the panel
  double live_pan_x = 0, live_pan_y = 0;   // [tiles] view centre from the map's centre
  int live_map_id = -1;
  int next_texture_slot = 100;
  // Video panel: the corners clicked so far on a frozen frame, a drag in progress (normalised
  // image coordinates), and which frame of which vehicle is in the texture.
  std::vector<std::array<float, 2>> video_clicks;
  std::array<float, 2> video_press{0, 0};
  bool video_dragging = false;
  std::string video_vehicle;
  // What is drawn over the video (each can be hidden): the tracker's box, power lines, the depth
  // grid, the active-stereo dots, stereo obstacles.
  struct VideoOverlays {
    bool track = true, wires = true, depth = true, dots = true, obstacles = true;
  } video_overlays;
  int64_t video_frames_shown = -1;
  void* video_texture = nullptr;
  // Parameters panel: open, its search, the values being typed (by name) and the file.
  bool show_parameters = false;
  bool show_sticks = false;  // the Sticks window (virtual sticks, gamepad)
  bool show_attitude = false;  // the Attitude window (artificial horizon)
  bool sticks_deadman_latched = false;  // the Sticks window's "deadman held" box
  bool sticks_left_held = false, sticks_right_held = false;  // the on-screen sticks, last frame
  std::string params_filter;
  std::map<std::string, std::string> params_edits;
  std::string params_file = "vehicle.params";
  int params_format = 0;  // 0 our vehicle file, 1 QGroundControl's .params
  // Number fields (number_field.hpp), by widget id: the text being typed, and why the last value
  // typed was refused (shown until a good value is typed).
  std::map<std::string, std::string> number_edits;
  std::map<std::string, std::string> number_refused;
  bool mission_latlon = false;  // the mission list shows positions as latitude/longitude (else north/east of home)
  float replay_seek = -1.0f;  // the seek slider while it is being dragged [s]; < 0: follows the replay
  std::string replay_speed_text;   // the speed being typed
  std::string replay_speed_error;  // why the typed speed was refused
};

// Where the map was drawn this frame: screen = centre + (east, -north) * px_per_m.
struct MapTransform {
  bool valid = false;
  float screen_cx = 0, screen_cy = 0;
  double center_n = 0, center_e = 0, px_per_m = 1;
};

struct UiContext {
  double now = 0.0;         // GCS monotonic clock [s]
  double start_time = 0.0;  // GCS clock when the application started [s]
  UiState state;
  // Rebuilt every frame: label -> screen rectangle of the widget.
  std::map<std::string, WidgetRect> widgets;
  MapTransform map;
  // Set by the application from its platform: uploads RGBA into a texture slot and returns the
  // ImTextureID (nullptr headless). Unset: panels draw no images.
  std::function<void*(int slot, const uint8_t* rgba, int width, int height)> update_texture;
  // Set while replaying a log: the Replay panel's pause, seek slider and speed act on it.
  ReplayControl* replay = nullptr;
  // Why the widgets drawn now are disabled (between BeginDisabledBecause and EndDisabled).
  std::string disabled_because;
};

// Records the last ImGui item under `label` (call right after drawing it), with why it is
// disabled when it is drawn inside BeginDisabledBecause.
void RegisterLastItem(UiContext& ctx, const std::string& label);
// ImGui::BeginDisabled(disabled) that remembers why, for RegisterLastItem; pair with EndDisabledBecause.
void BeginDisabledBecause(UiContext& ctx, bool disabled, const std::string& why);
void EndDisabledBecause(UiContext& ctx);

}  // namespace uav::gcs
