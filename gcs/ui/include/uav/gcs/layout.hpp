#pragma once
// The default window layout: each window's rectangle as fractions of the display, one table for
// the GCS (its first run; afterwards the layout file keeps what the operator arranged) and for
// the screenshot test that checks it. Plain data: no ImGui here.
//
// The panels always shown tile the display (three columns under the status bar: telemetry and
// video; plots, command bar, sensing, messages and obstacles; map, survey and live map); the
// windows opened on demand open over other panels (the mission editor under the map it edits;
// parameters, sticks and attitude over the plots), never over the command bar with its
// emergency stop, nor over the status bar.
#include <string>
#include <vector>

namespace uav::gcs {

struct WindowPlace {
  const char* window;      // the window's title
  float x0, y0, x1, y1;    // [fraction of the display] left, top, right, bottom
  float min_w_px, min_h_px;  // what its content needs: the display must give it at least this
  bool on_demand;          // opened from a button, over other panels
};

const std::vector<WindowPlace>& DefaultLayout();
// The entry for `window`; nullptr when it is not in the table.
const WindowPlace* FindWindowPlace(const std::string& window);

// The windows nothing may cover: the status bar, and the command bar with the emergency stop.
bool IsProtectedWindow(const std::string& window);

// What is wrong with the table on a display of width x height pixels ("" entries none): two
// panels always shown that overlap, an on-demand window over a protected one, a window off the
// display, or one smaller than its content needs.
std::vector<std::string> CheckLayout(float width_px, float height_px);

}  // namespace uav::gcs
