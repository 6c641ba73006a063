#include "uav/gcs/layout.hpp"

#include <algorithm>
#include <cstdio>

namespace uav::gcs {
namespace {

// Rows and columns of the tiling: the status bar's two lines on top, then three columns.
constexpr float kTop = 0.055f;  // under the status bar (two lines at 900 px)
constexpr float kLeft = 0.22f, kRight = 0.62f;

}  // namespace

const std::vector<WindowPlace>& DefaultLayout() {
  static const std::vector<WindowPlace> kTable = {
      {"Status", 0.0f, 0.0f, 1.0f, kTop, 1200, 46, false},
      // Left: what the vehicle is, whether it may arm, its signals, its camera.
      {"Vehicles", 0.0f, kTop, kLeft, 0.13f, 300, 60, false},
      {"Pre-arm", 0.0f, 0.13f, kLeft, 0.34f, 300, 185, false},
      {"Replay", 0.0f, 0.13f, kLeft, 0.34f, 300, 185, false},  // in the Pre-arm panel's place when replaying
      {"Vehicle state", 0.0f, 0.34f, kLeft, 0.64f, 300, 200, false},
      {"Video", 0.0f, 0.64f, kLeft, 1.0f, 300, 250, false},
      // Middle: the plots, the command bar (with the emergency stop), the vision workers'
      // health, the messages and what the stereo pair sees.
      {"Plot", kLeft, kTop, kRight, 0.40f, 560, 300, false},
      {"Command", kLeft, 0.40f, kRight, 0.59f, 560, 165, false},
      {"Sensing", kLeft, 0.59f, kRight, 0.75f, 560, 140, false},
      {"Messages", kLeft, 0.75f, 0.45f, 1.0f, 330, 200, false},
      {"Obstacles", 0.45f, 0.75f, kRight, 1.0f, 250, 200, false},
      // Right: the map, the survey and mission files, the map being stitched.
      {"Map", kRight, kTop, 1.0f, 0.46f, 560, 360, false},
      {"Survey", kRight, 0.46f, 1.0f, 0.80f, 560, 300, false},
      {"Live map", kRight, 0.80f, 1.0f, 1.0f, 560, 170, false},
      // On demand: the mission editor under the map it edits (over the survey panel, its files
      // at hand in it); the others over the plots.
      {"Mission", kRight, 0.46f, 1.0f, 1.0f, 560, 450, true},
      {"Parameters", kLeft, kTop, kRight, 0.40f, 560, 300, true},
      {"Sticks", kLeft, kTop, 0.45f, 0.40f, 360, 300, true},
      {"Attitude", 0.45f, kTop, kRight, 0.34f, 240, 240, true},
  };
  return kTable;
}

const WindowPlace* FindWindowPlace(const std::string& window) {
  for (const WindowPlace& p : DefaultLayout())
    if (window == p.window) return &p;
  return nullptr;
}

bool IsProtectedWindow(const std::string& window) { return window == "Status" || window == "Command"; }

std::vector<std::string> CheckLayout(float width_px, float height_px) {
  std::vector<std::string> problems;
  char buf[200];
  const auto& table = DefaultLayout();
  auto overlap = [](const WindowPlace& a, const WindowPlace& b) {
    constexpr float kTouch = 1e-4f;  // shared edges are not overlaps
    return a.x0 < b.x1 - kTouch && b.x0 < a.x1 - kTouch && a.y0 < b.y1 - kTouch && b.y0 < a.y1 - kTouch;
  };
  auto same_place = [](const WindowPlace& a, const WindowPlace& b) {
    return a.x0 == b.x0 && a.y0 == b.y0 && a.x1 == b.x1 && a.y1 == b.y1;
  };
  for (std::size_t i = 0; i < table.size(); ++i) {
    const WindowPlace& a = table[i];
    if (a.x0 < 0 || a.y0 < 0 || a.x1 > 1 || a.y1 > 1 || a.x0 >= a.x1 || a.y0 >= a.y1) {
      std::snprintf(buf, sizeof buf, "%s is not within the display", a.window);
      problems.push_back(buf);
    }
    const float w = (a.x1 - a.x0) * width_px, h = (a.y1 - a.y0) * height_px;
    if (w < a.min_w_px || h < a.min_h_px) {
      std::snprintf(buf, sizeof buf, "%s is %.0f x %.0f px at %.0f x %.0f, its content needs %.0f x %.0f", a.window, w, h,
                    width_px, height_px, a.min_w_px, a.min_h_px);
      problems.push_back(buf);
    }
    for (std::size_t j = i + 1; j < table.size(); ++j) {
      const WindowPlace& b = table[j];
      if (!overlap(a, b)) continue;
      const bool both_shown = !a.on_demand && !b.on_demand && !same_place(a, b);  // Pre-arm and Replay alternate
      const bool covers_protected = (a.on_demand && IsProtectedWindow(b.window)) || (b.on_demand && IsProtectedWindow(a.window));
      if (both_shown || covers_protected) {
        std::snprintf(buf, sizeof buf, "%s and %s overlap", a.window, b.window);
        problems.push_back(buf);
      }
    }
  }
  return problems;
}

}  // namespace uav::gcs
